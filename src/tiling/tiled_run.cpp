// A tiled reconstruction's work directory: each stage's task per region, reading and writing
// files only (the partition: region_partition.cpp).

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

#include "tiling/region_stages.hpp"
#include "tiling/tiled_run_files.hpp"
#include "tiling/tiled_run_impl.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string_view>
#include <type_traits>

namespace clustersurf {

namespace {

/// Fields of ReconstructOptions that decide nothing a run stores: whether to mesh at all, the
/// walk's memory guard, and what the join applies to the welded tiles.
constexpr std::array<std::string_view, 5> kNotStored = {"mesh", "meshing.grid.memory_limit", "meshing.closing",
                                                        "meshing.decimation", "meshing.distance_scale"};

/// One line "name value" per field of `o` (nested option structs by their fields, names joined
/// by dots), but the kNotStored ones.
template <class Options>
void write_fields(std::ostream& out, const Options& o, const std::string& prefix) {
  for_each_field(o, [&](std::string_view name, const auto& value) {
    using V = std::remove_cvref_t<decltype(value)>;
    const std::string key = prefix + std::string(name);
    if (std::find(kNotStored.begin(), kNotStored.end(), key) != kNotStored.end()) return;
    if constexpr (std::is_enum_v<V>) {
      out << key << ' ' << static_cast<long long>(value) << '\n';
    } else if constexpr (std::is_arithmetic_v<V>) {
      out << key << ' ' << +value << '\n';
    } else if constexpr (kIsOptional<V>) {
      out << key << ' ';
      if (value)
        out << +*value;
      else
        out << "none";
      out << '\n';
    } else {
      write_fields(out, value, key + '.');
    }
  });
}

}  // namespace

std::string options_fingerprint(const ReconstructOptions& options) {
  std::ostringstream out;
  out << std::setprecision(17);
  write_fields(out, options, "");
  return out.str();
}

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

RegionCloud TiledRun::load(std::int32_t region) const {
  impl_->check(region);
  const detail::PartitionRecord& r = impl_->record;
  const std::size_t record = detail::region_record_values(r);
  const auto k = static_cast<std::size_t>(region);
  RegionCloud out;
  out.own = r.own[k];
  const auto rows = static_cast<Eigen::Index>(r.own[k] + r.halo[k]);
  out.points.positions.resize(rows, 3);
  if (r.normals) out.points.normals.resize(rows, 3);
  if (r.colors) out.points.colors.resize(rows, 3);
  out.points.origin = r.origin;
  out.points.up = r.up;
  Eigen::Index row = 0;
  for (const char* part : {"own", "halo"}) {
    const std::filesystem::path f = impl_->need(impl_->file("region", region, part), "the partition");
    const std::uint64_t expected = (part[0] == 'o' ? r.own[k] : r.halo[k]) * record * sizeof(double);
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(f, ec);
    if (ec) throw IoError(f.string() + ": cannot open: " + ec.message());
    if (size != expected)
      throw InputError(
          f, FileLocation{std::nullopt, std::min<std::uint64_t>(size, expected)},
          "region file holds " + std::to_string(size) + " bytes, the plan says " + std::to_string(expected));
    std::FILE* in = std::fopen(f.c_str(), "rb");
    if (in == nullptr) throw IoError(f.string() + ": cannot open: " + std::strerror(errno));
    std::vector<double> chunk(record * 65536);
    const auto points = static_cast<Eigen::Index>(expected / (record * sizeof(double)));
    for (Eigen::Index done = 0; done < points;) {
      const auto m = std::min<Eigen::Index>(65536, points - done);
      if (std::fread(chunk.data(), sizeof(double) * record, static_cast<std::size_t>(m), in) !=
          static_cast<std::size_t>(m)) {
        std::fclose(in);
        throw IoError(f.string() + ": read failed");
      }
      for (Eigen::Index i = 0; i < m; ++i, ++row) {
        const double* v = chunk.data() + static_cast<std::size_t>(i) * record;
        out.points.positions.row(row) << v[0], v[1], v[2];
        if (r.normals) out.points.normals.row(row) << v[3], v[4], v[5];
        if (r.colors) out.points.colors.row(row) = detail::unpack_color(v[r.normals ? 6 : 3]);
      }
      done += m;
    }
    std::fclose(in);
  }
  return out;
}

std::uintmax_t TiledRun::file_bytes() const {
  std::uintmax_t bytes = 0;
  std::error_code ec;
  for (const std::filesystem::path& f : detail::run_files(impl_->dir, regions())) {
    const std::uintmax_t size = std::filesystem::file_size(f, ec);
    if (!ec) bytes += size;
  }
  return bytes;
}

void remove_tiled_run(const std::filesystem::path& directory) {
  std::error_code ec;
  if (!std::filesystem::is_directory(directory, ec)) return;
  const std::optional<detail::RunRecord> record = detail::read_run_record(directory);
  if (!record) return;
  detail::remove_files(detail::run_files(directory, record->regions));
  detail::remove_files({directory / detail::kRunRecordName});
  // The directories the run created, each only when that left it empty (remove() fails on
  // a directory that holds anything).
  std::filesystem::path level = std::filesystem::canonical(directory, ec);
  for (int k = 0; k < record->created_levels && !ec && level.has_relative_path(); ++k, level = level.parent_path())
    if (!std::filesystem::remove(level, ec)) break;
}

void TiledRun::check_output(const std::filesystem::path& file) const {
  std::error_code ec;
  if (detail::is_run_file_name(file) &&
      std::filesystem::equivalent(file.parent_path().empty() ? "." : file.parent_path(), impl_->dir, ec))
    throw OptionError("the output file " + file.string() +
                      " has the name of one of the work directory's own files: choose another name");
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
  const std::string text = options_fingerprint(options);
  if (std::filesystem::exists(f)) {
    if (detail::read_text(f) != text)
      throw OptionError(impl_->dir.string() +
                        " holds a run made with other options: remove it, or use another work directory");
    return;
  }
  detail::write_text(f, text);
}

void TiledRun::survey(std::int32_t region, const BuildOptions& options) const {
  if (done("survey", region)) return;
  detail::write_survey(impl_->file("survey", region, "txt"), survey_region(load(region), input_points(), options));
}

CloudScale TiledRun::scale() const {
  std::vector<RegionSurvey> surveys;
  for (std::int32_t k = 0; k < static_cast<std::int32_t>(regions()); ++k)
    surveys.push_back(detail::read_survey(impl_->need(impl_->file("survey", k, "txt"), "every region's survey")));
  return combine_surveys(surveys);
}

void TiledRun::build(std::int32_t region, const BuildOptions& options) const {
  if (done("build", region)) return;
  BuildOptions build = options;
  build.keep_point_leaves = false;
  OrientationReport oriented;
  const ClusterTree tree = detail::build_region(load(region), plan(), region, scale(), build, oriented);
  if (!tree.nodes.empty()) save_tree(impl_->file("tree", region, "cstree"), tree);
  detail::write_orientation(impl_->file("orientation", region, "txt"), oriented, tree.nodes.empty());
}

ClusterTree TiledRun::merge() const {
  const std::filesystem::path f = impl_->dir / "tree.cstree";
  if (std::filesystem::exists(f)) return impl_->merged_tree();
  std::vector<ClusterTree> trees;
  std::vector<OrientationReport> oriented(regions());
  std::vector<std::uint8_t> empty(regions(), 0);
  for (std::int32_t k = 0; k < static_cast<std::int32_t>(regions()); ++k) {
    oriented[static_cast<std::size_t>(k)] = impl_->orientation(k, empty[static_cast<std::size_t>(k)]);
    trees.push_back(empty[static_cast<std::size_t>(k)] ? ClusterTree{} : impl_->region_tree(k));
  }
  RegionMerge record;
  ClusterTree merged = merge_region_trees(plan(), std::move(trees), detail::propagated(oriented, empty), record);
  record.auto_cell = detail::merged_auto_cell(merged);
  detail::write_merge(impl_->dir / "merge.txt", record);
  save_tree(f, merged);  // last: the merge is done
  return merged;
}

RegionMerge TiledRun::merge_record() const { return impl_->merge_record(); }

OrientationReport TiledRun::orientation() const {
  std::vector<OrientationReport> oriented(regions());
  std::vector<std::uint8_t> empty(regions(), 0);
  for (std::int32_t k = 0; k < static_cast<std::int32_t>(regions()); ++k)
    oriented[static_cast<std::size_t>(k)] = impl_->orientation(k, empty[static_cast<std::size_t>(k)]);
  return detail::combine_orientations(oriented, empty);
}

void TiledRun::mesh(std::int32_t region, const ReconstructOptions& options) const {
  if (done("mesh", region)) return;
  require_tiled_meshing(options.meshing);
  impl_->need(impl_->dir / "tree.cstree", "the merge");
  // The tile's tree from the region trees its leaves may come from, never the whole tree.
  const RegionMerge merge = impl_->merge_record();
  if (merge.reach.size() != regions())
    throw InputError(impl_->dir / "merge.txt", {}, "the merge record does not match the plan");
  const MeshTile tile = detail::mesh_region(plan(), merge, region, load(region), scale(), options,
                                            [&](std::int32_t k) { return impl_->region_tree(k); });
  detail::write_tile(impl_->file("tile", region, "bin"), tile);
}

SurfaceMesh TiledRun::join(const SurfaceMeshOptions& options) const {
  require_tiled_meshing(options);
  std::vector<MeshTile> tiles;
  for (std::int32_t k = 0; k < static_cast<std::int32_t>(regions()); ++k)
    tiles.push_back(detail::read_tile(impl_->need(impl_->file("tile", k, "bin"), "every region's mesh")));
  return detail::join_region_tiles(std::move(tiles), impl_->merge_record(), origin(), options,
                                   [&] { return impl_->merged_tree(); });
}

WrittenMesh TiledRun::write_mesh(const std::filesystem::path& file, const SurfaceMeshOptions& options,
                                 const PlyWriteOptions& ply) const {
  require_tiled_meshing(options);
  check_output(file);
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  WrittenMesh out;
  out.file = file;
  if (extension != ".ply" || !ply.binary || ply.double_precision || options.decimation.enabled()) {
    const SurfaceMesh mesh = join(options);
    write_triangle_mesh(file, mesh.mesh, ply);
    out.vertices = static_cast<std::size_t>(mesh.mesh.vertices.rows());
    out.triangles = static_cast<std::size_t>(mesh.mesh.triangles.rows());
    out.blended_nodes = mesh.blended_nodes;
    out.grid = mesh.grid;
    out.coarsening = mesh.coarsening;
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
    detail::keep_tile_colors(t, options);
    if (!counted[static_cast<std::size_t>(k)]++) detail::add_tile_reports(out.grid, out.coarsening, t);
    return t;
  };
  const JoinedMesh joined = join_tiles_to_ply(tile, plan(), options.trim, file, surface ? &*surface : nullptr);
  out.vertices = joined.vertices;
  out.triangles = joined.triangles;
  out.removed_components = joined.removed_components;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace clustersurf
