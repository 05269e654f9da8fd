// halves_drops(): the residual drops of a cluster's halves at the median of each frame axis.

#include <clustersurf/cluster/noise.hpp>

#include "cluster/halves_test.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace clustersurf::detail {

namespace {

/// A quadratic's coefficients: what the halves add.
constexpr double kAddedCoefficients = 6;

}  // namespace

std::array<HalvesDrop, 2> halves_drops(const Points& points, std::span<const std::uint32_t> ids,
                                       std::span<const double> weights, const Frame& frame) {
  const std::size_t n = ids.size();
  if (n < 2) return {};
  std::vector<Eigen::Vector3d> local(n);
  for (std::size_t k = 0; k < n; ++k) local[k] = frame.to_local(points.row(ids[k]).transpose());
  // rows: the order of the points (indices into `ids`); part_ids and part_weights follow it.
  std::vector<std::size_t> rows(n);
  std::iota(rows.begin(), rows.end(), std::size_t{0});
  std::vector<std::uint32_t> part_ids(ids.begin(), ids.end());
  std::vector<double> part_weights(weights.begin(), weights.end());
  const auto residual = [&](std::size_t begin, std::size_t end) {
    const std::span<const std::uint32_t> sub(part_ids.data() + begin, end - begin);
    const std::span<const double> w =
        weights.empty() ? std::span<const double>() : std::span<const double>(part_weights.data() + begin, end - begin);
    const PolyProxy p = fit_poly_in_frame(frame, points, sub, w);
    double sum = 0;
    for (std::size_t k = begin; k < end; ++k) {
      const Eigen::Vector3d& l = local[rows[k]];
      const double r = l.z() - p.height(l.x(), l.y());
      sum += (weights.empty() ? 1.0 : part_weights[k]) * r * r;
    }
    return sum;
  };
  const auto spread = [&](std::size_t begin, std::size_t end) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero(), sum2 = Eigen::Vector2d::Zero();
    for (std::size_t k = begin; k < end; ++k) {
      const Eigen::Vector2d l = local[rows[k]].head<2>();
      sum += l;
      sum2 += l.cwiseProduct(l);
    }
    const double m = static_cast<double>(end - begin);
    return (sum2 / m - (sum / m).cwiseProduct(sum / m)).minCoeff();
  };
  const double whole = residual(0, n);
  const std::size_t half = n / 2;
  std::array<HalvesDrop, 2> out;
  for (const int axis : {0, 1}) {
    std::nth_element(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(half), rows.end(),
                     [&](std::size_t a, std::size_t b) { return local[a][axis] < local[b][axis]; });
    for (std::size_t j = 0; j < n; ++j) {
      part_ids[j] = ids[rows[j]];
      if (!weights.empty()) part_weights[j] = weights[rows[j]];
    }
    out[static_cast<std::size_t>(axis)] = {whole - residual(0, half) - residual(half, n),
                                           std::min(spread(0, half), spread(half, n))};
  }
  return out;
}

double halves_drop_bound(double noise, double mean_weight) {
  return mean_weight * noise * noise * kAddedCoefficients * noise_variance_quantile(kAddedCoefficients);
}

}  // namespace clustersurf::detail
