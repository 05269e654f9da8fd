#pragma once
// The regions of a cloud (regions.hpp) meshed as tiles of one lattice: tiles cut from one global
// grid evaluate the same f, so they meet without seams (docs/architecture.md, "Regions and
// tiles"); and the whole pipeline run region by region in memory.

#include <clustersurf/mesh/mesh_coarsening.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/mesh/mesh_trim.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/regions/regions.hpp>
#include <clustersurf/surface/implicit_surface.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <vector>

namespace clustersurf {

/// The regions whose leaves mesh_tile() of region `region_index` may meet, on the lattice of
/// grid.voxel_size (required) with its fill band: those whose cell, grown by their reach and
/// the band, meets the tile's cells or the supports that seed its walk. Ascending.
std::vector<std::int32_t> tile_regions(const RegionPlan& plan, const RegionMerge& merge, std::int32_t region_index,
                                       const MeshOptions& grid);

/// One tile of a tiled mesh: the triangles of the global lattice's f = 0 whose centroid lies in
/// the tile's region, trimmed to the region's points, their flat blocks merged, with the votes of
/// the region's own points for their nearest vertex (the trim's fragment test is decided by
/// join_tiles() on the whole mesh). Vertices are exactly those of the neighbouring tiles where
/// they meet.
struct MeshTile {
  std::int32_t region = -1;
  TriangleMesh mesh;  ///< its "votes" attribute: own points nearest to each vertex
  MeshReport grid;
  /// Of the triangles the region owns: their count before and after the merges, the blocks
  /// merged and the tolerance.
  CoarseningReport coarsening;
};

/// Cells of lattice a tile meshes beyond its region (mesh_tile()): a triangle whose centroid
/// lies in the region comes from cells within two of it (a quad spans the two cells on each side
/// of its edge, and the projection moves a vertex at most one cell), whose corner values every
/// tile that visits them computes alike.
inline constexpr double kTileMarginCells = 4;

/// Cells of lattice from another region's cell within which no block of a tile merges
/// (mesh_tile()): the refit of a vertex on a tile border reads the mesh about four edges around
/// it (the moves over two rings of each neighbour whose move may turn one of its triangles),
/// and a merge's fan reaches an edge beyond its block, so both tiles hold the lattice's
/// triangles wherever a vertex they share looks.
inline constexpr double kTileFixedCells = 16;

/// Per vertex of `mesh`, 1 where it lies within `distance` of the cell of a region other than
/// the one holding it (RegionPlan::region_of()), else 0.
Eigen::VectorXf near_other_regions(const TriangleMesh& mesh, const RegionPlan& plan, double distance);

/// The tile of region `region_index` of `surface` (of a merged tree) on the lattice of cell
/// size grid.voxel_size (required) anchored at the tree's box: the lattice is meshed over the
/// region's cell and a margin of cells around it, seeded on the blended proxies and on the
/// region's points, and trimmed with meshing.trim to the region's points but its outliers
/// (without the fragment test, which join_tiles() decides, and without closing pinholes); its
/// flat blocks merged with meshing.coarsening as mesh_tree() merges them, but for the vertices
/// within kTileFixedCells of another region's cell (near_other_regions()), which stay; its
/// vertices refitted to those points with meshing.refit, as mesh_tree() does; colored from
/// those points (colors_from_points()) when meshing.coloring asks for the input's colors and
/// they have them. Deterministic. Throws OptionError for invalid options.
MeshTile mesh_tile(const ImplicitSurface& surface, const RegionPlan& plan, std::int32_t region_index,
                   const RegionCloud& region, const MeshOptions& grid, const SurfaceMeshOptions& meshing = {},
                   const ProgressCallback& progress = {});

/// The tiles as one mesh: vertices at the same position welded, then components on which fewer
/// than trim.min_component_points votes fall dropped (the best-supported always stays), as
/// trim_to_points() does. The result does not depend on the order of the tiles.
TriangleMesh join_tiles(std::span<const MeshTile> tiles, const TrimOptions& trim = {});

/// Where reconstruct_regions() reads its regions (reconstruct_tiled(): a cloud in memory).
/// A run on disk reads its region files instead (TiledRun::load()).
class RegionSource {
 public:
  virtual ~RegionSource() = default;
  /// The points of region r of the plan, own first, then its halo. Called once per pass.
  virtual RegionCloud load(std::int32_t region) const = 0;
};

/// The pipeline over regions in memory, by the stages of a run on disk (TiledRun's tasks, the
/// same functions): every region surveyed (survey_region(), combine_surveys()), its outliers
/// marked and its subtree built (build_region_tree()), the subtrees merged
/// (merge_region_trees()) and, on request, meshed tile by tile (mesh_tile() on tile_tree(),
/// join_tiles()), decimated and colored as mesh_tree() does: the tree and the mesh of a
/// TiledRun of the same plan, to the byte. Holds one region's points at a time and every
/// region tree. Throws OptionError for what tiles cannot do: levels of detail, closing,
/// distance colors.
Reconstruction reconstruct_regions(const RegionPlan& plan, const RegionSource& source,
                                   const ReconstructOptions& options = {}, const ProgressCallback& progress = {});

/// What join_tiles_to_ply() wrote.
struct JoinedMesh {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t removed_components = 0;  ///< components the votes did not support
};

/// join_tiles() of the tiles tile(0), ..., tile(count − 1) (tile(k): region k's), written to
/// a binary PLY file tile by tile, with colors by node from `colors` when given, else the
/// tiles' own colors when they have them: the bytes write_ply() writes of join_tiles()'s mesh,
/// never the whole mesh in memory. Each tile is asked for four times; memory holds one tile, 13
/// bytes per vertex and the vertices near region borders (welded by position). Atomic. Throws OptionError for tiles
/// that do not match the plan.
JoinedMesh join_tiles_to_ply(const std::function<MeshTile(std::int32_t)>& tile, const RegionPlan& plan,
                             const TrimOptions& trim, const std::filesystem::path& file,
                             const ImplicitSurface* colors = nullptr);

/// Throws OptionError for what a tiled mesh cannot do: levels of detail, closing, distance and
/// intensity colors, closing pinholes.
void require_tiled_meshing(const SurfaceMeshOptions& options);

/// The lattice cell of a tiled mesh of `tree`: options.grid's voxel size, else the tree's
/// (auto resolution, auto_cell_size() of its leaves), else its resolution along the longest side.
double tiled_cell_size(const ClusterTree& tree, const SurfaceMeshOptions& options);
/// The same from the merge record, without the tree: its automatic cell (RegionMerge::auto_cell,
/// which the merge of a tiled run measures on the merged tree), else its spacing's cell
/// (cell_size_for_spacing()), else the resolution along its box's longest side.
double tiled_cell_size(const RegionMerge& merge, const SurfaceMeshOptions& options);

/// reconstruct_regions() of a cloud in memory, split by plan_regions() of an even sample of
/// it (the halo measured in the sample's spacing, scaled to the cloud's density). The same
/// surface as reconstruct() within the difference of the leaves along region borders; one
/// region gives reconstruct()'s tree. Its tree's point-leaf table follows the cloud's rows.
Reconstruction reconstruct_tiled(const PointCloud& cloud, const RegionOptions& regions,
                                 const ReconstructOptions& options = {}, const ProgressCallback& progress = {});

/// An estimate of a cloud's median spacing from an even sample of it: the sample's spacing
/// times √(sample / total) (a surface sampled k times more sparsely has √k times wider spacing).
double spacing_from_sample(const Points& sample, std::uint64_t total_points);

}  // namespace clustersurf
