// Splitting a would-be leaf that holds two sheets facing apart (the two sides of a thin part,
// the two faces of a deep fold, a separate part tucked against another) by its input normals.

#include "cluster/splitters.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace clustersurf::detail {

namespace {
/// Rounds of 2-means on the normals: the groups of two sheets settle in one or two.
constexpr int kNormalRounds = 4;
/// Two groups of normals are two sheets when their heights differ by more than this many
/// standard errors (a chance of about 3 in 1,000 for groups on one sheet).
constexpr double kApartErrors = 3;
/// Or when the smaller group holds at least 1/kBalancedShare of the points (both sides of a part
/// thinner than the noise), a share that scattered orientation errors, up to kFlippedShare of
/// the normals, give it with a chance under kFlippedChance.
constexpr double kBalancedShare = 3;
constexpr double kFlippedShare = 0.1;
constexpr double kFlippedChance = 1e-4;

/// The unit mean of the normals of a range's rows, or zero when they cancel.
Eigen::Vector3d mean_normal(const Points& normals, std::span<const std::uint32_t> ids,
                            std::span<const std::uint32_t> range) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (auto row : range) sum += normals.row(ids[row]).transpose();
  const double norm = sum.norm();
  return norm > 0 ? Eigen::Vector3d(sum / norm) : Eigen::Vector3d::Zero();
}

/// Whether the two groups (`side`) lie apart along `axis`, the direction between their mean
/// normals: their mean heights differ by more than kApartErrors standard errors of that
/// difference (from their pooled variance). Two sheets are a thickness or a fold apart;
/// normals flipped by a scanner's orientation errors lie on the same sheet as their
/// neighbours, within the noise.
bool apart(const Points& points, std::span<const std::uint32_t> range, std::span<const std::uint8_t> side,
           const Eigen::Vector3d& axis) {
  double sum[2] = {0, 0}, sum2[2] = {0, 0}, count[2] = {0, 0};
  const Eigen::Vector3d origin = points.row(range[0]).transpose();
  for (std::size_t k = 0; k < range.size(); ++k) {
    const double h = axis.dot(points.row(range[k]).transpose() - origin);
    sum[side[k]] += h;
    sum2[side[k]] += h * h;
    count[side[k]] += 1;
  }
  // Under one sheet both groups scatter alike: their pooled variance gives the standard error.
  double mean[2], squares = 0;
  for (int g = 0; g < 2; ++g) {
    mean[g] = sum[g] / count[g];
    squares += std::max(0.0, sum2[g] - count[g] * mean[g] * mean[g]);
  }
  const double gap = mean[1] - mean[0];
  const double error2 = squares / std::max(1.0, count[0] + count[1] - 2) * (1 / count[0] + 1 / count[1]);
  return gap * gap > kApartErrors * kApartErrors * error2;
}

/// The chance that at least `k` of `n` normals are flipped when each is with chance `p`.
double binomial_tail(std::size_t n, std::size_t k, double p) {
  double tail = 0;
  const double log_p = std::log(p), log_q = std::log1p(-p);
  const double log_n = std::lgamma(static_cast<double>(n) + 1);
  for (std::size_t j = k; j <= n; ++j) {
    const auto x = static_cast<double>(j);
    tail += std::exp(log_n - std::lgamma(x + 1) - std::lgamma(static_cast<double>(n) - x + 1) + x * log_p +
                     (static_cast<double>(n) - x) * log_q);
  }
  return tail;
}

}  // namespace

std::size_t split_two_sheets(const Points& points, const Points& normals, std::span<const std::uint32_t> ids,
                             std::span<std::uint32_t> range, std::size_t min_side) {
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
  // Normals flipped by orientation errors are a few among the right ones, on the same sheet;
  // two sheets are either apart or each a good share of the cluster (both sides of a part
  // thinner than the noise).
  const std::size_t fewer = std::min(ones, n - ones);
  const bool balanced = kBalancedShare * static_cast<double>(fewer) >= static_cast<double>(n) &&
                        binomial_tail(n, fewer, kFlippedShare) < kFlippedChance;
  if (!balanced && !apart(points, range, side, (c0 - c1).normalized())) return 0;
  std::vector<std::uint32_t> first, second;
  for (std::size_t k = 0; k < n; ++k) (side[k] ? second : first).push_back(range[k]);
  std::copy(first.begin(), first.end(), range.begin());
  std::copy(second.begin(), second.end(), range.begin() + static_cast<std::ptrdiff_t>(first.size()));
  return first.size();
}

}  // namespace clustersurf::detail
