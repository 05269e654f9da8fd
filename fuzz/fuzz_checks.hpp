#pragma once
// Properties every successful parse must have, checked by the fuzz targets (a violation aborts,
// which libFuzzer reports as a crash with the input that caused it).

#include <clustersurf/point_cloud.hpp>

#include <cstdlib>

namespace clustersurf::fuzz {

/// Aborts unless `condition` holds.
inline void require(bool condition) {
  if (!condition) std::abort();
}

/// A cloud as the readers promise it: points, finite coordinates and normals, attribute rows
/// matching the positions.
inline void check_cloud(const PointCloud& c) {
  require(c.size() > 0 && c.positions.cols() == 3 && c.positions.allFinite());
  require(!c.has_normals() || (c.normals.rows() == c.size() && c.normals.allFinite()));
  require(!c.has_colors() || c.colors.rows() == c.size());
}

/// A mesh as the readers promise it: every triangle index names a vertex.
inline void check_mesh(const TriangleMesh& m) {
  require(m.vertices.rows() > 0 && m.vertices.allFinite());
  require(m.triangles.size() == 0 || (m.triangles.minCoeff() >= 0 && m.triangles.maxCoeff() < m.vertices.rows()));
}

}  // namespace clustersurf::fuzz
