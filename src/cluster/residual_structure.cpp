// The residual correlation of a cluster's proxy (see residual_structure.hpp).

#include "cluster/residual_structure.hpp"

#include <clustersurf/kd_tree.hpp>

#include <cmath>
#include <vector>

namespace clustersurf::detail {

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
  const KdTree index(plane);
  std::vector<Neighbor> nearest;
  double cross = 0, own = 0, other = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    index.neighbors_of(k, 1, nearest);
    const double a = q[static_cast<std::size_t>(k)], b = q[nearest[0].index];
    cross += a * b;
    own += a * a;
    other += b * b;
  }
  return own > 0 && other > 0 ? cross / std::sqrt(own * other) : 0;
}

}  // namespace clustersurf::detail
