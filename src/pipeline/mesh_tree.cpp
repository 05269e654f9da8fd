// The mesh step of the pipeline: grid, mesher, trim and colors for a tree.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>
#include <clustersurf/mesh/vertex_refit.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>

#include "mesh/mesh_closing.hpp"
#include "mesh/mesh_untangle.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>

namespace clustersurf {

const char* to_string(MeshColoring coloring) {
  switch (coloring) {
    case MeshColoring::None:
      return "none";
    case MeshColoring::ByNode:
      return "leaf";
    case MeshColoring::ByDistance:
      return "distance";
    case MeshColoring::FromInput:
      return "input";
    case MeshColoring::FromIntensity:
      return "intensity";
  }
  return "unknown";
}

MeshColoring parse_mesh_coloring(std::string_view text) {
  for (MeshColoring c : {MeshColoring::None, MeshColoring::ByNode, MeshColoring::ByDistance, MeshColoring::FromInput,
                         MeshColoring::FromIntensity})
    if (text == to_string(c)) return c;
  throw OptionError("color must be none, leaf, distance, input or intensity, not \"" + std::string(text) + "\"");
}

namespace {

/// coarsen_mesh() of `mesh` on the lattice extract_mesh() walked (its cell, anchored at the
/// tree's box), within the share options.coarsening asks of the tree's error scale.
TriangleMesh coarsened(const TriangleMesh& mesh, const ClusterTree& tree, const SurfaceMeshOptions& options,
                       SurfaceMesh& out) {
  return coarsen_mesh(mesh, tree.bbox.min, out.grid.voxel_size, coarsening_scale(tree), options.coarsening,
                      &out.coarsening);
}

/// The closed mesh of `surface`: meshed through its ClosedSurface, the vertices the data does
/// not support marked "filled", fragments the data does not support dropped (the trim's vote,
/// no triangle cut), and filled patches wider than the limit opened again.
TriangleMesh closed_mesh(const ImplicitSurface& surface, const SurfaceMeshOptions& options, const MeshOptions& grid,
                         const KdTree* data, SurfaceMesh& out, const ProgressCallback& progress) {
  if (!(options.closing.max_hole_size >= 0) || !std::isfinite(options.closing.max_hole_size))
    throw OptionError("the largest hole to fill must be a finite size >= 0 (0: fill every hole)");
  const ClosedSurface closed(surface, options.closing, grid.min_weight, progress);
  TriangleMesh mesh = extract_mesh(closed, grid, &out.grid, progress);
  TrimOptions reach = options.trim;
  reach.typical_spread = typical_spread(surface.tree());
  mesh.attributes.push_back({"filled", detail::filled_vertices(mesh, closed, data, reach)});
  if (data != nullptr) {
    TrimOptions debris = options.trim;
    debris.spread_factor = 0;  // keep every triangle: the holes are closed on purpose
    debris.close_pinholes = false;
    mesh = trim_to_points(mesh, *data, debris, &out.trim);
  }
  mesh = coarsened(mesh, surface.tree(), options, out);
  if (options.closing.max_hole_size > 0)
    out.closing.opened_holes =
        detail::open_large_fills(mesh, mesh.attributes.back().values, options.closing.max_hole_size);
  if (data != nullptr) {
    const Eigen::VectorXf& filled = mesh.attributes.back().values;
    out.refit = refit_vertices(mesh, *data, surface, options.refit,
                               std::span<const float>(filled.data(), static_cast<std::size_t>(filled.size())));
  }
  // A closed mesh is for solids and printers: no triangle may pass through another.
  detail::UntangleReport untangled = detail::untangle(mesh);
  out.closing.untangled_intersections = untangled.intersections_before - untangled.remaining.count;
  const Eigen::VectorXf& filled = mesh.attributes.back().values;
  out.closing.closed = true;
  out.closing.filled_vertices = static_cast<std::size_t>((filled.array() > 0).count());
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    out.closing.filled_triangles +=
        filled(mesh.triangles(t, 0)) > 0 || filled(mesh.triangles(t, 1)) > 0 || filled(mesh.triangles(t, 2)) > 0;
  out.closing.fill_cell = closed.cell_size();
  out.closing.fill_nodes = closed.filled_nodes();
  untangled.remaining.pairs.resize(std::min(untangled.remaining.pairs.size(), MeshCheckOptions{}.max_pairs));
  out.closing.check = check_mesh(mesh, std::move(untangled.remaining));
  return mesh;
}

/// colors_from_points() of `colors` (one per input point) over the rows the tree clusters (its
/// outliers' colors left out).
Colors clustered_colors(const TriangleMesh& mesh, const ClusterTree& tree, const CloudIndex& input,
                        const Colors& colors) {
  const CloudIndex::Subset data = clustered_subset(input, tree);
  if (data.positions.rows() == colors.rows()) return colors_from_points(mesh, data.index, colors);
  const std::vector<std::uint32_t> rows = clustered_rows(tree);
  return colors_from_points(mesh, data.index, colors(rows, Eigen::all));
}

/// The input's "intensity" attribute, or null.
const PointAttribute* intensity_of(const PointCloud& cloud) {
  for (const PointAttribute& a : cloud.attributes)
    if (a.name == "intensity" && a.values.size() == cloud.size()) return &a;
  return nullptr;
}

}  // namespace

SurfaceMesh mesh_tree(const ClusterTree& tree, const SurfaceMeshOptions& options, const CloudIndex* input,
                      const ProgressCallback& progress) {
  if (options.coloring == MeshColoring::ByDistance && input == nullptr)
    throw OptionError("distance colors need the tree's input points");
  if (options.coloring == MeshColoring::ByDistance &&
      (!(options.distance_scale > 0) || !std::isfinite(options.distance_scale)))
    throw OptionError("the distance color scale must be positive");
  if (input != nullptr) require_tree_input(tree, input->cloud().positions);

  const ImplicitSurface surface(tree, level_of_detail(tree, options.lod_depth, options.lod_error));
  MeshOptions grid = options.grid;
  // The automatic cell: the grid's, unless the options give one, and the fill band's. Where the
  // points coincide (no spacing), only an automatic grid needs it (and refuses).
  const bool automatic_grid = options.auto_resolution && !grid.voxel_size;
  std::optional<double> automatic;
  if (tree.point_spacing > 0)
    automatic = auto_cell_size(surface);
  else if (input != nullptr && (automatic_grid || input->median_spacing() > 0))
    automatic = auto_cell_size(surface, input->median_spacing());
  if (automatic_grid) grid.voxel_size = automatic;
  if (!grid.fill_cell) grid.fill_cell = automatic;
  const auto start = std::chrono::steady_clock::now();
  SurfaceMesh out;
  out.blended_nodes = surface.cut().size();
  if (options.closing.enabled) {
    out.mesh = closed_mesh(surface, options, grid, input == nullptr ? nullptr : &clustered_subset(*input, tree).index,
                           out, progress);
  } else {
    out.mesh = extract_mesh(surface, grid, &out.grid, progress);
    // Trimmed to the clustered points: an outlier next to an extrapolated flap must not keep it.
    const std::optional<CloudIndex::Subset> data =
        input != nullptr ? std::optional(clustered_subset(*input, tree)) : std::nullopt;
    if (data) {
      const bool spread_known = data->spread_neighbors == options.trim.neighbors;
      TrimOptions trim = options.trim;
      trim.typical_spread = typical_spread(tree);
      out.mesh = trim_to_points(out.mesh, data->index, trim, &out.trim,
                                spread_known ? data->spread : std::span<const double>());
    }
    out.mesh = coarsened(out.mesh, tree, options, out);
    if (data) out.refit = refit_vertices(out.mesh, data->index, surface, options.refit);
  }
  if (options.decimation.enabled()) {
    out.mesh = decimate(out.mesh, options.decimation, &out.decimation);
    if (out.closing.closed) out.closing.check = check_mesh(out.mesh);  // of the mesh delivered
  }
  if (options.coloring == MeshColoring::ByNode) out.mesh.colors = colors_by_node(out.mesh, surface);
  if (options.coloring == MeshColoring::ByDistance)
    out.mesh.colors = colors_by_distance(out.mesh, input->points(), options.distance_scale * tree.bbox.diagonal());
  if (options.coloring == MeshColoring::FromInput && input != nullptr && input->cloud().has_colors())
    out.mesh.colors = clustered_colors(out.mesh, tree, *input, input->cloud().colors);
  if (options.coloring == MeshColoring::FromIntensity && input != nullptr)
    if (const PointAttribute* intensity = intensity_of(input->cloud()))
      out.mesh.colors = clustered_colors(out.mesh, tree, *input, intensity_grey(intensity->values));
  out.mesh.origin = tree.origin;
  out.mesh.up = tree.up;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace clustersurf
