#pragma once
// The mean and covariance of a point's neighbours: their plane, and how flat it is.

#include <clustersurf/spatial/kd_tree.hpp>

#include <span>

namespace clustersurf::detail {

/// The mean and the covariance of a set of points.
struct NeighborhoodShape {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

/// The shape of the points of `points` that `near` names (zero for none).
inline NeighborhoodShape neighborhood_shape(const Points& points, std::span<const Neighbor> near) {
  NeighborhoodShape s;
  if (near.empty()) return s;
  for (const Neighbor& q : near) s.mean += points.row(q.index).transpose();
  s.mean /= static_cast<double>(near.size());
  for (const Neighbor& q : near) {
    const Eigen::Vector3d d = points.row(q.index).transpose() - s.mean;
    s.covariance.noalias() += d * d.transpose();
  }
  s.covariance /= static_cast<double>(near.size());
  return s;
}

}  // namespace clustersurf::detail
