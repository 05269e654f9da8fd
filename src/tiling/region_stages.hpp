#pragma once
// The stages of a tiled run, once: what a region's build, a region's tile and the join do with
// their inputs. Every tiled path runs them: the work directory's tasks (TiledRun, so the
// out-of-core run and Dask) and the regions of a cloud in memory (reconstruct_regions()); only
// where their inputs and results are kept differs.

#include "tiling/tiles.hpp"

#include <functional>
#include <vector>

namespace clustersurf::detail {

/// Region `region`'s tree at the cloud's scale, its outliers marked first when the options
/// remove them; `oriented` gets how its proxies were oriented.
ClusterTree build_region(RegionCloud points, const RegionPlan& plan, std::int32_t region, const CloudScale& scale,
                         const BuildOptions& options, OrientationReport& oriented);

/// The run's orientation from its regions' (`oriented`, the empty regions' left out): normals
/// or scanners used where every region used them, flips and components summed.
OrientationReport combine_orientations(const std::vector<OrientationReport>& oriented,
                                       const std::vector<std::uint8_t>& empty);

/// Whether some region was oriented by propagation (the merge then makes the regions agree).
bool propagated(const std::vector<OrientationReport>& oriented, const std::vector<std::uint8_t>& empty);

/// The merged tree's automatic lattice cell (auto_cell_size(), coarsened for clumps as in
/// core), for RegionMerge::auto_cell; 0 for a tree without a point spacing.
double merged_auto_cell(const ClusterTree& merged);

/// The tile of region `region` on the merged tree's lattice: meshed from the region trees its
/// leaves may meet (tile_regions(); `region_tree(k)` gives tree k), trimmed to its points, their
/// outliers marked as the build marked them. An empty tile where no leaf reaches it.
MeshTile mesh_region(const RegionPlan& plan, const RegionMerge& merge, std::int32_t region, RegionCloud points,
                     const CloudScale& scale, const ReconstructOptions& options,
                     const std::function<ClusterTree(std::int32_t)>& region_tree);

/// Drops a tile's own colors (its points', made by the mesh task) unless `options` color the
/// mesh from the input: a join with other colors, or none, has no use for them.
void keep_tile_colors(MeshTile& tile, const SurfaceMeshOptions& options);

/// The tile's lattice figures summed into `grid`, and its merges into `coarsening`.
void add_tile_reports(MeshReport& grid, CoarseningReport& coarsening, const MeshTile& tile);

/// The tiles welded into one mesh, then decimated and colored as `options` say (`merged_tree()`
/// for colors by node); with the tiles' own colors only for colors from the input.
SurfaceMesh join_region_tiles(std::vector<MeshTile> tiles, const RegionMerge& merge, const Eigen::Vector3d& origin,
                              const SurfaceMeshOptions& options, const std::function<ClusterTree()>& merged_tree);

}  // namespace clustersurf::detail
