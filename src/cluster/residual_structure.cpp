// The residual correlation of a cluster's proxy (see residual_structure.hpp).

#include "cluster/residual_structure.hpp"

#include <clustersurf/kd_tree.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace clustersurf::detail {

namespace {
/// Clusters up to this size find their points' nearest neighbours by comparing every pair.
constexpr Eigen::Index kBruteForcePoints = 128;
}  // namespace

double residual_correlation(const Points& points, std::span<const std::uint32_t> range, const Frame& frame,
                            const Proxy& proxy) {
  const auto n = static_cast<Eigen::Index>(range.size());
  if (n < 4) return 0;
  Points plane(n, 3);
  std::vector<double> q(range.size());
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Vector3d p = points.row(range[static_cast<std::size_t>(k)]).transpose();
    const Eigen::Vector3d d = p - frame.origin;
    plane.row(k) << d.dot(frame.axes.col(0)), d.dot(frame.axes.col(1)), 0.0;
    q[static_cast<std::size_t>(k)] = proxy.value(p);
  }
  // Each point's nearest other point in the plane (ties: the lowest index, as KdTree orders
  // them): by brute force for the clusters near the leaves, where building a k-d tree costs
  // more than comparing every pair.
  std::vector<std::uint32_t> nearest(range.size());
  if (n <= kBruteForcePoints) {
    for (Eigen::Index k = 0; k < n; ++k) {
      double best = std::numeric_limits<double>::infinity();
      for (Eigen::Index j = 0; j < n; ++j) {
        if (j == k) continue;
        double d2 = 0;
        for (int c = 0; c < 3; ++c) {
          const double d = plane(k, c) - plane(j, c);
          d2 += d * d;
        }
        if (d2 < best) best = d2, nearest[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(j);
      }
    }
  } else {
    const KdTree index(plane);
    std::vector<Neighbor> found;
    for (Eigen::Index k = 0; k < n; ++k) {
      index.neighbors_of(k, 1, found);
      nearest[static_cast<std::size_t>(k)] = found[0].index;
    }
  }
  double cross = 0, own = 0, other = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double a = q[static_cast<std::size_t>(k)], b = q[nearest[static_cast<std::size_t>(k)]];
    cross += a * b;
    own += a * a;
    other += b * b;
  }
  return own > 0 && other > 0 ? cross / std::sqrt(own * other) : 0;
}

}  // namespace clustersurf::detail
