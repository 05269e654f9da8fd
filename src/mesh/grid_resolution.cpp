// The mesh grid matched to the sampling density of the input points and the curvature of the
// leaves, and what a walk of it costs.

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
#include <utility>
#include <variant>
#include <vector>

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

/// The largest principal curvature at the center of a quadratic height field (its Hessian's
/// largest eigenvalue in magnitude); 0 for the other proxies (planes, creases: their cells
/// need no curvature resolved).
double center_curvature(const Proxy& proxy) {
  const auto* poly = std::get_if<PolyProxy>(&proxy.variant());
  if (poly == nullptr) return 0;
  const auto& c = poly->coeffs;  // h = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v²
  const double mean = c[3] + c[5], spread = std::hypot(c[3] - c[5], c[4]);
  return std::abs(mean) + spread;
}

/// The largest cell that resolves the curvature of all but kUnresolvedCurvedShare of the area
/// of the blended nodes `cut` (at most `coarsest`).
double curvature_cell(const ClusterTree& tree, std::span<const std::int32_t> cut, double coarsest) {
  std::vector<std::pair<double, double>> cells;  // (the cell a node asks for, its area)
  double total = 0;
  for (const std::int32_t n : cut) {
    const ClusterNode& node = tree.nodes[static_cast<std::size_t>(n)];
    const double area = node.extent * node.extent;
    total += area;
    const double kappa = center_curvature(node.proxy);
    const double cell = kappa > 0 ? 1 / (kCellsPerCurvatureRadius * kappa) : coarsest;
    if (cell < coarsest) cells.emplace_back(cell, area);
  }
  std::sort(cells.begin(), cells.end());
  double finer = 0;  // the area asking for cells finer than the one reached
  for (const auto& [cell, area] : cells) {
    finer += area;
    if (finer > kUnresolvedCurvedShare * total) return cell;
  }
  return coarsest;
}

/// auto_cell_size() of the blended nodes `cut` of `tree`.
double auto_cell_of(const ClusterTree& tree, std::span<const std::int32_t> cut, double point_spacing) {
  const double spacing_cell = cell_size_for_spacing(point_spacing);
  const double h =
      std::max(cell_size_for_spacing(point_spacing, kFinestSpacingsPerCell), curvature_cell(tree, cut, spacing_cell));
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

double auto_cell_size(const ImplicitSurface& surface) { return auto_cell_size(surface, surface.tree().point_spacing); }

double auto_cell_size(const ImplicitSurface& surface, double point_spacing) {
  return auto_cell_of(surface.tree(), surface.cut(), point_spacing);
}

double auto_cell_size(const ClusterTree& tree) { return auto_cell_of(tree, tree.leaves(), tree.point_spacing); }

}  // namespace clustersurf
