// The noise field: a scan whose noise differs from part to part reads each part's own noise,
// relief is not read as noise, and a tree keeps each part's noise: the noisier part averaged
// as its own noise asks, the quieter part as fine as before.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/cluster/noise.hpp>
#include <clustersurf/cluster/noise_field.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/surface/implicit_surface.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

using namespace clustersurf;

namespace {

/// The share of the unit square, x above it, whose noise is kLoudFactor times the rest's.
constexpr double kLoudFrom = 0.7;
constexpr double kLoudFactor = 3;

/// n points of the unit square in z = 0, noise `sigma` in every direction where x < kLoudFrom
/// and kLoudFactor σ beyond: a scan whose far part the scanner saw at a grazing angle.
PointCloud two_noise_plane(int n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 1);
  PointCloud c;
  c.positions.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    const double s = x < kLoudFrom ? sigma : kLoudFactor * sigma;
    c.positions.row(i) << x + s * g(rng), y + s * g(rng), s * g(rng);
  }
  return c;
}

/// n points of the unit square with noise σ in z, in one layer where x < kLoudFrom and in two
/// 6 σ apart beyond (every other point in each), each point's normal +z with `normals`.
PointCloud two_layer_plane(int n, double sigma, bool normals) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, sigma);
  PointCloud c;
  c.positions.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    const double layer = x > kLoudFrom ? (i % 2 == 0 ? 3 * sigma : -3 * sigma) : 0;
    c.positions.row(i) << x, y, layer + g(rng);
  }
  if (normals) {
    c.normals = Points::Zero(n, 3);
    c.normals.col(2).setOnes();
  }
  return c;
}

NoiseEstimate field_of(const PointCloud& c) {
  const KdTree index(c.positions);
  return estimate_noise_field(c.positions, index, NoiseOptions{}, c.normals.rows() > 0 ? &c.normals : nullptr);
}

/// The field of two_layer_plane() (σ = 0.001) at three places on its two layers; `estimate` the
/// cloud's noise estimate.
std::vector<double> field_on_two_layers(bool normals, double& estimate) {
  const double sigma = 0.001;
  const NoiseEstimate e = field_of(two_layer_plane(60000, sigma, normals));
  estimate = e.sigma;
  std::vector<double> out;
  for (const double y : {0.2, 0.5, 0.8}) out.push_back(e.field.at(Eigen::Vector3d(0.88, y, 0)));
  std::cout << (normals ? "with" : "without") << " normals: the layers read " << out[0] / sigma << ", "
            << out[1] / sigma << ", " << out[2] / sigma << " sigma (estimate " << e.sigma / sigma << ")\n";
  return out;
}

/// The RMS of f at the plane's points over x in [x0, x1], y in [0.15, 0.85].
double rms_on_plane(const ClusterTree& t, double x0, double x1) {
  const ImplicitSurface s(t);
  double sum2 = 0;
  int count = 0;
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 20; ++i) {
      const double v = s.value(Eigen::Vector3d(x0 + (x1 - x0) * i / 20, 0.15 + 0.7 * j / 40, 0)).value_or(1.0);
      sum2 += v * v;
      ++count;
    }
  return std::sqrt(sum2 / count);
}

/// The mean count of input points inside the supports of the leaves centred in x0 ≤ x ≤ x1.
double mean_support_points(const ClusterTree& t, const PointCloud& c, double x0, double x1) {
  const KdTree index(c.positions);
  std::vector<Neighbor> inside;
  double sum = 0;
  int leaves = 0;
  for (const ClusterNode& n : t.nodes) {
    if (!n.is_leaf() || n.support.center.x() < x0 || n.support.center.x() > x1) continue;
    index.radius_unsorted(n.support.center, n.support.radius, inside);
    sum += static_cast<double>(inside.size());
    ++leaves;
  }
  return leaves > 0 ? sum / leaves : 0;
}

}  // namespace

TEST(NoiseField, EachPartReadsItsOwnNoise) {
  const double sigma = 0.002;
  const NoiseEstimate e = field_of(two_noise_plane(60000, sigma, 5));
  ASSERT_FALSE(e.field.empty());
  // The estimate is the median: the quieter part's, 70 % of the surface.
  EXPECT_NEAR(e.sigma, sigma, 0.15 * sigma);
  for (const double y : {0.2, 0.5, 0.8}) {
    const double quiet = e.field.at(Eigen::Vector3d(0.3, y, 0)), loud = e.field.at(Eigen::Vector3d(0.88, y, 0));
    std::cout << "y " << y << ": quiet part " << quiet / sigma << " sigma, loud part " << loud / sigma << " sigma\n";
    EXPECT_NEAR(quiet, sigma, 0.2 * sigma);
    // Less than the whole of it: the narrowest fits follow part of a noise that is large
    // against their width (the least of the three widths' readings is taken), and the field
    // keeps only the excess beyond what sampling lets noise of the estimate read.
    EXPECT_GT(loud, 0.5 * kLoudFactor * sigma);
    EXPECT_LT(loud, 1.1 * kLoudFactor * sigma);
  }
}

TEST(NoiseField, ReliefOnPartOfAQuietSurfaceIsNotNoise) {
  // Bumps a tenth of the square wide and 40 σ high where x > 0.5; noise σ everywhere.
  const double sigma = 0.0005;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, sigma);
  PointCloud c;
  c.positions.resize(60000, 3);
  for (Eigen::Index i = 0; i < c.positions.rows(); ++i) {
    const double x = u(rng), y = u(rng);
    const double h = x > 0.5 ? 40 * sigma * std::sin(20 * M_PI * x) * std::sin(20 * M_PI * y) : 0;
    c.positions.row(i) << x, y, h + g(rng);
  }
  const NoiseEstimate e = field_of(c);
  int raised = 0, places = 0;
  for (int j = 1; j < 10; ++j)
    for (int i = 1; i < 10; ++i, ++places) {
      const double x = 0.5 + 0.05 * i, y = 0.1 * j;
      const double h = 40 * sigma * std::sin(20 * M_PI * x) * std::sin(20 * M_PI * y);
      raised += e.field.at(Eigen::Vector3d(x, y, h)) > 1.5 * e.sigma;
    }
  std::cout << "estimate " << e.sigma / sigma << " sigma; field above 1.5 times it at " << raised << " of " << places
            << " places on the relief\n";
  EXPECT_LE(raised, places / 10);
}

TEST(NoiseField, TheTwoSidesOfAThinPartAreNotNoise) {
  // Without normals, the two layers are a plate 6 σ thick: both its sides lie within one fit's
  // neighbourhood, whose residuals then read about 3 σ, flatter than noise's.
  double estimate = 0;
  for (const double plate : field_on_two_layers(false, estimate)) EXPECT_LT(plate, 1.25 * estimate);
}

TEST(NoiseField, WithNormalsTwoLayersFacingOneWayAreNoise) {
  // The same two layers, each point's normal +z: two scans of one surface, misregistered.
  // Their residuals are as flat as the plate's, but facing one way they are one surface's noise.
  double estimate = 0;
  for (const double layers : field_on_two_layers(true, estimate)) EXPECT_GT(layers, 1.5 * estimate);
}

TEST(NoiseField, ATreeAveragesEachPartAsItsOwnNoiseAsks) {
  const double sigma = 0.002;
  const PointCloud c = two_noise_plane(60000, sigma, 11);
  BuildOptions global;
  global.noise.local = false;
  ClusterTree t = build_cluster_tree(c, {});
  ClusterTree u = build_cluster_tree(c, global);
  orient_tree(t, c);
  orient_tree(u, c);
  const double loud = rms_on_plane(t, kLoudFrom + 0.05, 0.95), loud_global = rms_on_plane(u, kLoudFrom + 0.05, 0.95);
  const double quiet = rms_on_plane(t, 0.05, kLoudFrom - 0.05), quiet_global = rms_on_plane(u, 0.05, kLoudFrom - 0.05);
  const double n = mean_support_points(t, c, kLoudFrom, 1);
  std::cout << "loud part: rms " << loud / sigma << " sigma (" << loud_global / sigma
            << " with the estimate everywhere), support points " << n << "; quiet part: " << quiet / sigma << " ("
            << quiet_global / sigma << ")\n";
  // The loud part within a few standard errors of its supports, as a plane of one noise is
  // (NoiseAveraging); the quiet part as it is with the estimate everywhere.
  EXPECT_LT(loud, 8.0 * kLoudFactor * sigma / std::sqrt(n));
  EXPECT_LT(quiet, 1.25 * quiet_global);
}
