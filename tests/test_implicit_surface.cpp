// Implicit surface: zero set near the data, gradient = finite differences, undefined outside
// the supports, hierarchy traversal = brute force, level of detail.

#include <clustersurf/surface/implicit_surface.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <gtest/gtest.h>

#include <random>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

ClusterTree oriented_tree(const PointCloud& c, BuildOptions o = {}) {
  ClusterTree t = build_cluster_tree(c, o);
  orient_tree(t, c);
  return t;
}

}  // namespace

TEST(ImplicitSurface, SphereValueIsSignedDistanceNearSurface) {
  const PointCloud c = test::sample_sphere(20000, 1.0);
  const ClusterTree t = oriented_tree(c);
  const ImplicitSurface f(t);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g(0, 1);
  for (int k = 0; k < 500; ++k) {
    const Eigen::Vector3d dir = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    for (double r : {0.97, 1.0, 1.03}) {
      const auto v = f.value(r * dir);
      ASSERT_TRUE(v.has_value());
      EXPECT_NEAR(*v, r - 1.0, 0.004) << "r=" << r;
    }
  }
}

TEST(ImplicitSurface, UndefinedFarFromData) {
  const PointCloud c = test::sample_sphere(5000, 1.0);
  const ClusterTree t = oriented_tree(c);
  const ImplicitSurface f(t);
  EXPECT_FALSE(f.value(Eigen::Vector3d(5, 0, 0)).has_value());
  EXPECT_FALSE(f.sample(Eigen::Vector3d(0, 0, -4)).defined);
}

TEST(ImplicitSurface, GradientMatchesFiniteDifferences) {
  PointCloud c = test::sample_torus(15000);
  const ClusterTree t = oriented_tree(c);
  const ImplicitSurface f(t);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  int checked = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d x = c.positions.row(k * 37).transpose() + Eigen::Vector3d(u(rng), u(rng), u(rng));
    const SurfaceSample s = f.sample(x);
    if (!s.defined) continue;
    const double h = 1e-6;
    Eigen::Vector3d fd;
    bool ok = true;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e(a) = h;
      const auto p = f.value(x + e), m = f.value(x - e);
      ok = ok && p && m;
      if (ok) fd(a) = (*p - *m) / (2 * h);
    }
    if (!ok) continue;
    ++checked;
    EXPECT_LT((s.gradient - fd).norm(), 1e-4 * std::max(1.0, fd.norm()));
  }
  EXPECT_GT(checked, 250);
}

TEST(ImplicitSurface, HierarchyFindsExactlyTheSupportsBruteForceFinds) {
  const PointCloud c = test::sample_torus(10000);
  const ClusterTree t = oriented_tree(c);
  const ImplicitSurface f(t);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int k = 0; k < 500; ++k) {
    const Eigen::Vector3d x(u(rng), u(rng), 0.3 * u(rng));
    std::vector<std::int32_t> found, brute;
    f.for_each_support(x, [&](std::int32_t i, double) { found.push_back(i); });
    for (auto i : f.cut())
      if (t.nodes[static_cast<std::size_t>(i)].support.contains(x)) brute.push_back(i);
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, brute);
  }
}

TEST(ImplicitSurface, CoarserCutsHaveFewerNodesAndBoundedError) {
  const PointCloud c = test::sample_torus(30000);
  BuildOptions o;
  o.threshold_mode = ThresholdMode::Relative;
  o.tolerance = 0.0002;
  const ClusterTree t = oriented_tree(c, o);
  std::size_t previous = std::numeric_limits<std::size_t>::max();
  double previous_error = 0;
  for (std::uint32_t depth : {100u, 8u, 5u}) {
    LevelOfDetail lod;
    lod.max_depth = depth;
    const ImplicitSurface f(t, lod);
    EXPECT_LT(f.cut().size(), previous);
    previous = f.cut().size();
    // RMS of f over the samples: grows as the cut coarsens, but stays bounded.
    double ss = 0;
    int n = 0;
    for (Eigen::Index i = 0; i < c.size(); i += 10) {
      const auto v = f.value(c.positions.row(i).transpose());
      ASSERT_TRUE(v.has_value());
      ss += *v * *v, ++n;
    }
    const double rms = std::sqrt(ss / n);
    EXPECT_GE(rms, previous_error * 0.9);
    EXPECT_LT(rms, 0.05);  // 1.6 % of the diagonal even for the coarsest cut
    previous_error = rms;
  }
  LevelOfDetail by_error;
  by_error.error_limit = 0.01;
  EXPECT_LT(lod_cut(t, by_error).size(), t.leaves().size());
}
