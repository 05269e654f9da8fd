// Splitting a would-be leaf that holds two sheets facing apart (the two sides of a thin part,
// the two faces of a deep fold, a separate part tucked against another) by its input normals.

#include "cluster/splitters.hpp"

#include <algorithm>
#include <vector>

namespace clustersurf::detail {

namespace {
/// Rounds of 2-means on the normals: the groups of two sheets settle in one or two.
constexpr int kNormalRounds = 4;

/// The unit mean of the normals of a range's rows, or zero when they cancel.
Eigen::Vector3d mean_normal(const Points& normals, std::span<const std::uint32_t> ids, std::span<const std::uint32_t> range) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (auto row : range) sum += normals.row(ids[row]).transpose();
  const double norm = sum.norm();
  return norm > 0 ? Eigen::Vector3d(sum / norm) : Eigen::Vector3d::Zero();
}

}  // namespace

std::size_t split_two_sheets(const Points& normals, std::span<const std::uint32_t> ids, std::span<std::uint32_t> range,
                             std::size_t min_side) {
  const std::size_t n = range.size();
  if (n < 2 * std::max<std::size_t>(min_side, 1)) return 0;
  const auto normal = [&](std::uint32_t row) -> Eigen::Vector3d { return normals.row(ids[row]).transpose(); };
  // Seeds: the mean normal (or the first one, when they cancel) and the normal farthest from it.
  Eigen::Vector3d c0 = mean_normal(normals, ids, range);
  if (c0.isZero()) c0 = normal(range[0]);
  Eigen::Vector3d c1 = c0;
  for (auto row : range)
    if (normal(row).dot(c0) < c1.dot(c0)) c1 = normal(row);
  if (!(c1.dot(c0) < 0)) return 0;  // every normal within 90 degrees of the mean: one sheet
  std::vector<std::uint8_t> side(n);
  for (int round = 0; round < kNormalRounds; ++round) {
    Eigen::Vector3d s0 = Eigen::Vector3d::Zero(), s1 = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < n; ++k) {
      const Eigen::Vector3d m = normal(range[k]);
      side[k] = m.dot(c1) > m.dot(c0);
      (side[k] ? s1 : s0) += m;
    }
    if (s0.isZero() || s1.isZero()) return 0;
    c0 = s0.normalized();
    c1 = s1.normalized();
  }
  // Two sheets face apart: their mean normals more than 90 degrees from each other. A crease
  // between two faces of one side of a part is left to the error-driven splits.
  if (!(c0.dot(c1) < 0)) return 0;
  const auto ones = static_cast<std::size_t>(std::count(side.begin(), side.end(), std::uint8_t{1}));
  if (ones < min_side || n - ones < min_side) return 0;
  std::vector<std::uint32_t> first, second;
  for (std::size_t k = 0; k < n; ++k) (side[k] ? second : first).push_back(range[k]);
  std::copy(first.begin(), first.end(), range.begin());
  std::copy(second.begin(), second.end(), range.begin() + static_cast<std::ptrdiff_t>(first.size()));
  return first.size();
}

}  // namespace clustersurf::detail
