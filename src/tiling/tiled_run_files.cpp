// The small files of a tiled run: names, the run record, plan, merge, surveys and orientations
// (text; the tiles' binary files in tile_file.cpp).

#include <clustersurf/core/errors.hpp>

#include "io/atomic_file.hpp"
#include "tiling/tiled_run_files.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <unordered_set>
#include <utility>

namespace clustersurf::detail {

namespace {

constexpr std::string_view kPlanMagic = "clustersurf-tiles 2";
constexpr std::string_view kRunMagic = "clustersurf-run 1";

/// Reads whitespace-separated fields of a text file, line by line, with the line in errors.
class Lines {
 public:
  Lines(const std::filesystem::path& file, const std::string& text) : file_(file), in_(text) {}
  /// The next line's fields, which must start with `key` (empty: any) and hold `count` more.
  std::istringstream next(std::string_view key, const char* what) {
    std::string line;
    ++line_;
    if (!std::getline(in_, line)) fail(std::string("file ends before ") + what);
    std::istringstream fields(line);
    if (!key.empty()) {
      std::string word;
      fields >> word;
      if (word != key) fail("expected \"" + std::string(key) + "\" (" + what + ")");
    }
    return fields;
  }
  template <class... T>
  void read(std::istringstream& fields, const char* what, T&... values) {
    if (!(fields >> ... >> values)) fail(std::string("malformed ") + what);
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(file_, FileLocation{line_, std::nullopt}, message);
  }

 private:
  std::filesystem::path file_;
  std::istringstream in_;
  std::uint64_t line_ = 0;
};

std::ostringstream text_stream() {
  std::ostringstream out;
  out << std::setprecision(17);  // doubles round-trip exactly
  return out;
}

}  // namespace

std::filesystem::path region_file(const std::filesystem::path& dir, std::string_view name, std::int32_t region,
                                  std::string_view ext) {
  char number[16];
  std::snprintf(number, sizeof number, "%06d", static_cast<int>(region));
  return dir / (std::string(name) + "-" + number + "." + std::string(ext));
}

namespace {

/// The files of a run: one of each kind per region ("tile-000003.bin"), and the run's own.
constexpr std::pair<std::string_view, std::string_view> kRegionFiles[] = {{"region", "own"},      {"region", "halo"},
                                                                          {"survey", "txt"},      {"tree", "cstree"},
                                                                          {"orientation", "txt"}, {"tile", "bin"}};
constexpr std::string_view kRunFiles[] = {"tree.cstree", "merge.txt", "options.txt", "plan.txt"};

/// The name of the file a write is for: `name` itself, or NAME for the temporary file
/// ".NAME.tmpXXXXXX" of an atomic write (io::AtomicFile) that a killed task left behind.
std::string written_name(const std::string& name) {
  const std::size_t tmp = name.rfind(".tmp");
  if (name.starts_with(".") && tmp != std::string::npos && tmp > 1 && name.size() == tmp + 10)
    return name.substr(1, tmp - 1);
  return name;
}

}  // namespace

bool is_run_file_name(const std::filesystem::path& file) {
  const std::string name = written_name(file.filename().string());
  for (const auto& [kind, ext] : kRegionFiles)
    if (name.starts_with(std::string(kind) + "-")) return true;
  return std::find(std::begin(kRunFiles), std::end(kRunFiles), name) != std::end(kRunFiles) || name == kRunRecordName;
}

std::vector<std::filesystem::path> run_files(const std::filesystem::path& dir, std::uint64_t regions) {
  std::unordered_set<std::string> names;
  for (const std::string_view name : kRunFiles) names.emplace(name);
  for (std::uint64_t k = 0; k < regions; ++k)
    for (const auto& [kind, ext] : kRegionFiles)
      names.insert(region_file({}, kind, static_cast<std::int32_t>(k), ext).string());
  std::vector<std::filesystem::path> out;
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator(dir, ec); !ec && it != std::filesystem::directory_iterator();
       it.increment(ec))
    if (it->is_regular_file() && !it->is_symlink() && names.count(written_name(it->path().filename().string())))
      out.push_back(it->path());
  if (ec) throw IoError(dir.string() + ": cannot list the work directory: " + ec.message());
  std::sort(out.begin(), out.end());
  return out;
}

void remove_files(const std::vector<std::filesystem::path>& files) {
  std::error_code ec;
  for (const auto& f : files)
    if (!std::filesystem::remove(f, ec) && ec) throw IoError(f.string() + ": cannot remove: " + ec.message());
}

void write_run_record(const std::filesystem::path& dir, const RunRecord& r) {
  std::ostringstream out = text_stream();
  out << kRunMagic << "\ncreated-levels " << r.created_levels << "\nregions " << r.regions << "\n";
  write_text(dir / kRunRecordName, out.str());
}

std::optional<RunRecord> read_run_record(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / kRunRecordName;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return std::nullopt;
  const std::string text = read_text(file);
  Lines lines(file, text);
  {
    std::istringstream f = lines.next("", "the header");
    std::string word, version;
    f >> word >> version;
    if (word + " " + version != kRunMagic)
      lines.fail("not a clustersurf run record (expected \"" + std::string(kRunMagic) + "\")");
  }
  RunRecord r;
  auto f = lines.next("created-levels", "the created directories");
  lines.read(f, "created directories", r.created_levels);
  f = lines.next("regions", "the region count");
  lines.read(f, "region count", r.regions);
  if (r.created_levels < 0 || r.created_levels > 4096) lines.fail("implausible count of created directories");
  return r;
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw IoError(file.string() + ": cannot open: " + std::strerror(errno));
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

void write_text(const std::filesystem::path& file, std::string_view text) {
  io::AtomicFile out(file);
  out.write(text);
  out.commit();
}

void write_partition(const std::filesystem::path& file, const PartitionRecord& r) {
  std::ostringstream out = text_stream();
  out << kPlanMagic << "\n";
  out << "input " << r.input_size << " " << r.input_mtime << " " << r.input_points << " " << (r.normals ? 1 : 0) << " "
      << (r.colors ? 1 : 0) << " " << (r.up == UpAxis::Z ? "z" : "y") << "\n";
  out << "regions-options " << r.max_points << " " << r.halo_spacings << "\n";
  out << "origin " << r.origin.x() << " " << r.origin.y() << " " << r.origin.z() << "\n";
  out << "spacing " << r.plan.point_spacing << " " << r.plan.halo << "\n";
  out << "cells " << r.plan.cells.size() << "\n";
  for (const RegionPlan::Cell& c : r.plan.cells)
    out << "cell " << c.left << " " << c.right << " " << c.axis << " " << c.split << " " << c.region << " "
        << c.box.min.x() << " " << c.box.min.y() << " " << c.box.min.z() << " " << c.box.max.x() << " " << c.box.max.y()
        << " " << c.box.max.z() << "\n";
  out << "regions " << r.plan.regions() << "\n";
  for (std::size_t k = 0; k < r.plan.regions(); ++k)
    out << "region " << r.plan.region_cell[k] << " " << r.own[k] << " " << r.halo[k] << "\n";
  write_text(file, out.str());
}

PartitionRecord read_partition(const std::filesystem::path& file) {
  const std::string text = read_text(file);
  Lines lines(file, text);
  PartitionRecord r;
  {
    std::istringstream f = lines.next("", "the header");
    std::string word, version;
    f >> word >> version;
    if (word + " " + version != kPlanMagic)
      lines.fail("not a clustersurf tile plan (expected \"" + std::string(kPlanMagic) + "\")");
  }
  int normals = 0, colors = 0;
  std::string up;
  auto f = lines.next("input", "the input line");
  lines.read(f, "input line", r.input_size, r.input_mtime, r.input_points, normals, colors, up);
  if (up != "y" && up != "z") lines.fail("the up axis must be y or z");
  r.normals = normals != 0;
  r.colors = colors != 0;
  r.up = up == "z" ? UpAxis::Z : UpAxis::Y;
  f = lines.next("regions-options", "the region options");
  lines.read(f, "region options", r.max_points, r.halo_spacings);
  f = lines.next("origin", "the origin");
  lines.read(f, "origin", r.origin.x(), r.origin.y(), r.origin.z());
  f = lines.next("spacing", "the spacing");
  lines.read(f, "spacing", r.plan.point_spacing, r.plan.halo);
  std::size_t cells = 0, regions = 0;
  f = lines.next("cells", "the cell count");
  lines.read(f, "cell count", cells);
  // A cell's line holds 12 fields, a region's 4: counts the text cannot hold are refused before
  // anything is allocated.
  if (cells == 0 || cells > text.size() / 24) lines.fail("cell count out of range for the file's size");
  r.plan.cells.resize(cells);
  for (RegionPlan::Cell& c : r.plan.cells) {
    f = lines.next("cell", "a cell");
    lines.read(f, "cell", c.left, c.right, c.axis, c.split, c.region, c.box.min.x(), c.box.min.y(), c.box.min.z(),
               c.box.max.x(), c.box.max.y(), c.box.max.z());
  }
  f = lines.next("regions", "the region count");
  lines.read(f, "region count", regions);
  if (regions == 0 || regions > cells || regions > text.size() / 8) lines.fail("region count out of range");
  r.own.resize(regions);
  r.halo.resize(regions);
  r.plan.region_cell.resize(regions);
  for (std::size_t k = 0; k < regions; ++k) {
    f = lines.next("region", "a region");
    lines.read(f, "region", r.plan.region_cell[k], r.own[k], r.halo[k]);
  }
  constexpr std::uint64_t kMaxPoints = std::uint64_t{1} << 40;
  if (r.input_points == 0 || r.input_points > kMaxPoints) lines.fail("input point count out of range");
  std::uint64_t owned = 0;
  for (std::size_t k = 0; k < regions; ++k) {
    if (r.own[k] > r.input_points || r.halo[k] > r.input_points)
      lines.fail("region " + std::to_string(k) + ": point counts out of range");
    owned += r.own[k];
  }
  if (owned != r.input_points) lines.fail("the regions' own points do not add up to the input's");
  r.plan.points = r.input_points;
  if (!r.origin.allFinite() || !(r.plan.point_spacing >= 0) || !std::isfinite(r.plan.point_spacing) ||
      !(r.plan.halo >= 0) || !std::isfinite(r.plan.halo))
    lines.fail("origin, spacing or halo is not a finite number (spacing and halo >= 0)");
  // The cells must form the tree region_of() walks: children after their parent, leaves naming
  // their region, regions naming their leaf.
  const auto n = static_cast<std::int32_t>(cells);
  for (std::int32_t i = 0; i < n; ++i) {
    const RegionPlan::Cell& c = r.plan.cells[static_cast<std::size_t>(i)];
    const bool leaf = c.left < 0 && c.right < 0;
    const bool inner = c.left > i && c.left < n && c.right > i && c.right < n && c.axis >= 0 && c.axis < 3;
    if (!(leaf ? c.region >= 0 && c.region < static_cast<std::int32_t>(regions) &&
                     r.plan.region_cell[static_cast<std::size_t>(c.region)] == i
               : inner))
      lines.fail("cell " + std::to_string(i) + " is not a valid cell of the plan");
  }
  for (std::size_t k = 0; k < regions; ++k) {
    const std::int32_t c = r.plan.region_cell[k];
    if (c < 0 || c >= n || r.plan.cells[static_cast<std::size_t>(c)].left >= 0 ||
        r.plan.cells[static_cast<std::size_t>(c)].region != static_cast<std::int32_t>(k))
      lines.fail("region " + std::to_string(k) + " does not name its cell");
  }
  return r;
}

void write_merge(const std::filesystem::path& file, const RegionMerge& m) {
  std::ostringstream out = text_stream();
  out << "merge " << m.leaves << " " << m.point_spacing << " " << m.bbox.min.x() << " " << m.bbox.min.y() << " "
      << m.bbox.min.z() << " " << m.bbox.max.x() << " " << m.bbox.max.y() << " " << m.bbox.max.z() << " " << m.auto_cell
      << "\n";
  out << "regions " << m.reach.size() << "\n";
  for (std::size_t r = 0; r < m.reach.size(); ++r)
    out << "region " << static_cast<int>(m.flipped[r]) << " " << m.reach[r] << "\n";
  write_text(file, out.str());
}

RegionMerge read_merge(const std::filesystem::path& file) {
  const std::string text = read_text(file);
  Lines lines(file, text);
  RegionMerge m;
  auto head = lines.next("merge", "the merge");
  lines.read(head, "merge", m.leaves, m.point_spacing, m.bbox.min.x(), m.bbox.min.y(), m.bbox.min.z(), m.bbox.max.x(),
             m.bbox.max.y(), m.bbox.max.z(), m.auto_cell);
  if (!m.bbox.min.allFinite() || !m.bbox.max.allFinite() || (m.bbox.min.array() > m.bbox.max.array()).any())
    lines.fail("the merged box must be finite, its minimum below its maximum");
  if (!(m.point_spacing >= 0) || !std::isfinite(m.point_spacing))
    lines.fail("the point spacing must be finite and >= 0");
  if (!(m.auto_cell >= 0) || !std::isfinite(m.auto_cell)) lines.fail("the automatic cell must be finite and >= 0");
  auto count_line = lines.next("regions", "the region count");
  std::uint64_t count = 0;
  lines.read(count_line, "region count", count);
  if (count > text.size() / 10) lines.fail("more regions than the file has lines for");  // "region 0 0\n" is 11 bytes
  m.flipped.resize(count);
  m.reach.resize(count);
  for (std::uint64_t r = 0; r < count; ++r) {
    auto f = lines.next("region", "every region");
    int flipped = 0;
    lines.read(f, "region", flipped, m.reach[r]);
    if (flipped != 0 && flipped != 1) lines.fail("a region is flipped (1) or not (0)");
    if (!(m.reach[r] >= 0) || !std::isfinite(m.reach[r])) lines.fail("a region's reach must be finite and >= 0");
    m.flipped[r] = static_cast<std::uint8_t>(flipped);
  }
  return m;
}

void write_survey(const std::filesystem::path& file, const RegionSurvey& s) {
  std::ostringstream out = text_stream();
  out << "survey " << s.points << " " << s.median_spacing << " " << s.median_spread << " " << s.noise_sigma << " "
      << s.outliers;
  if (s.bbox.empty())
    out << " empty\n";
  else
    out << " " << s.bbox.min.x() << " " << s.bbox.min.y() << " " << s.bbox.min.z() << " " << s.bbox.max.x() << " "
        << s.bbox.max.y() << " " << s.bbox.max.z() << "\n";
  write_text(file, out.str());
}

RegionSurvey read_survey(const std::filesystem::path& file) {
  Lines lines(file, read_text(file));
  RegionSurvey s;
  auto f = lines.next("survey", "the survey");
  lines.read(f, "survey", s.points, s.median_spacing, s.median_spread, s.noise_sigma, s.outliers);
  for (const double v : {s.median_spacing, s.median_spread, s.noise_sigma})
    if (!(v >= 0) || !std::isfinite(v)) lines.fail("survey values must be finite and >= 0");
  std::string rest;
  if (f >> rest && rest != "empty") {
    std::istringstream box(rest + " " + std::string(std::istreambuf_iterator<char>(f), {}));
    lines.read(box, "survey box", s.bbox.min.x(), s.bbox.min.y(), s.bbox.min.z(), s.bbox.max.x(), s.bbox.max.y(),
               s.bbox.max.z());
  }
  return s;
}

void write_orientation(const std::filesystem::path& file, const OrientationReport& o, bool empty) {
  std::ostringstream out = text_stream();
  out << "orientation " << o.used_normals << " " << o.used_scanners << " " << o.flipped << " " << o.components << " "
      << (empty ? "empty" : "tree") << "\n";
  write_text(file, out.str());
}

OrientationReport read_orientation(const std::filesystem::path& file, bool& empty) {
  Lines lines(file, read_text(file));
  OrientationReport o;
  auto f = lines.next("orientation", "the orientation");
  std::string tree;
  lines.read(f, "orientation", o.used_normals, o.used_scanners, o.flipped, o.components, tree);
  if (tree != "empty" && tree != "tree") lines.fail("expected \"empty\" or \"tree\" after the orientation");
  empty = tree == "empty";
  return o;
}

}  // namespace clustersurf::detail
