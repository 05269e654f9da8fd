// A tiled reconstruction's work directory: the partition into region files, and each stage's
// task per region, reading and writing files only.

#include <clustersurf/errors.hpp>
#include <clustersurf/mesh_colors.hpp>
#include <clustersurf/point_stream.hpp>
#include <clustersurf/tiled_run.hpp>
#include <clustersurf/tree_file.hpp>

#include "io/tiled_run_files.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <mutex>
#include <tuple>
#include <sstream>

namespace clustersurf {

namespace {

/// Even sample of the input that places the plan's cuts and measures its halo.
constexpr std::uint64_t kPlanSample = 200000;

using detail::region_file;

/// The input's size and modification time (nanoseconds), which say whether a partition is of it.
std::pair<std::uintmax_t, std::int64_t> file_identity(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw IoError(file.string() + ": cannot open: " + ec.message());
  const auto time = std::filesystem::last_write_time(file, ec);
  if (ec) throw IoError(file.string() + ": cannot stat: " + ec.message());
  return {size, static_cast<std::int64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count())};
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

/// The files a run makes in its directory (plan.txt last), and the temporary files of writes
/// a killed task left behind (".NAME.tmpXXXXXX").
bool is_run_file(const std::filesystem::path& file) {
  std::string name = file.filename().string();
  if (name.starts_with(".") && name.find(".tmp") != std::string::npos) name = name.substr(1, name.rfind(".tmp") - 1);
  for (const char* prefix : {"region-", "survey-", "tree-", "orientation-", "tile-"})
    if (name.starts_with(prefix)) return true;
  return name == "tree.cstree" || name == "merge.txt" || name == "options.txt" || name == "plan.txt";
}

void remove_run_files(const std::filesystem::path& dir) {
  std::error_code ec;
  std::vector<std::filesystem::path> files;
  for (auto it = std::filesystem::directory_iterator(dir, ec); !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    if (it->is_regular_file() && is_run_file(it->path())) files.push_back(it->path());
  if (ec) throw IoError(dir.string() + ": cannot list the work directory: " + ec.message());
  for (const auto& f : files)
    if (!std::filesystem::remove(f, ec) && ec) throw IoError(f.string() + ": cannot remove: " + ec.message());
}

/// The options that decide a run's results, as text (options.txt).
std::string describe(const ReconstructOptions& o) {
  std::ostringstream out;
  out << std::setprecision(17);
  const BuildOptions& b = o.build;
  out << "build " << static_cast<int>(b.proxy) << " " << static_cast<int>(b.splitter) << " " << static_cast<int>(b.metric) << " "
      << static_cast<int>(b.threshold_mode) << " " << b.tolerance << " " << b.noise_factor << " " << b.min_points << " " << b.max_depth
      << " " << b.alpha << " " << b.kstep << " " << b.lloyd_restarts << " " << b.proxy_lloyd_iterations << " " << b.seed << " "
      << b.support_factor << " " << b.remove_outliers << " " << b.use_normals << " " << b.frames_from_normals << " " << b.creases
      << "\noutliers " << b.outliers.neighbors << " " << b.outliers.local_ratio << " " << b.outliers.global_ratio << " "
      << b.outliers.min_points << "\nnoise " << b.noise.neighbors << " " << b.noise.samples << " " << b.noise.min_width_ratio << " "
      << b.noise.detail_ratio << " " << b.noise.residual_differences << "\n";
  const SurfaceMeshOptions& m = o.meshing;
  out << "mesh " << m.grid.resolution << " " << (m.grid.voxel_size ? *m.grid.voxel_size : 0.0) << " " << m.grid.newton_steps << " "
      << m.grid.min_weight << " " << m.grid.fill_cells << " " << m.auto_resolution << "\ntrim " << m.trim.spread_factor << " "
      << m.trim.neighbors << " " << m.trim.min_component_points << "\n";
  return out.str();
}

}  // namespace

struct TiledRun::Impl {
  std::filesystem::path dir;
  detail::PartitionRecord record;

  std::filesystem::path file(std::string_view name, std::int32_t region, std::string_view ext) const {
    return region_file(dir, name, region, ext);
  }
  void check(std::int32_t region) const {
    if (region < 0 || static_cast<std::size_t>(region) >= record.plan.regions())
      throw OptionError("region " + std::to_string(region) + " is not in the plan (it has " + std::to_string(record.plan.regions()) + ")");
  }
  /// A stage's input file, or InputError saying which stage must run first.
  std::filesystem::path need(const std::filesystem::path& f, const char* stage) const {
    if (!std::filesystem::exists(f)) throw InputError(f, {}, std::string("missing: run ") + stage + " first");
    return f;
  }
  ClusterTree merged_tree() const { return load_tree(need(dir / "tree.cstree", "the merge")); }
  RegionMerge merge_record() const { return detail::read_merge(need(dir / "merge.txt", "the merge")); }
  /// A region's tree as its build wrote it (empty for an empty region).
  ClusterTree region_tree(std::int32_t region) const {
    bool empty = false;
    detail::read_orientation(need(file("orientation", region, "txt"), "every region's build"), empty);
    return empty ? ClusterTree{} : load_tree(need(file("tree", region, "cstree"), "every region's build"));
  }
};

TiledRun::TiledRun(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
TiledRun::TiledRun(const std::filesystem::path& directory) : impl_(std::make_unique<Impl>()) {
  impl_->dir = directory;
  impl_->record = detail::read_partition(impl_->need(directory / "plan.txt", "the partition"));
}
TiledRun::~TiledRun() = default;
TiledRun::TiledRun(TiledRun&&) noexcept = default;
TiledRun& TiledRun::operator=(TiledRun&&) noexcept = default;

const std::filesystem::path& TiledRun::directory() const noexcept { return impl_->dir; }
const RegionPlan& TiledRun::plan() const noexcept { return impl_->record.plan; }
std::uint64_t TiledRun::input_points() const noexcept { return impl_->record.input_points; }
bool TiledRun::has_normals() const noexcept { return impl_->record.normals; }
const Eigen::Vector3d& TiledRun::origin() const noexcept { return impl_->record.origin; }

TiledRun TiledRun::partition(const std::filesystem::path& input, const std::filesystem::path& directory,
                             const PartitionOptions& options, const ProgressCallback& progress) {
  if (options.block_points == 0) throw OptionError("the input must be read in blocks of at least one point");
  if (options.regions.max_points == 0) throw OptionError("a region must hold at least one point");
  auto impl = std::make_unique<Impl>();
  impl->dir = directory;
  detail::PartitionRecord& r = impl->record;
  std::tie(r.input_size, r.input_mtime) = file_identity(input);
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  if (ec) throw IoError(directory.string() + ": cannot create the work directory: " + ec.message());
  r.max_points = options.regions.max_points;
  r.halo_spacings = options.regions.halo_spacings;
  const std::filesystem::path plan_file = directory / "plan.txt";
  if (std::filesystem::exists(plan_file)) {
    const detail::PartitionRecord old = detail::read_partition(plan_file);
    if (old.input_size == r.input_size && old.input_mtime == r.input_mtime && old.max_points == r.max_points &&
        old.halo_spacings == r.halo_spacings) {
      impl->record = old;
      return TiledRun(std::move(impl));
    }
  }
  remove_run_files(directory);  // another input's or options' partition and results

  // Pass 1: count, bounds, an even sample.
  PointStream stream(input, options.read);
  const std::uint64_t declared = stream.size();
  const std::uint64_t stride = std::max<std::uint64_t>(1, declared / kPlanSample);
  const auto report = [&](std::string_view stage, double done) {
    if (progress && !progress(stage, declared == 0 ? 1.0 : std::min(1.0, done / static_cast<double>(declared)))) throw Cancelled();
  };
  BoundingBox box;
  std::vector<Eigen::Vector3d> sampled;
  PointCloud block;
  std::uint64_t seen = 0, count = 0;
  while (stream.read(options.block_points, block)) {
    report("scanning input", static_cast<double>(seen));
    for (Eigen::Index i = 0; i < block.size(); ++i, ++count) {
      const Eigen::Vector3d x = block.positions.row(i).transpose();
      box.extend(x);
      if (count % stride == 0) sampled.push_back(x);
    }
    seen += static_cast<std::uint64_t>(block.size());
  }
  if (count == 0) throw InputError(input, {}, "the file holds no points");
  r.input_points = count;
  r.normals = stream.has_normals();
  r.origin = origin_shift(box);
  Points sample(static_cast<Eigen::Index>(sampled.size()), 3);
  for (std::size_t i = 0; i < sampled.size(); ++i) sample.row(static_cast<Eigen::Index>(i)) = (sampled[i] - r.origin).transpose();
  BoundingBox relative;
  relative.extend(box.min - r.origin);
  relative.extend(box.max - r.origin);
  r.plan = plan_regions(sample, count, relative, spacing_from_sample(sample, count), options.regions);

  // Pass 2: every point to its region's file and the halo files of the regions near it.
  const std::size_t n = r.plan.regions();
  const std::size_t record = r.normals ? 6 : 3;
  const std::size_t capacity = std::max<std::size_t>(record * 1024, options.buffer_bytes / sizeof(double) / (2 * n));
  std::vector<RegionWriter> own, halo;
  for (std::size_t k = 0; k < n; ++k) {
    own.emplace_back(impl->file("region", static_cast<std::int32_t>(k), "own"), capacity);
    halo.emplace_back(impl->file("region", static_cast<std::int32_t>(k), "halo"), capacity);
  }
  r.own.assign(n, 0);
  r.halo.assign(n, 0);
  stream.rewind();
  seen = 0;
  std::vector<std::int32_t> near;
  double values[6];
  while (stream.read(options.block_points, block)) {
    report("partitioning input", static_cast<double>(seen));
    for (Eigen::Index i = 0; i < block.size(); ++i) {
      const Eigen::Vector3d x = block.positions.row(i).transpose() - r.origin;
      for (int c = 0; c < 3; ++c) values[c] = x(c);
      if (r.normals)
        for (int c = 0; c < 3; ++c) values[3 + c] = block.normals(i, c);
      const auto k = static_cast<std::size_t>(r.plan.region_of(x));
      own[k].add(values, record);
      ++r.own[k];
      r.plan.halo_regions(x, near);
      for (const std::int32_t h : near) halo[static_cast<std::size_t>(h)].add(values, record), ++r.halo[static_cast<std::size_t>(h)];
    }
    seen += static_cast<std::uint64_t>(block.size());
  }
  for (auto& w : own) w.flush();
  for (auto& w : halo) w.flush();
  detail::write_partition(plan_file, r);  // last: the partition is complete
  return TiledRun(std::move(impl));
}

RegionCloud TiledRun::load(std::int32_t region) const {
  impl_->check(region);
  const detail::PartitionRecord& r = impl_->record;
  const std::size_t record = r.normals ? 6 : 3;
  const auto k = static_cast<std::size_t>(region);
  RegionCloud out;
  out.own = r.own[k];
  const auto rows = static_cast<Eigen::Index>(r.own[k] + r.halo[k]);
  out.points.positions.resize(rows, 3);
  if (r.normals) out.points.normals.resize(rows, 3);
  out.points.origin = r.origin;
  Eigen::Index row = 0;
  for (const char* part : {"own", "halo"}) {
    const std::filesystem::path f = impl_->need(impl_->file("region", region, part), "the partition");
    const std::uint64_t expected = (part[0] == 'o' ? r.own[k] : r.halo[k]) * record * sizeof(double);
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(f, ec);
    if (ec) throw IoError(f.string() + ": cannot open: " + ec.message());
    if (size != expected)
      throw InputError(f, FileLocation{std::nullopt, std::min<std::uint64_t>(size, expected)},
                       "region file holds " + std::to_string(size) + " bytes, the plan says " + std::to_string(expected));
    std::FILE* in = std::fopen(f.c_str(), "rb");
    if (in == nullptr) throw IoError(f.string() + ": cannot open: " + std::strerror(errno));
    std::vector<double> chunk(record * 65536);
    const auto points = static_cast<Eigen::Index>(expected / (record * sizeof(double)));
    for (Eigen::Index done = 0; done < points;) {
      const auto m = std::min<Eigen::Index>(65536, points - done);
      if (std::fread(chunk.data(), sizeof(double) * record, static_cast<std::size_t>(m), in) != static_cast<std::size_t>(m)) {
        std::fclose(in);
        throw IoError(f.string() + ": read failed");
      }
      for (Eigen::Index i = 0; i < m; ++i, ++row) {
        const double* v = chunk.data() + static_cast<std::size_t>(i) * record;
        out.points.positions.row(row) << v[0], v[1], v[2];
        if (r.normals) out.points.normals.row(row) << v[3], v[4], v[5];
      }
      done += m;
    }
    std::fclose(in);
  }
  return out;
}

bool TiledRun::done(std::string_view stage, std::int32_t region) const {
  impl_->check(region);
  if (stage == "survey") return std::filesystem::exists(impl_->file("survey", region, "txt"));
  if (stage == "build") return std::filesystem::exists(impl_->file("orientation", region, "txt"));
  if (stage == "mesh") return std::filesystem::exists(impl_->file("tile", region, "bin"));
  throw OptionError("no stage \"" + std::string(stage) + "\" (survey, build or mesh)");
}

void TiledRun::claim(const ReconstructOptions& options) const {
  const std::filesystem::path f = impl_->dir / "options.txt";
  const std::string text = describe(options);
  if (std::filesystem::exists(f)) {
    if (detail::read_text(f) != text)
      throw OptionError(impl_->dir.string() + " holds a run made with other options: remove it, or use another work directory");
    return;
  }
  detail::write_text(f, text);
}

void TiledRun::survey(std::int32_t region, const BuildOptions& options) const {
  if (done("survey", region)) return;
  detail::write_survey(impl_->file("survey", region, "txt"), survey_region(load(region), options));
}

CloudScale TiledRun::scale() const {
  std::vector<RegionSurvey> surveys;
  for (std::int32_t k = 0; k < static_cast<std::int32_t>(regions()); ++k)
    surveys.push_back(detail::read_survey(impl_->need(impl_->file("survey", k, "txt"), "every region's survey")));
  return combine_surveys(surveys);
}

void TiledRun::build(std::int32_t region, const BuildOptions& options) const {
  if (done("build", region)) return;
  const CloudScale scale = this->scale();
  RegionCloud points = load(region);
  if (options.remove_outliers) mark_outliers(points, scale, options.outliers);
  BuildOptions build = options;
  build.keep_point_leaves = false;
  OrientationReport oriented;
  const ClusterTree tree = build_region_tree(points, plan(), region, scale, build, &oriented);
  if (!tree.nodes.empty()) save_tree(impl_->file("tree", region, "cstree"), tree);
  detail::write_orientation(impl_->file("orientation", region, "txt"), oriented, tree.nodes.empty());
}

ClusterTree TiledRun::merge() const {
  const std::filesystem::path f = impl_->dir / "tree.cstree";
  if (std::filesystem::exists(f)) return impl_->merged_tree();
  std::vector<ClusterTree> trees;
  bool propagated = false;
  for (std::int32_t k = 0; k < static_cast<std::int32_t>(regions()); ++k) {
    bool empty = false;
    const OrientationReport o = detail::read_orientation(impl_->need(impl_->file("orientation", k, "txt"), "every region's build"), empty);
    trees.push_back(empty ? ClusterTree{} : load_tree(impl_->need(impl_->file("tree", k, "cstree"), "every region's build")));
    propagated = propagated || (!empty && !o.used_normals && !o.used_scanners);
  }
  RegionMerge record;
  ClusterTree merged = merge_region_trees(plan(), std::move(trees), propagated, record);
  detail::write_merge(impl_->dir / "merge.txt", record);
  save_tree(f, merged);  // last: the merge is done
  return merged;
}

RegionMerge TiledRun::merge_record() const { return impl_->merge_record(); }

OrientationReport TiledRun::orientation() const {
  OrientationReport sum;
  sum.used_normals = sum.used_scanners = true;
  for (std::int32_t k = 0; k < static_cast<std::int32_t>(regions()); ++k) {
    bool empty = false;
    const OrientationReport o = detail::read_orientation(impl_->need(impl_->file("orientation", k, "txt"), "every region's build"), empty);
    if (empty) continue;
    sum.used_normals = sum.used_normals && o.used_normals;
    sum.used_scanners = sum.used_scanners && o.used_scanners;
    sum.flipped += o.flipped;
    sum.components += o.components;
  }
  return sum;
}

void TiledRun::mesh(std::int32_t region, const ReconstructOptions& options) const {
  if (done("mesh", region)) return;
  require_tiled_meshing(options.meshing);
  impl_->need(impl_->dir / "tree.cstree", "the merge");
  // The tile's tree from the region trees its leaves may come from, never the whole tree.
  const RegionMerge merge = impl_->merge_record();
  if (merge.reach.size() != regions()) throw InputError(impl_->dir / "merge.txt", {}, "the merge record does not match the plan");
  std::vector<ClusterTree> trees(regions());
  ClusterTree first = impl_->region_tree(region);
  for (std::int32_t k = 0; first.nodes.empty() && k < static_cast<std::int32_t>(regions()); ++k)
    if (merge.reach[static_cast<std::size_t>(k)] > 0) first = impl_->region_tree(k);  // for the cell size: any non-empty region
  MeshOptions grid = options.meshing.grid;
  first.bbox = merge.bbox;
  grid.voxel_size = tiled_cell_size(first, options.meshing);
  first = {};
  for (const std::int32_t k : tile_regions(plan(), merge, region, grid)) trees[static_cast<std::size_t>(k)] = impl_->region_tree(k);
  RegionCloud points = load(region);
  if (options.build.remove_outliers) mark_outliers(points, scale(), options.build.outliers);
  MeshTile tile;
  tile.region = region;
  if (std::any_of(trees.begin(), trees.end(), [](const ClusterTree& t) { return !t.nodes.empty(); })) {
    const ClusterTree tree = tile_tree(plan(), std::move(trees), merge);
    tile = mesh_tile(ImplicitSurface(tree), plan(), region, points, grid, options.meshing.trim);
  }
  detail::write_tile(impl_->file("tile", region, "bin"), tile);
}

SurfaceMesh TiledRun::join(const SurfaceMeshOptions& options) const {
  require_tiled_meshing(options);
  const auto start = std::chrono::steady_clock::now();
  SurfaceMesh out;
  std::vector<MeshTile> tiles;
  for (std::int32_t k = 0; k < static_cast<std::int32_t>(regions()); ++k) {
    tiles.push_back(detail::read_tile(impl_->need(impl_->file("tile", k, "bin"), "every region's mesh")));
    out.grid.voxel_size = tiles.back().grid.voxel_size;
    out.grid.evaluated_corners += tiles.back().grid.evaluated_corners;
    out.grid.surface_cells += tiles.back().grid.surface_cells;
  }
  out.mesh = join_tiles(tiles, options.trim);
  tiles.clear();
  out.blended_nodes = impl_->merge_record().leaves;
  if (options.decimation.enabled()) out.mesh = decimate(out.mesh, options.decimation, &out.decimation);
  if (options.coloring == MeshColoring::ByNode) {
    const ClusterTree tree = impl_->merged_tree();  // the colors need every leaf
    out.mesh.colors = colors_by_node(out.mesh, ImplicitSurface(tree));
  }
  out.mesh.origin = origin();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

WrittenMesh TiledRun::write_mesh(const std::filesystem::path& file, const SurfaceMeshOptions& options, const PlyWriteOptions& ply) const {
  require_tiled_meshing(options);
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  WrittenMesh out;
  out.file = file;
  if (extension != ".ply" || !ply.binary || ply.double_precision || options.decimation.enabled()) {
    const SurfaceMesh mesh = join(options);
    write_triangle_mesh(file, mesh.mesh, ply);
    out.vertices = static_cast<std::size_t>(mesh.mesh.vertices.rows());
    out.triangles = static_cast<std::size_t>(mesh.mesh.triangles.rows());
    out.blended_nodes = mesh.blended_nodes;
    out.grid = mesh.grid;
    out.decimation = mesh.decimation;
    out.seconds = mesh.seconds;
    return out;
  }
  const auto start = std::chrono::steady_clock::now();
  out.blended_nodes = impl_->merge_record().leaves;
  out.streamed = true;
  // Only colors by node need the merged tree here.
  std::optional<ClusterTree> tree;
  std::optional<ImplicitSurface> surface;
  if (options.coloring == MeshColoring::ByNode) tree = impl_->merged_tree(), surface.emplace(*tree);
  std::vector<std::uint8_t> counted(regions(), 0);  // the join reads every tile several times
  const auto tile = [&](std::int32_t k) {
    MeshTile t = detail::read_tile(impl_->need(impl_->file("tile", k, "bin"), "every region's mesh"));
    if (!counted[static_cast<std::size_t>(k)]++) {
      out.grid.voxel_size = t.grid.voxel_size;
      out.grid.evaluated_corners += t.grid.evaluated_corners;
      out.grid.surface_cells += t.grid.surface_cells;
    }
    return t;
  };
  const JoinedMesh joined = join_tiles_to_ply(tile, plan(), options.trim, file,
                                              surface ? &*surface : nullptr);
  out.vertices = joined.vertices;
  out.triangles = joined.triangles;
  out.removed_components = joined.removed_components;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

std::uint64_t region_points_for_memory(std::uint64_t memory_limit) {
  if (memory_limit < 2 * kProcessBytes) throw OptionError("the memory limit must be at least 128M");
  return (memory_limit - kProcessBytes) / kRegionBytesPerPoint;
}

std::uint64_t parse_memory_size(std::string_view text) {
  std::string s(text);
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string suffix = s.substr(used);
  for (const char* tail : {"iB", "B"})
    if (suffix.size() > 1 && suffix.ends_with(tail)) suffix.resize(suffix.size() - std::strlen(tail));
  double scale = 1;
  if (suffix == "K" || suffix == "k") scale = 1024.0;
  else if (suffix == "M" || suffix == "m") scale = 1024.0 * 1024;
  else if (suffix == "G" || suffix == "g") scale = 1024.0 * 1024 * 1024;
  else if (suffix == "T" || suffix == "t") scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!suffix.empty()) used = 0;
  const double bytes = value * scale;
  if (used == 0 || !(bytes >= 1) || !(bytes < 1.8e19))
    throw OptionError("a memory size is a number with an optional K, M, G or T (e.g. 4G), not \"" + s + "\"");
  return static_cast<std::uint64_t>(bytes);
}

OutOfCoreReconstruction reconstruct_out_of_core(const std::filesystem::path& input, const ReconstructOptions& options,
                                                const OutOfCoreOptions& out_of_core, const ProgressCallback& progress) {
  if (out_of_core.work_directory.empty()) throw OptionError("an out-of-core run needs a work directory");
  if (options.mesh && out_of_core.mesh_output.empty()) throw OptionError("an out-of-core run writes its mesh to a file: give one");
  if (options.mesh) require_tiled_meshing(options.meshing);
  const auto start = std::chrono::steady_clock::now();
  PartitionOptions partition;
  partition.regions.max_points = region_points_for_memory(out_of_core.memory_limit);
  partition.read = out_of_core.read;
  // The partition's buffers and blocks within the limit too: an eighth of the working memory
  // for the region files' buffers, a sixteenth for a block of points (48 bytes each).
  const std::uint64_t working = out_of_core.memory_limit - kProcessBytes;
  partition.buffer_bytes = static_cast<std::size_t>(std::min<std::uint64_t>(partition.buffer_bytes, working / 8));
  partition.block_points = static_cast<std::size_t>(std::clamp<std::uint64_t>(working / 16 / 48, 4096, partition.block_points));
  OutOfCoreReconstruction out;
  auto lap = std::chrono::steady_clock::now();
  const auto timed = [&](const char* name) {
    const auto now = std::chrono::steady_clock::now();
    out.stage_seconds.emplace_back(name, std::chrono::duration<double>(now - lap).count());
    lap = now;
  };
  const TiledRun run = TiledRun::partition(input, out_of_core.work_directory, partition, progress);
  run.claim(options);
  timed("partition");
  const auto n = static_cast<std::int32_t>(run.regions());
  out.regions = run.regions();
  const auto stage = [&](std::string_view name, std::int32_t done) {
    if (progress && !progress(name, static_cast<double>(done) / static_cast<double>(n))) throw Cancelled();
  };
  for (std::int32_t k = 0; k < n; ++k) stage("surveying regions", k), run.survey(k, options.build);
  timed("survey");
  for (std::int32_t k = 0; k < n; ++k) stage("building regions", k), run.build(k, options.build);
  timed("build");
  run.merge();  // not held while the tiles are meshed: the tasks read the region trees
  out.orientation = run.orientation();
  timed("merge");
  out.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (options.mesh) {
    const auto mesh_start = std::chrono::steady_clock::now();
    for (std::int32_t k = 0; k < n; ++k) stage("meshing tiles", k), run.mesh(k, options);
    timed("mesh");
    stage("joining tiles", n);
    out.mesh = run.write_mesh(out_of_core.mesh_output, options.meshing, out_of_core.ply);
    timed("join");
    out.mesh->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - mesh_start).count();
  }
  out.tree = run.merge();  // read back from its file
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator(out_of_core.work_directory, ec); !ec && it != std::filesystem::directory_iterator();
       it.increment(ec))
    if (it->is_regular_file() && is_run_file(it->path())) out.work_bytes += it->file_size();
  if (out_of_core.remove_work_directory) {
    remove_run_files(out_of_core.work_directory);
    std::filesystem::remove(out_of_core.work_directory, ec);  // only when that left it empty
  }
  return out;
}

}  // namespace clustersurf
