// The stages of a tiled run (region_stages.hpp).

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>

#include "tiling/region_stages.hpp"

#include <algorithm>
#include <chrono>

namespace clustersurf::detail {

namespace {

/// Marks what a region's build and tile leave out: its outliers, unless kept, and its repeated
/// positions.
void mark_left_out(RegionCloud& points, const CloudScale& scale, const BuildOptions& options) {
  if (options.remove_outliers)
    mark_outliers(points, scale, options.outliers);
  else
    mark_repeated_positions(points);
}

}  // namespace

ClusterTree build_region(RegionCloud points, const RegionPlan& plan, std::int32_t region, const CloudScale& scale,
                         const BuildOptions& options, OrientationReport& oriented) {
  mark_left_out(points, scale, options);
  return build_region_tree(points, plan, region, scale, options, &oriented);
}

OrientationReport combine_orientations(const std::vector<OrientationReport>& oriented,
                                       const std::vector<std::uint8_t>& empty) {
  OrientationReport sum;
  sum.used_normals = sum.used_scanners = true;
  for (std::size_t k = 0; k < oriented.size(); ++k) {
    if (empty[k]) continue;
    sum.used_normals = sum.used_normals && oriented[k].used_normals;
    sum.used_scanners = sum.used_scanners && oriented[k].used_scanners;
    sum.flipped += oriented[k].flipped;
    sum.components += oriented[k].components;
  }
  return sum;
}

bool propagated(const std::vector<OrientationReport>& oriented, const std::vector<std::uint8_t>& empty) {
  for (std::size_t k = 0; k < oriented.size(); ++k)
    if (!empty[k] && !oriented[k].used_normals && !oriented[k].used_scanners) return true;
  return false;
}

MeshTile mesh_region(const RegionPlan& plan, const RegionMerge& merge, std::int32_t region, RegionCloud points,
                     const CloudScale& scale, const ReconstructOptions& options,
                     const std::function<ClusterTree(std::int32_t)>& region_tree) {
  require_tiled_meshing(options.meshing);
  MeshOptions grid = options.meshing.grid;
  grid.voxel_size = tiled_cell_size(merge, options.meshing);
  if (!grid.fill_cell && merge.auto_cell > 0) grid.fill_cell = merge.auto_cell;
  std::vector<ClusterTree> trees(plan.regions());
  for (const std::int32_t k : tile_regions(plan, merge, region, grid))
    trees[static_cast<std::size_t>(k)] = region_tree(k);
  mark_left_out(points, scale, options.build);
  MeshTile tile;
  tile.region = region;
  if (std::none_of(trees.begin(), trees.end(), [](const ClusterTree& t) { return !t.nodes.empty(); })) return tile;
  const ClusterTree tree = tile_tree(plan, std::move(trees), merge);
  return mesh_tile(ImplicitSurface(tree), plan, region, points, grid, options.meshing);
}

double merged_auto_cell(const ClusterTree& merged) {
  return merged.point_spacing > 0 && !merged.nodes.empty() ? auto_cell_size(merged) : 0.0;
}

void keep_tile_colors(MeshTile& tile, const SurfaceMeshOptions& options) {
  if (options.coloring != MeshColoring::FromInput) tile.mesh.colors.resize(0, 3);
}

void add_tile_reports(MeshReport& grid, CoarseningReport& coarsening, const MeshTile& tile) {
  grid.voxel_size = tile.grid.voxel_size;
  grid.evaluated_corners += tile.grid.evaluated_corners;
  grid.surface_cells += tile.grid.surface_cells;
  coarsening.tolerance = std::max(coarsening.tolerance, tile.coarsening.tolerance);
  coarsening.merged_blocks += tile.coarsening.merged_blocks;
  coarsening.triangles_before += tile.coarsening.triangles_before;
  coarsening.triangles_after += tile.coarsening.triangles_after;
}

SurfaceMesh join_region_tiles(std::vector<MeshTile> tiles, const RegionMerge& merge, const Eigen::Vector3d& origin,
                              const SurfaceMeshOptions& options, const std::function<ClusterTree()>& merged_tree) {
  require_tiled_meshing(options);
  const auto start = std::chrono::steady_clock::now();
  SurfaceMesh out;
  for (MeshTile& t : tiles) {
    add_tile_reports(out.grid, out.coarsening, t);
    keep_tile_colors(t, options);
  }
  out.mesh = join_tiles(tiles, options.trim);
  tiles.clear();
  out.blended_nodes = merge.leaves;
  if (options.decimation.enabled()) out.mesh = decimate(out.mesh, options.decimation, &out.decimation);
  if (options.coloring == MeshColoring::ByNode) {
    const ClusterTree tree = merged_tree();  // the colors need every leaf
    out.mesh.colors = colors_by_node(out.mesh, ImplicitSurface(tree));
  }
  out.mesh.origin = origin;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace clustersurf::detail
