#pragma once
// Triangle mesh of the zero set of an ImplicitSurface (or of its closed extension).

#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/core/progress.hpp>
#include <clustersurf/surface/closed_surface.hpp>
#include <clustersurf/surface/implicit_surface.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

namespace clustersurf {

/// cell_size_for_points()'s default: cells this many median point spacings wide. Finer cells add
/// vertices faster than accuracy: the leaves' blend, not the grid, bounds the error there; coarser
/// cells lose relief.
inline constexpr double kSpacingsPerCell = 2.0;

/// Options of extract_mesh().
struct MeshOptions {
  /// Grid cells along the longest side of the tree's bounding box (ignored with voxel_size).
  std::uint32_t resolution = 256;
  /// Grid cell size in the input's units; overrides resolution.
  std::optional<double> voxel_size;
  /// Newton steps projecting each vertex onto f = 0 along ∇f.
  int newton_steps = 2;
  /// Grid points whose total blending weight Σwᵢ is at most this count as undefined, so the
  /// mesh stops where only the outer rim of a support reaches (see kMinWeight).
  double min_weight = kMinWeight;
  /// Grid points where f is undefined (or below min_weight) take the value of the blend with
  /// every support radius grown by this many cells (ImplicitSurface::with_margin), and
  /// vertices whose projection fails there are projected onto that blend's zero set. Fine
  /// leaves have supports a few cells wide: a cell their data crosses can have a corner
  /// (up to √3 cells off the surface) outside every support, and without this fill the cell
  /// is left out as a pinhole. Only a band this wide beyond the supports is filled, so real
  /// gaps in the data stay holes (and trim_to_points() cuts the band back to the data).
  /// 0 = no fill.
  double fill_cells = 2;
  /// The cell the fill band is counted in when it is larger than the grid's (unset: the grid's
  /// cell). The pipeline sets the automatic cell (auto_cell_size()), so that a grid finer than
  /// the automatic one meets the same gaps between the supports and bridges them as it does,
  /// instead of opening them as holes.
  std::optional<double> fill_cell;
  /// The most memory, in bytes, the walk may take by its estimate (estimate_mesh()) before it
  /// starts; 0: the physical memory the machine has free. Over it, extract_mesh() throws
  /// OptionError instead of starting a walk the machine cannot hold.
  std::uint64_t memory_limit = 0;
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<MeshOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("resolution", o.resolution);
  f("voxel_size", o.voxel_size);
  f("newton_steps", o.newton_steps);
  f("min_weight", o.min_weight);
  f("fill_cells", o.fill_cells);
  f("fill_cell", o.fill_cell);
  f("memory_limit", o.memory_limit);
}

/// How far beyond the supports grid corners are filled (MeshOptions::fill_cells of the larger of
/// the grid's cell `h` and MeshOptions::fill_cell).
inline double fill_band(const MeshOptions& options, double h) {
  return std::max(options.fill_cells, 0.0) * std::max(h, options.fill_cell.value_or(h));
}

/// Bytes a walk takes per surface cell, all its stages together (the walk's grids, the
/// polygons, the mesh with its normals): about 420 on a detailed statue sampled at 1 M points
/// and 385 on a clumped sphere, with a margin.
inline constexpr double kMeshBytesPerSurfaceCell = 450;

/// What a walk of extract_mesh() will cost, estimated from the blended proxies before any cell is
/// visited: the surface they cover (each blended cluster a square patch whose diagonal is its
/// extent, extent² / 2, as clusters are nearly flat at their own scale; times the square of how
/// far its support grew beyond alpha × extent to hold its N_min points, the gap it blends
/// across) in cells.
struct MeshEstimate {
  double area = 0;           ///< surface covered by the blended clusters
  double surface_cells = 0;  ///< area / cell size²
  double bytes = 0;          ///< surface_cells × kMeshBytesPerSurfaceCell
};

/// estimate_mesh() of `surface` at cell size `cell_size` (> 0).
MeshEstimate estimate_mesh(const ImplicitSurface& surface, double cell_size);

/// What extract_mesh() visited.
struct MeshReport {
  double voxel_size = 0;
  std::size_t evaluated_corners = 0;  ///< grid points where f was evaluated
  std::size_t surface_cells = 0;      ///< cells crossed by f = 0 with f defined at all corners
};

/// Meshes f = 0 on a sparse grid that follows the surface from seeds on every blended proxy:
/// only cells crossed by the surface (and their corners) are visited, so the cost follows the
/// surface area. Cells with a corner where f is undefined (or below min_weight), beyond the
/// fill band, are not meshed, so missing data gives a hole with a boundary, never a wall. Polygons come from OpenVDB's
/// volumeToMesh (manifold, one or more vertices per cell); vertices are then moved onto f = 0 by Newton steps along ∇f
/// and get ∇f as normal; quads are split along their shorter diagonal; degenerate triangles
/// and unused vertices are removed. Triangles face outward (towards f > 0). Deterministic.
/// Throws OptionError for invalid options, Cancelled when `progress` says stop.
TriangleMesh extract_mesh(const ImplicitSurface& surface, const MeshOptions& options = {}, MeshReport* report = nullptr,
                          const ProgressCallback& progress = {});
/// The same walk on a closed surface's F (ClosedSurface::value()): identical where the blend is
/// above the closed surface's own confidence floor (`options.min_weight` and `fill_cells` do
/// not apply), the fill, faded in from f, elsewhere (vertices there keep the polygonizer's
/// position and take F's gradient as normal), so the mesh is closed: no cell is left out for an
/// undefined corner.
TriangleMesh extract_mesh(const ClosedSurface& closed, const MeshOptions& options = {}, MeshReport* report = nullptr,
                          const ProgressCallback& progress = {});

/// A mesh grid cell size matched to how densely the input samples the surface:
/// `spacing_factor` times its median point spacing (PointSpacing::median, which trees store as
/// ClusterTree::point_spacing). A grid much finer than the samples adds triangles, not
/// accuracy; a coarser one loses the detail the leaves fit. Throws OptionError when the
/// spacing is 0 (most points coincide).
double cell_size_for_spacing(double median_spacing, double spacing_factor = kSpacingsPerCell);

/// A grid of cell size `cell_size` visits at most this many surface cells per clustered point
/// when its size is automatic: a uniform sample at the default two spacings per cell gives
/// about one (its median spacing is half the side of the area per point); where the points
/// come in clumps (multi-view stereo) the median spacing is the clumps', and a grid that fine
/// would cost far more than the points can resolve.
inline constexpr double kMaxSurfaceCellsPerPoint = 4;

/// The automatic grid resolves a curved part with cells at most this share of its radius of
/// curvature: a tube of radius r gets four cells across (a coarser lattice cuts a tube about
/// two cells wide into fins and gaps).
inline constexpr double kCellsPerCurvatureRadius = 2;
/// The share of the blended leaves' area (by their extents) that may be curved beyond what the
/// automatic cell resolves: the cell follows the curvature of all but the most curved tenth of
/// the surface, so a few leaves bent by noise or strays do not refine the whole grid.
inline constexpr double kUnresolvedCurvedShare = 0.1;
/// The automatic cell is never finer than this many median point spacings: the leaves hold no
/// detail finer than the samples.
inline constexpr double kFinestSpacingsPerCell = 1;

/// The automatic cell size of `surface`: cell_size_for_spacing() of its tree's point spacing,
/// made finer where the blended leaves are curved (their quadratics' largest curvature κ asks
/// for at most 1 / (kCellsPerCurvatureRadius κ), for all but kUnresolvedCurvedShare of their
/// area; never below kFinestSpacingsPerCell spacings), then coarsened until estimate_mesh()
/// finds at most kMaxSurfaceCellsPerPoint surface cells per clustered point. Throws OptionError
/// when the tree has no spacing.
double auto_cell_size(const ImplicitSurface& surface);
/// auto_cell_size() for the median spacing `point_spacing` of the tree's input (a version-1
/// tree file stores none).
double auto_cell_size(const ImplicitSurface& surface, double point_spacing);
/// auto_cell_size() of the tree's leaves, without building its surface (a merged tree's at the
/// merge of a tiled run).
double auto_cell_size(const ClusterTree& tree);

/// cell_size_for_spacing() of `cloud`'s median spacing (compute_stats()).
double cell_size_for_points(const PointCloud& cloud, double spacing_factor = kSpacingsPerCell);

/// A component with less than this share of a mesh's area is a loose fragment
/// (MeshTopology::small_components): debris beside the surface, not a part of it.
inline constexpr double kSmallComponentShare = 0.001;

/// Edge-manifoldness, boundary and Euler characteristic of a mesh.
struct MeshTopology {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t edges = 0;
  std::size_t boundary_edges = 0;      ///< edges with one triangle
  std::size_t non_manifold_edges = 0;  ///< edges with more than two triangles
  std::size_t inconsistent_edges = 0;  ///< interior edges traversed twice in the same direction
  long euler_characteristic = 0;       ///< V − E + F
  std::size_t components = 0;          ///< connected components (triangles sharing a vertex)
  /// Components with less than kSmallComponentShare of the area (loose fragments).
  std::size_t small_components = 0;
  double signed_volume = 0;  ///< > 0 for closed outward-facing meshes
  double area = 0;           ///< total triangle area
  /// Total length of the boundary edges. Divided by √area it does not depend on the mesh's
  /// scale: how much rim a surface has (0 for a closed one). A finer grid makes a ragged rim
  /// longer, so compare meshes of similar resolution.
  double boundary_length = 0;
};

/// Edge and component counts of `mesh`, its area, boundary length and signed volume
/// (OptionError when a triangle refers to a vertex that does not exist).
MeshTopology mesh_topology(const TriangleMesh& mesh);

/// MeshTopology::boundary_length over the square root of the area (0 for a mesh without area).
inline double boundary_per_sqrt_area(const MeshTopology& t) noexcept {
  return t.area > 0 ? t.boundary_length / std::sqrt(t.area) : 0.0;
}

/// Closed and edge-manifold: every edge has exactly two triangles (and there is at least one).
inline bool is_watertight(const MeshTopology& t) noexcept {
  return t.triangles > 0 && t.boundary_edges == 0 && t.non_manifold_edges == 0;
}

}  // namespace clustersurf
