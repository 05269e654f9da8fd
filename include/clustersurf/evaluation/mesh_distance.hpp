#pragma once
// Exact point-to-triangle-mesh distance queries over a bounding-volume hierarchy (Embree).

#include <clustersurf/core/closest_point.hpp>
#include <clustersurf/core/point_cloud.hpp>

#include <memory>

namespace clustersurf {

/// The point of a mesh nearest to a query point.
struct ClosestPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double distance_squared = 0;
  std::int32_t triangle = -1;  ///< -1 when the mesh has no triangle
};

/// Nearest points on the triangles of a mesh: the true distance to the surface, not to the
/// nearest vertex. Distances are computed in double precision from the mesh's own coordinates;
/// the hierarchy only prunes. The mesh is copied; queries are const and thread-safe.
class MeshDistance {
 public:
  explicit MeshDistance(const TriangleMesh& mesh);
  ~MeshDistance();
  MeshDistance(MeshDistance&&) noexcept;
  MeshDistance& operator=(MeshDistance&&) noexcept;

  /// The nearest point of the mesh to `query` (ties between triangles: the lowest index).
  ClosestPoint closest(const Eigen::Vector3d& query) const;
  /// Unit normal of triangle `t` (zero for a degenerate triangle).
  Eigen::Vector3d triangle_normal(std::int32_t t) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clustersurf
