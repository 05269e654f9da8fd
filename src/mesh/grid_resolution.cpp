// The mesh grid matched to the sampling density of the input points, and what a walk of it costs.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>

#include "mesh/clipped_extraction.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <span>
#include <string>

namespace clustersurf {

double cell_size_for_spacing(double median_spacing, double spacing_factor) {
  if (!(spacing_factor > 0) || !std::isfinite(spacing_factor))
    throw OptionError("the grid's spacing factor must be positive");
  if (!(median_spacing > 0) || !std::isfinite(median_spacing))
    throw OptionError("cannot match the mesh grid to the points: most of them coincide (median spacing 0)");
  return spacing_factor * median_spacing;
}

double cell_size_for_points(const PointCloud& cloud, double spacing_factor) {
  return cell_size_for_spacing(compute_stats(cloud).median_spacing, spacing_factor);
}

namespace {

/// estimate_mesh() of the blended nodes `cut` of `tree` whose supports meet `box` (all when null).
MeshEstimate estimate_cut(const ClusterTree& tree, std::span<const std::int32_t> cut, double cell_size,
                          const BoundingBox* box) {
  if (!(cell_size > 0) || !std::isfinite(cell_size)) throw OptionError("mesh voxel size must be positive");
  MeshEstimate out;
  for (const std::int32_t n : cut) {
    const ClusterNode& node = tree.nodes[static_cast<std::size_t>(n)];
    if (box != nullptr && !detail::sphere_meets_box(node.support, *box)) continue;
    // A support grown beyond alpha × extent to hold MPU's N_min points (sparse or clumped
    // points) blends the surface over the gap it reaches across, in proportion to its disk.
    const double own = tree.parameters.alpha * node.extent;
    const double grown = own > 0 ? std::max(1.0, node.support.radius * node.support.radius / (own * own)) : 1.0;
    out.area += 0.5 * node.extent * node.extent * grown;
  }
  out.surface_cells = out.area / (cell_size * cell_size);
  out.bytes = out.surface_cells * kMeshBytesPerSurfaceCell;
  return out;
}

/// auto_cell_size() of the blended nodes `cut` of `tree`.
double auto_cell_of(const ClusterTree& tree, std::span<const std::int32_t> cut) {
  const double h = cell_size_for_spacing(tree.point_spacing);
  const double points = tree.nodes.empty() ? 0.0 : static_cast<double>(tree.nodes[0].point_count);
  const double cells = estimate_cut(tree, cut, h, nullptr).surface_cells;
  const double most = kMaxSurfaceCellsPerPoint * points;
  // The estimate falls with the square of the cell size.
  return cells > most && most > 0 ? h * std::sqrt(cells / most) : h;
}

}  // namespace

MeshEstimate detail::estimate_mesh_within(const ImplicitSurface& surface, double cell_size, const BoundingBox* box) {
  return estimate_cut(surface.tree(), surface.cut(), cell_size, box);
}

MeshEstimate estimate_mesh(const ImplicitSurface& surface, double cell_size) {
  return detail::estimate_mesh_within(surface, cell_size, nullptr);
}

double auto_cell_size(const ImplicitSurface& surface) { return auto_cell_of(surface.tree(), surface.cut()); }

double auto_cell_size(const ClusterTree& tree) { return auto_cell_of(tree, tree.leaves()); }

}  // namespace clustersurf
