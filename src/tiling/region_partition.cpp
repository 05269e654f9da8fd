// TiledRun::partition(): the input streamed twice into region files on disk.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_stream.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

#include "tiling/tiled_run_files.hpp"
#include "tiling/tiled_run_impl.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <optional>
#include <tuple>
#include <vector>

namespace clustersurf {

namespace {

/// Even sample of the input that places the plan's cuts and measures its halo.
constexpr std::uint64_t kPlanSample = 200000;

/// The input's size and modification time (nanoseconds), which say whether a partition is of it.
std::pair<std::uintmax_t, std::int64_t> file_identity(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw IoError(file.string() + ": cannot open: " + ec.message());
  const auto time = std::filesystem::last_write_time(file, ec);
  if (ec) throw IoError(file.string() + ": cannot stat: " + ec.message());
  return {size, static_cast<std::int64_t>(
                    std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count())};
}

/// Appends doubles to a region file, buffered.
class RegionWriter {
 public:
  RegionWriter(std::filesystem::path file, std::size_t capacity) : file_(std::move(file)), capacity_(capacity) {
    std::FILE* f = std::fopen(file_.c_str(), "wb");  // truncated: a partition starts over
    if (f == nullptr) throw IoError(file_.string() + ": cannot create: " + std::strerror(errno));
    std::fclose(f);
  }
  void add(const double* values, std::size_t n) {
    buffer_.insert(buffer_.end(), values, values + n);
    if (buffer_.size() >= capacity_) flush();
  }
  void flush() {
    if (buffer_.empty()) return;
    std::FILE* f = std::fopen(file_.c_str(), "ab");
    if (f == nullptr) throw IoError(file_.string() + ": cannot open: " + std::strerror(errno));
    const std::size_t written = std::fwrite(buffer_.data(), sizeof(double), buffer_.size(), f);
    const int err = errno;
    if (std::fclose(f) != 0 || written != buffer_.size())
      throw IoError(file_.string() + ": write failed: " + std::strerror(written != buffer_.size() ? err : errno));
    buffer_.clear();
  }

 private:
  std::filesystem::path file_;
  std::size_t capacity_;
  std::vector<double> buffer_;
};

/// How many levels of the canonical path `directory`, from the deepest up, do not exist yet.
int missing_levels(const std::filesystem::path& directory) {
  int levels = 0;
  std::error_code ec;
  for (std::filesystem::path p = directory; p.has_relative_path() && !std::filesystem::exists(p, ec);
       p = p.parent_path())
    ++levels;
  return levels;
}

/// The run record of `directory`, which is created (with its parents, along its canonical
/// path `canonical`) when missing. A directory that is not a run's is used alongside the files
/// it holds, unless one of them has a run file's name (OptionError: nothing is written then).
/// OptionError for a path that is not a directory.
detail::RunRecord open_work_directory(const std::filesystem::path& directory, std::filesystem::path& canonical) {
  std::error_code ec;
  // The canonical path: "new/../old" is "old" (no "new" is made for it), and a parent reached
  // through ".." is never counted as the run's.
  canonical = std::filesystem::weakly_canonical(std::filesystem::absolute(directory, ec), ec);
  if (ec) throw IoError(directory.string() + ": cannot resolve the work directory: " + ec.message());
  const auto status = std::filesystem::status(canonical, ec);
  if (std::filesystem::exists(status) && !std::filesystem::is_directory(status))
    throw OptionError("the work directory " + directory.string() + " is not a directory");
  if (std::filesystem::exists(status)) {
    if (std::optional<detail::RunRecord> record = detail::read_run_record(canonical)) return *record;
    for (auto it = std::filesystem::directory_iterator(canonical, ec);
         !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
      if (detail::is_run_file_name(it->path()))
        throw OptionError("the work directory " + directory.string() + " holds " + it->path().filename().string() +
                          ", which is not a clustersurf run's file: use another work directory");
    if (ec) throw IoError(directory.string() + ": cannot list the work directory: " + ec.message());
  }
  detail::RunRecord record;
  record.created_levels = missing_levels(canonical);
  std::filesystem::create_directories(canonical, ec);
  if (ec) throw IoError(directory.string() + ": cannot create the work directory: " + ec.message());
  detail::write_run_record(canonical, record);
  return record;
}

/// Reports a pass's progress: the stage and how many points it has seen.
using PassReport = std::function<void(std::string_view, double)>;

/// Pass 1 over the input: its count, bounds and an even sample, then the region plan, into `r`.
void plan_from_scan(const std::filesystem::path& input, PointStream& stream, const PartitionOptions& options,
                    detail::PartitionRecord& r, const PassReport& report) {
  const std::uint64_t stride = std::max<std::uint64_t>(1, stream.size() / kPlanSample);
  BoundingBox box;
  std::vector<Eigen::Vector3d> sampled;
  PointCloud block;
  std::uint64_t count = 0;
  while (stream.read(options.block_points, block)) {
    report("scanning input", static_cast<double>(count));
    for (Eigen::Index i = 0; i < block.size(); ++i, ++count) {
      const Eigen::Vector3d x = block.positions.row(i).transpose();
      box.extend(x);
      if (count % stride == 0) sampled.push_back(x);
    }
  }
  if (count == 0) throw InputError(input, {}, "the file holds no points");
  r.input_points = count;
  r.normals = stream.has_normals();
  r.colors = stream.has_colors();
  r.up = stream.up();
  r.origin = origin_shift(box);
  Points sample(static_cast<Eigen::Index>(sampled.size()), 3);
  for (std::size_t i = 0; i < sampled.size(); ++i)
    sample.row(static_cast<Eigen::Index>(i)) = (sampled[i] - r.origin).transpose();
  BoundingBox relative;
  relative.extend(box.min - r.origin);
  relative.extend(box.max - r.origin);
  r.plan = plan_regions(sample, count, relative, spacing_from_sample(sample, count), options.regions);
}

/// Pass 2 over the input: every point to its region's writer in `own` and to the `halo`
/// writers of the regions near it, counted in `r`.
void distribute(PointStream& stream, const PartitionOptions& options, detail::PartitionRecord& r,
                std::vector<RegionWriter>& own, std::vector<RegionWriter>& halo, const PassReport& report) {
  const std::size_t n = r.plan.regions();
  const std::size_t record = detail::region_record_values(r);
  r.own.assign(n, 0);
  r.halo.assign(n, 0);
  stream.rewind();
  std::uint64_t seen = 0;
  std::vector<std::int32_t> near;
  PointCloud block;
  double values[7];
  while (stream.read(options.block_points, block)) {
    report("partitioning input", static_cast<double>(seen));
    for (Eigen::Index i = 0; i < block.size(); ++i) {
      const Eigen::Vector3d x = block.positions.row(i).transpose() - r.origin;
      for (int c = 0; c < 3; ++c) values[c] = x(c);
      if (r.normals)
        for (int c = 0; c < 3; ++c) values[3 + c] = block.normals(i, c);
      if (r.colors) values[r.normals ? 6 : 3] = detail::pack_color(block.colors.row(i));
      const auto k = static_cast<std::size_t>(r.plan.region_of(x));
      own[k].add(values, record);
      ++r.own[k];
      r.plan.halo_regions(x, near);
      for (const std::int32_t h : near)
        halo[static_cast<std::size_t>(h)].add(values, record), ++r.halo[static_cast<std::size_t>(h)];
    }
    seen += static_cast<std::uint64_t>(block.size());
  }
  for (auto& w : own) w.flush();
  for (auto& w : halo) w.flush();
}

}  // namespace

TiledRun TiledRun::partition(const std::filesystem::path& input, const std::filesystem::path& directory,
                             const PartitionOptions& options, const ProgressCallback& progress) {
  if (options.block_points == 0) throw OptionError("the input must be read in blocks of at least one point");
  if (options.regions.max_points == 0) throw OptionError("a region must hold at least one point");
  auto impl = std::make_unique<Impl>();
  detail::PartitionRecord& r = impl->record;
  std::tie(r.input_size, r.input_mtime) = file_identity(input);
  detail::RunRecord run = open_work_directory(directory, impl->dir);
  r.max_points = options.regions.max_points;
  r.halo_spacings = options.regions.halo_spacings;
  const std::filesystem::path& dir = impl->dir;
  const std::filesystem::path plan_file = dir / "plan.txt";
  if (std::filesystem::exists(plan_file)) {
    const detail::PartitionRecord old = detail::read_partition(plan_file);
    if (old.input_size != r.input_size || old.input_mtime != r.input_mtime || old.max_points != r.max_points ||
        old.halo_spacings != r.halo_spacings)
      throw OptionError(dir.string() +
                        " holds a run of another input, or of the input before it changed, or of other "
                        "region options: remove it, or use another work directory");
    impl->record = old;
    return TiledRun(std::move(impl));
  }
  detail::remove_files(detail::run_files(dir, run.regions));  // a partition that was interrupted

  // Pass 1: the plan from the input's count, bounds and an even sample.
  PointStream stream(input, options.read);
  const std::uint64_t declared = stream.size();
  const PassReport report = [&](std::string_view stage, double done) {
    if (progress && !progress(stage, declared == 0 ? 1.0 : std::min(1.0, done / static_cast<double>(declared))))
      throw Cancelled();
  };
  plan_from_scan(input, stream, options, r, report);

  // Pass 2: every point to its region's file and the halo files of the regions near it.
  const std::size_t n = r.plan.regions();
  run.regions = n;
  detail::write_run_record(dir, run);  // before the files it names
  const std::size_t record = detail::region_record_values(r);
  const std::size_t capacity = std::max<std::size_t>(record * 1024, options.buffer_bytes / sizeof(double) / (2 * n));
  std::vector<RegionWriter> own, halo;
  for (std::size_t k = 0; k < n; ++k) {
    own.emplace_back(impl->file("region", static_cast<std::int32_t>(k), "own"), capacity);
    halo.emplace_back(impl->file("region", static_cast<std::int32_t>(k), "halo"), capacity);
  }
  distribute(stream, options, r, own, halo, report);
  detail::write_partition(plan_file, r);  // last: the partition is complete
  return TiledRun(std::move(impl));
}

}  // namespace clustersurf
