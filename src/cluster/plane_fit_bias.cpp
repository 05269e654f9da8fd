// How much of the noise the noise estimate's local fit follows, simulated on a noisy plane
// (see local_fit.hpp).

#include "cluster/local_fit.hpp"

#include "core/portable_random.hpp"
#include "core/splitmix.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

namespace clustersurf::detail {

namespace {
/// Simulated neighbourhoods per calibration.
constexpr std::size_t kTrials = 256;
/// Points per simulated disc, per point of a fit: the disc reaches twice the nominal width.
constexpr std::size_t kDiscPointsPerFitPoint = 4;
}  // namespace

FitBias plane_fit_bias(std::size_t k, double nominal_width_over_sigma) {
  const std::size_t disc = kDiscPointsPerFitPoint * k;
  const double sigma = 1 / nominal_width_over_sigma;  // lengths in units of the nominal width
  std::vector<double> residual(kTrials), width(kTrials);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kTrials), [&](const auto& r) {
    Points points(static_cast<Eigen::Index>(disc), 3);
    std::vector<std::pair<double, std::uint32_t>> by_distance(disc);
    std::vector<std::uint32_t> idx;
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      PortableRandom random(splitmix64(t + 1));
      Eigen::Index centre = 0;
      for (Eigen::Index i = 0; i < points.rows(); ++i) {
        // Uniform in a disc of radius 2: k points within radius 1 of its centre on average.
        const double radius = 2 * std::sqrt(random.uniform()), angle = 2 * std::numbers::pi * random.uniform();
        points.row(i) << radius * std::cos(angle), radius * std::sin(angle), 0.0;
        if (points.row(i).head<2>().squaredNorm() < points.row(centre).head<2>().squaredNorm()) centre = i;
      }
      for (Eigen::Index i = 0; i < points.rows(); ++i)
        for (int c = 0; c < 3; ++c) points(i, c) += sigma * random.normal();
      for (std::size_t i = 0; i < disc; ++i) {
        const auto row = static_cast<Eigen::Index>(i);
        by_distance[i] = {(points.row(row) - points.row(centre)).squaredNorm(), static_cast<std::uint32_t>(i)};
      }
      const auto kth = by_distance.begin() + static_cast<std::ptrdiff_t>(k - 1);
      std::nth_element(by_distance.begin(), kth, by_distance.end());
      idx.clear();
      for (auto it = by_distance.begin(); it <= kth; ++it) idx.push_back(it->second);
      residual[t] = fit_residual(points, idx, false).residual / sigma;
      width[t] = std::sqrt(kth->first);
    }
  });
  const auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  return {median(residual), median(width)};
}

}  // namespace clustersurf::detail
