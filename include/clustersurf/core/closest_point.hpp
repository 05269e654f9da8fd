#pragma once
// The point of a triangle nearest to a point.

#include <Eigen/Core>

namespace clustersurf {

/// The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision Detection, 5.1.5);
/// a for a degenerate triangle whose regions all fail.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c);

}  // namespace clustersurf
