// The residual correlation of a cluster's proxy (see residual_structure.hpp).

#include "cluster/residual_structure.hpp"

#include <clustersurf/spatial/kd_tree.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace clustersurf::detail {

namespace {
/// Clusters up to this size find their points' nearest neighbours by a scan in order of u.
constexpr Eigen::Index kScanPoints = 128;
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
  // them). Clusters near the leaves, too small to repay a k-d tree, scan their points in order
  // of u outwards from each point, stopping where u alone is farther than the nearest found:
  // the answer of comparing every pair, at a fraction of the cost. Larger ones query a k-d tree.
  std::vector<std::uint32_t> nearest(range.size());
  if (n <= kScanPoints) {
    std::vector<std::uint32_t> by_u(range.size());
    std::iota(by_u.begin(), by_u.end(), 0u);
    std::sort(by_u.begin(), by_u.end(), [&](std::uint32_t a, std::uint32_t b) {
      return plane(a, 0) < plane(b, 0) || (plane(a, 0) == plane(b, 0) && a < b);
    });
    for (std::size_t p = 0; p < by_u.size(); ++p) {
      const Eigen::Index k = by_u[p];
      double best = std::numeric_limits<double>::infinity();
      std::uint32_t best_index = 0;
      // d² = du² + dv² is never below du², and |du| grows away from p: past du² > best nothing
      // closer (or as close with a lower index) remains on that side.
      const auto visit = [&](std::size_t q) {
        const Eigen::Index j = by_u[q];
        const double du = plane(k, 0) - plane(j, 0), dv = plane(k, 1) - plane(j, 1);
        if (du * du > best) return false;
        const double d2 = du * du + dv * dv;
        if (d2 < best || (d2 == best && static_cast<std::uint32_t>(j) < best_index))
          best = d2, best_index = static_cast<std::uint32_t>(j);
        return true;
      };
      for (std::size_t q = p + 1; q < by_u.size() && visit(q);) ++q;  // rightwards
      for (std::size_t q = p; q > 0 && visit(q - 1);) --q;            // leftwards
      nearest[static_cast<std::size_t>(k)] = best_index;
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
