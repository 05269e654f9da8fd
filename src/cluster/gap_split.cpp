// Splitting a cluster at an empty gap: two parts far apart are never one leaf.

#include "cluster/splitters.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace clustersurf::detail {

namespace {
/// A side with fewer than min_points is split off only across a gap this many times wider.
constexpr double kStrayGapRatio = 8;
}  // namespace

std::size_t split_at_gap(const Points& points, std::span<std::uint32_t> range, const Frame& frame,
                         std::uint32_t min_points) {
  const std::size_t n = range.size();
  const std::size_t m = std::max<std::size_t>(min_points, 1);
  if (n < 2) return 0;
  const Eigen::Vector3d axis = frame.axes.col(0);
  std::vector<std::pair<double, std::uint32_t>> along(n);
  for (std::size_t k = 0; k < n; ++k) along[k] = {axis.dot(points.row(range[k]).transpose() - frame.origin), range[k]};
  std::sort(along.begin(), along.end());  // ties by index: deterministic
  // The widest gap; a side below min_points only when the gap dwarfs both sides (a few stray
  // points far from the rest would otherwise stretch the leaf's support across the gap).
  std::size_t best = 0;
  double widest = 0;
  for (std::size_t j = 0; j + 1 < n; ++j) {
    const double gap = along[j + 1].first - along[j].first;
    if (gap <= widest) continue;
    const double left = along[j].first - along.front().first, right = along.back().first - along[j + 1].first;
    const bool sides_large = j + 1 >= m && n - (j + 1) >= m;
    if (sides_large ? gap > std::max(left, right) : gap > kStrayGapRatio * std::max(left, right))
      widest = gap, best = j + 1;
  }
  if (best == 0) return 0;
  for (std::size_t k = 0; k < n; ++k) range[k] = along[k].second;
  return best;
}

}  // namespace clustersurf::detail
