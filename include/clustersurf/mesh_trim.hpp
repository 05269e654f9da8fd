#pragma once
// Trimming a mesh to the reach of its input points: where the data stops (a scan's open border,
// an unscanned hole), the blended proxies extrapolate; the mesh stops with the data instead. And
// a loose fragment that hardly any input point lies nearest to (a sliver of extrapolated surface,
// a small inner shell between two scan layers) is debris, not surface: it goes too.

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
  /// A connected component is kept only when at least this many input points have their
  /// nearest mesh vertex on it (MPU's N_min: no proxy rests on fewer points); 0 keeps every
  /// component. A real part as small as one cluster of the tree is kept.
  std::size_t min_component_points = 30;
};

/// What trim_to_points() removed.
struct TrimReport {
  std::size_t removed_triangles = 0;
  std::size_t removed_vertices = 0;
  std::size_t removed_components = 0;  ///< components without the data's support (see TrimOptions)
};

/// `mesh` without the triangles that reach beyond the data, without the components the data does
/// not support (see TrimOptions), and without the vertices no triangle uses; vertex order,
/// normals and colors are kept for the rest.
/// Deterministic and independent of the thread count.
TriangleMesh trim_to_points(const TriangleMesh& mesh, const Points& points, const TrimOptions& options = {},
                            TrimReport* report = nullptr);

}  // namespace clustersurf
