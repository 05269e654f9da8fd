#pragma once
// The pipeline in one call: a point cloud becomes an oriented cluster tree and, on request, a
// trimmed (and colored) mesh of its surface; a loaded tree is meshed the same way. The CLI and
// the Python module call these and only map their arguments to the options.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/progress.hpp>
#include <clustersurf/mesh/mesh_check.hpp>
#include <clustersurf/mesh/mesh_coarsening.hpp>
#include <clustersurf/mesh/mesh_decimation.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/mesh/mesh_trim.hpp>
#include <clustersurf/mesh/vertex_refit.hpp>
#include <clustersurf/spatial/cloud_index.hpp>
#include <clustersurf/spatial/scan_registration.hpp>
#include <clustersurf/surface/implicit_surface.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace clustersurf {

/// How mesh_tree() colors the vertices.
enum class MeshColoring : std::uint8_t {
  None = 0,
  ByNode = 1,      ///< colors_by_node(): the blended node of largest weight
  ByDistance = 2,  ///< colors_by_distance() to the input points (needs them)
  /// colors_from_points() of the clustered input points when they have colors (a scan's RGB);
  /// no colors when the input has none or is not given.
  FromInput = 3,
  /// The same from the input's "intensity" attribute as grey (intensity_grey()); no colors when
  /// it has none or is not given.
  FromIntensity = 4,
};

/// "none", "leaf", "distance", "input" or "intensity" (the words the front ends take).
const char* to_string(MeshColoring coloring);
/// The coloring named by to_string(). Throws OptionError otherwise.
MeshColoring parse_mesh_coloring(std::string_view text);

/// Options of mesh_tree(); the defaults are those of `clustersurf mesh`.
struct SurfaceMeshOptions {
  /// Blend the cut at this depth instead of the leaves (level_of_detail()).
  std::optional<std::uint32_t> lod_depth;
  /// Blend the shallowest nodes whose error is at most this fraction of the tree's diagonal.
  std::optional<double> lod_error;
  /// The grid and the mesher; grid.voxel_size, when set, overrides the resolution.
  MeshOptions grid;
  /// Cells kSpacingsPerCell median point spacings wide (the tree's ClusterTree::point_spacing,
  /// else the given points'); with neither (a version-1 tree without its points), or off,
  /// grid.resolution cells along the longest side.
  bool auto_resolution = true;
  /// Applied when the input points are given.
  TrimOptions trim;
  /// The trimmed mesh's flat blocks merged into fewer vertices (coarsen_mesh(), on the mesh's
  /// lattice, within a share of the tree's coarsening_scale()), before the refit.
  CoarseningOptions coarsening;
  /// The trimmed mesh's vertices moved onto local fits of the input points, as far as the
  /// noise lets them (refit_vertices()); applied when the input points are given.
  VertexRefitOptions refit;
  /// A closed mesh (off by default): the holes filled from the harmonic fill of a
  /// ClosedSurface, the trim then only marking what the data does not reach (the "filled"
  /// vertex attribute) and dropping unsupported fragments.
  ClosingOptions closing;
  /// Fewer triangles after the trim (off by default).
  DecimationOptions decimation;
  MeshColoring coloring = MeshColoring::FromInput;
  /// ByDistance: the distance drawn full red, as a fraction of the tree's diagonal.
  double distance_scale = 0.005;
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<SurfaceMeshOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("lod_depth", o.lod_depth);
  f("lod_error", o.lod_error);
  f("grid", o.grid);
  f("auto_resolution", o.auto_resolution);
  f("trim", o.trim);
  f("coarsening", o.coarsening);
  f("refit", o.refit);
  f("closing", o.closing);
  f("decimation", o.decimation);
  f("coloring", o.coloring);
  f("distance_scale", o.distance_scale);
}

/// What closing the mesh did (SurfaceMeshOptions::closing).
struct ClosingReport {
  bool closed = false;                      ///< the mesh was closed (the option was on)
  std::size_t filled_vertices = 0;          ///< vertices marked "filled": invented, not fitted
  std::size_t filled_triangles = 0;         ///< triangles with a filled vertex
  std::size_t opened_holes = 0;             ///< filled patches wider than max_hole_size, left open
  std::size_t untangled_intersections = 0;  ///< self-intersecting triangle pairs smoothed away
  /// Print readiness of the closed mesh (check_mesh(): edges, genus, volume, self-intersections
  /// left, 0 unless the smoothing gave up).
  MeshCheck check;
  double fill_cell = 0;        ///< the fill grid's cell size
  std::size_t fill_nodes = 0;  ///< grid nodes the fill solved for
};

/// A mesh of a tree's surface and what made it.
struct SurfaceMesh {
  TriangleMesh mesh;
  MeshReport grid;
  TrimReport trim;
  CoarseningReport coarsening;
  VertexRefitReport refit;
  DecimationReport decimation;
  ClosingReport closing;
  std::size_t blended_nodes = 0;
  double seconds = 0;  ///< wall time of the mesh step
};

/// The report of `mesh` as one JSON object, the same for every front end: mesh_topology_json()
/// of its `topology`, then blended_nodes, the grid's voxel_size, surface_cells and evaluated_corners, the trim's
/// trimmed_triangles, removed_components and closed_pinholes, the coarsening's
/// coarsened_from_triangles and coarsening_tolerance, the refit's refitted_vertices and
/// refit_mean_move and refit_mean_chord_offset, the closing's filled_vertices, filled_triangles and opened_holes, the
/// decimation's decimated_from_triangles and decimation_deviation, mesh_seconds and, for a
/// closed mesh, check (mesh_check_json()).
std::string surface_mesh_json(const SurfaceMesh& mesh, const MeshTopology& topology);
/// surface_mesh_json() with the topology measured here (mesh_topology()).
std::string surface_mesh_json(const SurfaceMesh& mesh);

/// Meshes the tree's surface f = 0 (extract_mesh()), trims it to the clustered input points
/// (trim_to_points()), decimates it on request (decimate()) and colors it; the mesh carries the
/// tree's origin. `input`: the tree's input cloud, indexed, or null (no
/// trim; distance colors then throw OptionError). Throws OptionError when `input` is not the
/// tree's input (require_tree_input()) or an option is invalid; Cancelled when `progress` says
/// stop.
SurfaceMesh mesh_tree(const ClusterTree& tree, const SurfaceMeshOptions& options = {},
                      const CloudIndex* input = nullptr, const ProgressCallback& progress = {});

/// Options of reconstruct(); the defaults are those of `clustersurf reconstruct --mesh`.
struct ReconstructOptions {
  BuildOptions build;
  /// Mesh the surface too (with `meshing`, the input points trimming it).
  bool mesh = true;
  SurfaceMeshOptions meshing;
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<ReconstructOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("build", o.build);
  f("mesh", o.mesh);
  f("meshing", o.meshing);
}

/// What reconstruct() made.
struct Reconstruction {
  ClusterTree tree;  ///< built and oriented
  OrientationReport orientation;
  /// The scans' registration error where the input says which scan saw each point
  /// (measure_registration(); no overlaps otherwise).
  ScanRegistration registration;
  double build_seconds = 0;         ///< wall time of the build and the orientation
  std::optional<SurfaceMesh> mesh;  ///< when ReconstructOptions::mesh
};

/// Throws InputError unless `cloud` spans a surface: its points (if any) neither all coincide
/// nor all lie on one line (judged about the centroid, so a cloud far from the origin is judged as one
/// near it).
void require_surface_extent(const PointCloud& cloud);

/// The whole pipeline: require_surface_extent(), build_cluster_tree(), orient_tree() (by the
/// input normals unless options.build.use_normals is off), measure_registration() of a cloud
/// whose points name their scans, and on request mesh_tree() with the cloud, all sharing one
/// CloudIndex. Deterministic for any thread count. Throws InputError,
/// OptionError, Cancelled.
Reconstruction reconstruct(const PointCloud& cloud, const ReconstructOptions& options = {},
                           const ProgressCallback& progress = {});

}  // namespace clustersurf
