// Splitting a cluster at an empty gap: two parts far apart are never one leaf.

#include "cluster/splitters.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace clustersurf::detail {

std::size_t split_at_gap(const Points& points, std::span<std::uint32_t> range, const Frame& frame,
                         std::uint32_t min_points) {
  const std::size_t n = range.size();
  const std::size_t m = std::max<std::size_t>(min_points, 1);
  if (n < 2 * m) return 0;
  const Eigen::Vector3d axis = frame.axes.col(0);
  std::vector<std::pair<double, std::uint32_t>> along(n);
  for (std::size_t k = 0; k < n; ++k)
    along[k] = {axis.dot(points.row(range[k]).transpose() - frame.origin), range[k]};
  std::sort(along.begin(), along.end());  // ties by index: deterministic
  std::size_t best = 0;
  double widest = 0;
  for (std::size_t j = m - 1; j + m < n; ++j) {
    const double gap = along[j + 1].first - along[j].first;
    if (gap > widest) widest = gap, best = j + 1;
  }
  if (best == 0) return 0;
  const double left = along[best - 1].first - along.front().first;
  const double right = along.back().first - along[best].first;
  if (!(widest > std::max(left, right))) return 0;
  for (std::size_t k = 0; k < n; ++k) range[k] = along[k].second;
  return best;
}

}  // namespace clustersurf::detail
