// A vertex's local fits (src/mesh/vertex_fit.cpp): the noise their residuals show without the
// relief, on a noisy plane, on exact points of a rippled sheet and on noisy points of it.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <span>
#include <vector>

#include "mesh/vertex_fit.hpp"

using namespace clustersurf;

namespace {

constexpr int kPoints = 40000;  // over [-1, 1]²: a spacing of about 0.01
constexpr std::size_t kNarrow = 12;
constexpr int kQueries = 2000;

/// The rippled sheet's height a sin(k u) sin(k v).
double ripple(double u, double v, double a, double k) { return a * std::sin(k * u) * std::sin(k * v); }

/// kPoints points of the rippled sheet, uniform over [-1, 1]², with Gaussian noise of `sigma`
/// along z.
PointCloud rippled_sheet(double a, double k, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::normal_distribution<double> g(0, 1);
  PointCloud cloud;
  cloud.positions.resize(kPoints, 3);
  for (int i = 0; i < kPoints; ++i) {
    const double u = uniform(rng), v = uniform(rng);
    cloud.positions.row(i) << u, v, ripple(u, v, a, k) + sigma * g(rng);
  }
  return cloud;
}

struct MeanNoise {
  double narrow = 0;       ///< the narrow fits' residual variance
  double relief_free = 0;  ///< relief_free_noise()'s
  double dof = 0;          ///< the narrow fits' degrees of freedom, which the refit gives it
  double spread_dof = 0;   ///< those of a chi-square that spreads as much as the estimates do
};

/// The mean noise the fits at kQueries points of the sheet's middle show, each on the sheet, its
/// normal the sheet's.
MeanNoise mean_noise(const PointCloud& cloud, double a, double k) {
  const ClusterTree tree = build_cluster_tree(cloud);
  const KdTree index(cloud.positions);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(-0.5, 0.5);
  std::vector<Neighbor> near;
  MeanNoise mean;
  double squares = 0;
  int count = 0;
  for (int i = 0; i < kQueries; ++i) {
    const double u = uniform(rng), v = uniform(rng);
    const Eigen::Vector3d x(u, v, ripple(u, v, a, k));
    const Eigen::Vector3d normal(-a * k * std::cos(k * u) * std::sin(k * v), -a * k * std::sin(k * u) * std::cos(k * v),
                                 1);
    index.knn(x, 2 * kNarrow, near);
    const auto sorted = std::span<const Neighbor>(near);
    const detail::LocalFit narrow = detail::fit_at(x, normal, cloud.positions, sorted.first(kNarrow), tree, true);
    const detail::LocalFit wide = detail::fit_at(x, normal, cloud.positions, sorted, tree, true);
    if (!narrow.valid || !wide.valid) continue;
    const double noise = detail::relief_free_noise(narrow, wide);
    mean.narrow += narrow.residual_variance, mean.relief_free += noise, mean.dof += narrow.dof;
    squares += noise * noise;
    ++count;
  }
  EXPECT_GT(count, kQueries * 3 / 4);
  mean.narrow /= count, mean.relief_free /= count, mean.dof /= count;
  // A mean of ν squared normals over its mean squared has the variance 2 / ν.
  mean.spread_dof = 2 * mean.relief_free * mean.relief_free / (squares / count - mean.relief_free * mean.relief_free);
  return mean;
}

}  // namespace

TEST(VertexFit, OnANoisyPlaneTheNoiseIsTheNoise) {
  constexpr double kSigma = 0.002;
  const MeanNoise m = mean_noise(rippled_sheet(0, 0, kSigma, 1), 0, 0);
  std::cout << "noisy plane: sigma² " << kSigma * kSigma << ", narrow fits' residuals " << m.narrow << ", relief-free "
            << m.relief_free << " with " << m.dof << " degrees of freedom, spread as a chi-square of " << m.spread_dof
            << "\n";
  EXPECT_NEAR(m.narrow, kSigma * kSigma, 0.15 * kSigma * kSigma);
  EXPECT_NEAR(m.relief_free, kSigma * kSigma, 0.15 * kSigma * kSigma);
  // The margins the refit sets on it (noise_variance_margin()) are no narrower than its spread.
  EXPECT_GT(m.dof, 0.0);
  EXPECT_LE(m.dof, m.spread_dof);
}

TEST(VertexFit, TheReliefOfExactPointsIsNotNoise) {
  // Ripples 20 spacings long: the narrow fits' quadratics leave their cubic terms.
  constexpr double kAmplitude = 0.01, kWaves = 30;
  const MeanNoise m = mean_noise(rippled_sheet(kAmplitude, kWaves, 0, 2), kAmplitude, kWaves);
  std::cout << "exact ripples: narrow fits' residuals " << m.narrow << ", relief-free " << m.relief_free << "\n";
  EXPECT_GT(m.narrow, 0.0);
  EXPECT_LT(m.relief_free, 0.2 * m.narrow);
}

TEST(VertexFit, UnderNoiseTheReliefIsTakenAwayAndTheNoiseKept) {
  constexpr double kAmplitude = 0.01, kWaves = 30, kSigma = 0.0005;
  const MeanNoise m = mean_noise(rippled_sheet(kAmplitude, kWaves, kSigma, 3), kAmplitude, kWaves);
  std::cout << "noisy ripples: sigma² " << kSigma * kSigma << ", narrow fits' residuals " << m.narrow
            << ", relief-free " << m.relief_free << "\n";
  EXPECT_NEAR(m.relief_free, kSigma * kSigma, 0.25 * kSigma * kSigma);
}
