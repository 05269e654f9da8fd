// The pipeline over the regions of a plan: survey, build, merge, mesh by tiles.

#include "tiling/tiles.hpp"
#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>

#include "core/progress_reporter.hpp"
#include "tiling/region_stages.hpp"

#include <chrono>
#include <cmath>

namespace clustersurf {

namespace {

/// Regions cut from a cloud in memory.
class CloudRegions final : public RegionSource {
 public:
  CloudRegions(const PointCloud& cloud, const RegionPlan& plan)
      : cloud_(cloud), own_(plan.regions()), halo_(plan.regions()) {
    std::vector<std::int32_t> near;
    for (Eigen::Index i = 0; i < cloud.size(); ++i) {
      const Eigen::Vector3d x = cloud.positions.row(i).transpose();
      own_[static_cast<std::size_t>(plan.region_of(x))].push_back(i);
      plan.halo_regions(x, near);
      for (const std::int32_t r : near) halo_[static_cast<std::size_t>(r)].push_back(i);
    }
  }
  RegionCloud load(std::int32_t region) const override {
    const auto r = static_cast<std::size_t>(region);
    std::vector<Eigen::Index> rows = own_[r];
    rows.insert(rows.end(), halo_[r].begin(), halo_[r].end());
    RegionCloud out;
    out.points = select(cloud_, rows);
    out.own = own_[r].size();
    return out;
  }
  /// The cloud's rows of region r's own points.
  const std::vector<Eigen::Index>& own_rows(std::size_t r) const { return own_[r]; }

 private:
  const PointCloud& cloud_;
  std::vector<std::vector<Eigen::Index>> own_, halo_;
};

}  // namespace

double spacing_from_sample(const Points& sample, std::uint64_t total_points) {
  if (sample.rows() < 2 || total_points == 0) return 0;
  const double spacing = point_spacing(KdTree(sample)).median;
  return spacing * std::sqrt(static_cast<double>(sample.rows()) / static_cast<double>(total_points));
}

void require_tiled_meshing(const SurfaceMeshOptions& meshing) {
  if (meshing.lod_depth || meshing.lod_error)
    throw OptionError("a tiled mesh is of the leaves: levels of detail are not available");
  if (meshing.closing.enabled) throw OptionError("a tiled mesh cannot be closed (watertight) yet");
  if (meshing.coloring == MeshColoring::ByDistance) throw OptionError("a tiled mesh cannot be colored by distance");
  if (meshing.coloring == MeshColoring::FromIntensity)
    throw OptionError("a tiled mesh cannot be colored by intensity yet (the scan's colors can)");
  if (meshing.trim.close_pinholes) throw OptionError("a tiled mesh cannot close pinholes");
}

namespace {

double cell_size(const BoundingBox& bbox, double point_spacing, const SurfaceMeshOptions& options) {
  if (options.grid.voxel_size) return *options.grid.voxel_size;
  if (options.auto_resolution && point_spacing > 0) return cell_size_for_spacing(point_spacing);
  if (options.grid.resolution < 2) throw OptionError("the mesh resolution must be at least 2 cells");
  return bbox.extent().maxCoeff() / options.grid.resolution;
}

}  // namespace

double tiled_cell_size(const ClusterTree& tree, const SurfaceMeshOptions& options) {
  if (!options.grid.voxel_size && options.auto_resolution && tree.point_spacing > 0) return auto_cell_size(tree);
  return cell_size(tree.bbox, tree.point_spacing, options);
}

double tiled_cell_size(const RegionMerge& merge, const SurfaceMeshOptions& options) {
  if (!options.grid.voxel_size && options.auto_resolution && merge.auto_cell > 0) return merge.auto_cell;
  return cell_size(merge.bbox, merge.point_spacing, options);
}

Reconstruction reconstruct_regions(const RegionPlan& plan, const RegionSource& source,
                                   const ReconstructOptions& options, const ProgressCallback& progress) {
  if (options.mesh) require_tiled_meshing(options.meshing);
  const auto start = std::chrono::steady_clock::now();
  const auto n = static_cast<std::int32_t>(plan.regions());
  const auto report = [&](std::string_view stage, std::int32_t done) {
    if (progress && !progress(stage, static_cast<double>(done) / static_cast<double>(n))) throw Cancelled();
  };
  // The stages of a tiled run (detail::build_region, mesh_region, join_region_tiles), their
  // results kept in memory instead of the work directory's files.
  std::vector<RegionSurvey> surveys;
  for (std::int32_t r = 0; r < n; ++r) {
    report("surveying regions", r);
    surveys.push_back(survey_region(source.load(r), plan.points, options.build));
  }
  const CloudScale scale = combine_surveys(surveys);
  std::vector<ClusterTree> trees;
  std::vector<OrientationReport> oriented(plan.regions());
  std::vector<std::uint8_t> empty(plan.regions(), 0);
  for (std::int32_t r = 0; r < n; ++r) {
    report("building regions", r);
    const auto k = static_cast<std::size_t>(r);
    trees.push_back(detail::build_region(source.load(r), plan, r, scale, options.build, oriented[k]));
    empty[k] = trees.back().nodes.empty() ? 1 : 0;
  }
  Reconstruction out;
  out.orientation = detail::combine_orientations(oriented, empty);
  RegionMerge merge;
  out.tree = merge_region_trees(plan, trees, detail::propagated(oriented, empty), merge);
  merge.auto_cell = detail::merged_auto_cell(out.tree);
  out.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!options.mesh) return out;

  const auto mesh_start = std::chrono::steady_clock::now();
  // Each tile's tree is cut from the region trees as built (tile_tree() flips them as the merge did).
  std::vector<MeshTile> tiles;
  for (std::int32_t r = 0; r < n; ++r) {
    report("meshing tiles", r);
    tiles.push_back(detail::mesh_region(plan, merge, r, source.load(r), scale, options,
                                        [&](std::int32_t k) { return trees[static_cast<std::size_t>(k)]; }));
  }
  report("joining tiles", n);
  trees.clear();
  SurfaceMesh mesh =
      detail::join_region_tiles(std::move(tiles), merge, out.tree.origin, options.meshing, [&] { return out.tree; });
  mesh.mesh.up = out.tree.up;
  mesh.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - mesh_start).count();
  out.mesh = std::move(mesh);
  return out;
}

Reconstruction reconstruct_tiled(const PointCloud& cloud, const RegionOptions& regions,
                                 const ReconstructOptions& options, const ProgressCallback& progress) {
  require_surface_extent(cloud);
  if (cloud.empty()) throw OptionError("cannot build a tree from an empty point cloud");
  // An even sample of the cloud places the cuts and measures the halo.
  constexpr Eigen::Index kSample = 200000;
  const Eigen::Index step = std::max<Eigen::Index>(1, cloud.size() / kSample);
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < cloud.size(); i += step) rows.push_back(i);
  const Points sample = cloud.positions(rows, Eigen::all);
  const auto total = static_cast<std::uint64_t>(cloud.size());
  const RegionPlan plan =
      plan_regions(sample, total, bounding_box(cloud.positions), spacing_from_sample(sample, total), regions);
  const CloudRegions source(cloud, plan);
  Reconstruction out = reconstruct_regions(plan, source, options, progress);
  // The point-leaf table in the cloud's row order.
  if (out.tree.point_leaf.size() == static_cast<std::size_t>(cloud.size())) {
    std::vector<std::int32_t> by_row(out.tree.point_leaf.size(), -1);
    std::size_t k = 0;
    for (std::size_t r = 0; r < plan.regions(); ++r)
      for (const Eigen::Index row : source.own_rows(r))
        by_row[static_cast<std::size_t>(row)] = out.tree.point_leaf[k++];
    out.tree.point_leaf = std::move(by_row);
  }
  return out;
}

}  // namespace clustersurf
