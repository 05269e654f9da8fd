// Splitting a cluster at an empty gap: two parts far apart are never one leaf.

#include "cluster/splitters.hpp"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

namespace clustersurf::detail {

namespace {
/// A side with fewer than min_points is split off only across a gap this many times wider.
constexpr double kStrayGapRatio = 8;
/// split_at_linkage_gap(): the cut edge is this many times longer than any edge within either
/// group.
constexpr double kLinkageGapRatio = 2;
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

std::size_t split_at_linkage_gap(const Points& points, std::span<std::uint32_t> range, std::size_t min_side) {
  const std::size_t n = range.size();
  if (n < 2 * std::max<std::size_t>(min_side, 1)) return 0;
  const auto at = [&](std::size_t k) -> Eigen::Vector3d { return points.row(range[k]).transpose(); };
  // Prim's minimum spanning tree: parent[k] and the squared length of k's edge to it, in the
  // order the vertices join (ties by position in `range`: deterministic).
  constexpr double kFar = std::numeric_limits<double>::infinity();
  std::vector<double> reach(n, kFar), length(n, 0.0);
  std::vector<std::size_t> parent(n, 0), joined;
  std::vector<std::uint8_t> in(n, 0);
  joined.reserve(n);
  std::size_t next = 0;
  for (std::size_t step = 0; step < n; ++step) {
    in[next] = 1;
    joined.push_back(next);
    length[next] = step == 0 ? 0.0 : reach[next];
    const Eigen::Vector3d x = at(next);
    std::size_t best = n;
    for (std::size_t k = 0; k < n; ++k) {
      if (in[k]) continue;
      const double d = (at(k) - x).squaredNorm();
      if (d < reach[k]) reach[k] = d, parent[k] = next;
      if (best == n || reach[k] < reach[best]) best = k;
    }
    next = best;
  }
  // The longest edge, and the two groups it separates: the subtree below its lower end.
  std::size_t cut = 1;  // the root, joined[0], has no edge
  for (std::size_t k = 2; k < n; ++k)
    if (length[joined[k]] > length[joined[cut]]) cut = k;
  const std::size_t low = joined[cut];
  std::vector<std::uint8_t> below(n, 0);
  below[low] = 1;
  for (std::size_t k = cut + 1; k < n; ++k) below[joined[k]] = below[parent[joined[k]]];
  const auto size = static_cast<std::size_t>(std::count(below.begin(), below.end(), std::uint8_t{1}));
  double inner = 0;  // the longest edge left (the root's length is 0)
  for (std::size_t v = 0; v < n; ++v)
    if (v != low) inner = std::max(inner, length[v]);
  if (size < min_side || n - size < min_side || !(length[low] > kLinkageGapRatio * kLinkageGapRatio * inner)) return 0;
  std::vector<std::uint32_t> grouped;
  grouped.reserve(n);
  for (const std::uint8_t side : {std::uint8_t{1}, std::uint8_t{0}})
    for (std::size_t k = 0; k < n; ++k)
      if (below[k] == side) grouped.push_back(range[k]);
  std::copy(grouped.begin(), grouped.end(), range.begin());
  return size;
}

}  // namespace clustersurf::detail
