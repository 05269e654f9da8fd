#pragma once
// Trimming a mesh to the reach of its input points: where the data stops (a scan's open border,
// an unscanned hole), the blended proxies extrapolate; the mesh stops with the data instead.

#include <clustersurf/point_cloud.hpp>

#include <cstddef>

namespace clustersurf {

/// Options of trim_to_points().
struct TrimOptions {
  /// A triangle is dropped when a vertex lies farther from the nearest input point than this
  /// many times that point's spread (mean distance to its `neighbors` nearest points): about
  /// 3 sample spacings by default. 0 keeps every triangle.
  double spread_factor = 2.0;
  std::size_t neighbors = 8;
};

/// What trim_to_points() removed.
struct TrimReport {
  std::size_t removed_triangles = 0;
  std::size_t removed_vertices = 0;
};

/// `mesh` without the triangles that reach beyond the data (see TrimOptions), and without the
/// vertices no triangle uses; vertex order, normals and colors are kept for the rest.
/// Deterministic and independent of the thread count.
TriangleMesh trim_to_points(const TriangleMesh& mesh, const Points& points, const TrimOptions& options = {},
                            TrimReport* report = nullptr);

}  // namespace clustersurf
