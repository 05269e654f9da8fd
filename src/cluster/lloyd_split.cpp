// Lloyd clustering (thesis 3.2.1–3.2.2): 2-means with point proxies and restarts, optionally
// refined by proxy-Lloyd rounds.

#include "cluster/splitters.hpp"

#include <algorithm>
#include <random>
#include <vector>

namespace clustersurf::detail {

namespace {

/// k-means++ seeding for k = 2: a uniform first seed, the second with probability ∝ d².
std::pair<Eigen::Vector3d, Eigen::Vector3d> kmeanspp_seeds(const Points& points, std::span<const std::uint32_t> range,
                                                           std::mt19937_64& rng) {
  std::uniform_int_distribution<std::size_t> pick(0, range.size() - 1);
  const Eigen::Vector3d a = points.row(range[pick(rng)]).transpose();
  std::vector<double> d2(range.size());
  for (std::size_t k = 0; k < range.size(); ++k) d2[k] = (points.row(range[k]).transpose() - a).squaredNorm();
  std::discrete_distribution<std::size_t> weighted(d2.begin(), d2.end());
  const Eigen::Vector3d b = points.row(range[weighted(rng)]).transpose();
  return {a, b};
}

}  // namespace

std::size_t lloyd_split(const Points& points, std::span<std::uint32_t> range, const BuildOptions& options,
                        std::uint64_t node_seed) {
  const std::size_t m = range.size();
  const std::size_t kmin = std::max<std::size_t>(1, options.min_points);
  if (m < 2 * kmin) return 0;

  // Restart 0: farthest-point seeding from the mean; the others: k-means++.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (auto i : range) mean += points.row(i).transpose();
  mean /= static_cast<double>(m);
  auto farthest = [&](const Eigen::Vector3d& x) {
    double best = -1;
    Eigen::Vector3d far = x;
    for (auto i : range)
      if (const double d = (points.row(i).transpose() - x).squaredNorm(); d > best)
        best = d, far = points.row(i).transpose();
    return far;
  };
  const Eigen::Vector3d a = farthest(mean);
  TwoMeans best = two_means(points, range, a, farthest(a));
  std::mt19937_64 rng(node_seed);
  for (std::uint32_t r = 1; r < std::max<std::uint32_t>(1, options.lloyd_restarts); ++r) {
    const auto [s0, s1] = kmeanspp_seeds(points, range, rng);
    TwoMeans t = two_means(points, range, s0, s1);
    if (t.energy < best.energy) best = std::move(t);
  }
  std::vector<std::uint8_t> labels = std::move(best.labels);

  // Proxy-Lloyd refinement: fit a proxy per side, reassign each point to the proxy nearer to it.
  std::vector<std::uint32_t> side[2];
  auto gather = [&] {
    side[0].clear(), side[1].clear();
    for (std::size_t k = 0; k < m; ++k) side[labels[k]].push_back(range[k]);
  };
  for (std::uint32_t round = 0; round < options.proxy_lloyd_iterations; ++round) {
    gather();
    if (side[0].size() < kmin || side[1].size() < kmin) break;
    const Proxy p0 = fit_proxy(options.proxy, points, side[0]);
    const Proxy p1 = fit_proxy(options.proxy, points, side[1]);
    bool changed = false;
    for (std::size_t k = 0; k < m; ++k) {
      const Eigen::Vector3d x = points.row(range[k]).transpose();
      const std::uint8_t l = std::abs(p1.value(x)) < std::abs(p0.value(x)) ? 1 : 0;
      changed = changed || l != labels[k];
      labels[k] = l;
    }
    if (!changed) break;
  }

  // Enforce min_points: move the points of the large side nearest to the small side's center
  // (by projection on the line between the centers) until the small side is big enough.
  gather();
  Eigen::Vector3d c[2];
  for (int s = 0; s < 2; ++s) {
    c[s].setZero();
    for (auto i : side[s]) c[s] += points.row(i).transpose();
    if (!side[s].empty()) c[s] /= static_cast<double>(side[s].size());
  }
  if (side[0].size() < kmin || side[1].size() < kmin) {
    const int small = side[0].size() < side[1].size() ? 0 : 1;
    Eigen::Vector3d dir = c[small] - c[1 - small];
    if (!(dir.norm() > 0)) dir = Eigen::Vector3d::UnitX();
    std::vector<std::pair<double, std::uint32_t>> keyed;
    for (auto i : side[1 - small]) keyed.emplace_back(-dir.dot(points.row(i).transpose()), i);
    std::sort(keyed.begin(), keyed.end());
    const std::size_t need = kmin - side[small].size();
    for (std::size_t k = 0; k < need; ++k) side[small].push_back(keyed[k].second);
    side[1 - small].clear();
    for (std::size_t k = need; k < keyed.size(); ++k) side[1 - small].push_back(keyed[k].second);
  }
  if (side[0].empty() || side[1].empty()) return 0;
  std::copy(side[0].begin(), side[0].end(), range.begin());
  std::copy(side[1].begin(), side[1].end(), range.begin() + static_cast<std::ptrdiff_t>(side[0].size()));
  return side[0].size();
}

}  // namespace clustersurf::detail
