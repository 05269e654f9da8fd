// The support fit of a leaf (src/cluster/support_fit.cpp): with input normals surer than the
// positions (exact normals on noisy positions), the fit follows their slopes and the surface
// lands closer to the truth; where they add little (clean data), the tree is the positions'.

#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

constexpr double kTube = 0.25;  // the torus's tube radius (its ring's radius is 1)

/// n points on a torus around z (radii 1 and kTube) with their exact outward normals, and
/// Gaussian noise of standard deviation `sigma` on the positions (the benchmark's noisy clouds:
/// normals of the noise-free surface).
PointCloud noisy_torus(int n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 2 * M_PI);
  std::normal_distribution<double> g(0, 1);
  PointCloud c;
  c.positions.resize(n, 3);
  c.normals.resize(n, 3);
  for (int i = 0; i < n;) {
    const double a = u(rng), b = u(rng);
    // Area-uniform: accept by the circumference at b.
    if (u(rng) / (2 * M_PI) * (1 + kTube) > 1 + kTube * std::cos(b)) continue;
    const Eigen::Vector3d ring(std::cos(a), std::sin(a), 0);
    const Eigen::Vector3d normal = std::cos(b) * ring + std::sin(b) * Eigen::Vector3d::UnitZ();
    c.normals.row(i) = normal.transpose();
    c.positions.row(i) = (ring + kTube * normal + sigma * Eigen::Vector3d(g(rng), g(rng), g(rng))).transpose();
    ++i;
  }
  return c;
}

/// Mean distance of the mesh's vertices to the torus.
double mean_distance_to_torus(const TriangleMesh& mesh) {
  double sum = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const Eigen::Vector3d p = mesh.vertices.row(v).transpose();
    sum += std::abs(std::hypot(std::hypot(p.x(), p.y()) - 1, p.z()) - kTube);
  }
  return mesh.vertices.rows() > 0 ? sum / static_cast<double>(mesh.vertices.rows())
                                  : std::numeric_limits<double>::infinity();
}

double meshed_distance(const PointCloud& cloud, bool fit_normals) {
  ReconstructOptions options;
  options.build.fit_normals = fit_normals;
  const Reconstruction r = reconstruct(cloud, options);
  return r.mesh ? mean_distance_to_torus(r.mesh->mesh) : std::numeric_limits<double>::infinity();
}

}  // namespace

TEST(SupportFit, ExactNormalsOnNoisyPositionsBringTheSurfaceCloser) {
  // Noise of 4 % of the tube's radius: the positions' fits follow part of it, the normals do not.
  const PointCloud cloud = noisy_torus(12000, 0.04 * kTube, 7);
  const double positions = meshed_distance(cloud, false);
  const double hermite = meshed_distance(cloud, true);
  std::cout << "noisy torus, mean distance of the mesh: positions only " << positions << ", with the normals "
            << hermite << "\n";
  EXPECT_LT(hermite, 0.9 * positions);
}

TEST(SupportFit, CleanDataKeepThePositionsFits) {
  // Without noise the normals add less than a tenth of the positions' information: the same
  // tree with and without them in the fit, but for the few supports they stop short of the
  // tube's far side, which refit there.
  const PointCloud cloud = noisy_torus(8000, 0, 8);
  ReconstructOptions options;
  options.mesh = false;
  const ClusterTree with = reconstruct(cloud, options).tree;
  options.build.fit_normals = false;
  const ClusterTree without = reconstruct(cloud, options).tree;
  ASSERT_EQ(with.nodes.size(), without.nodes.size());
  std::size_t leaves = 0, same = 0;
  for (std::size_t k = 0; k < with.nodes.size(); ++k) {
    const auto* a = std::get_if<PolyProxy>(&with.nodes[k].proxy.variant());
    const auto* b = std::get_if<PolyProxy>(&without.nodes[k].proxy.variant());
    ASSERT_EQ(a == nullptr, b == nullptr) << "node " << k;
    if (!with.nodes[k].is_leaf()) continue;
    ++leaves;
    if (with.nodes[k].support.radius != without.nodes[k].support.radius) continue;
    ++same;
    if (a != nullptr) {
      EXPECT_EQ(a->coeffs, b->coeffs) << "node " << k;
    }
  }
  EXPECT_GT(same, leaves * 9 / 10);
}

TEST(SupportFit, ASparselySampledThinTubeStaysThin) {
  // A ring of a thin tube (radius 0.06 around a circle of radius 1) with 2,000 points, about 11
  // around the tube, their exact normals and 0.1 % noise: the legs of a sparse scan of an
  // animal. A leaf's support that reaches the far side of the tube blends in a proxy that
  // points the other way there, and a leaf of 15-20 points wraps half around it: both inflate
  // the tube (before: mean distance 0.0055, the tube swollen by 0.0039, 6.5 % of its radius;
  // now 0.0019 and 0.0010).
  constexpr double kRadius = 0.06;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 2 * M_PI);
  std::normal_distribution<double> g(0, 0.001);
  PointCloud c;
  const int n = 2000;
  c.positions.resize(n, 3);
  c.normals.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = u(rng), b = u(rng);
    const Eigen::Vector3d ring(std::cos(a), std::sin(a), 0);
    const Eigen::Vector3d normal = std::cos(b) * ring + std::sin(b) * Eigen::Vector3d::UnitZ();
    c.normals.row(i) = normal.transpose();
    c.positions.row(i) = (ring + (kRadius + g(rng)) * normal).transpose();
  }
  const Reconstruction r = reconstruct(c);
  ASSERT_TRUE(r.mesh.has_value());
  const TriangleMesh& mesh = r.mesh->mesh;
  double sum = 0, outward = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const Eigen::Vector3d p = mesh.vertices.row(v).transpose();
    const double d = std::hypot(std::hypot(p.x(), p.y()) - 1, p.z()) - kRadius;
    sum += std::abs(d);
    outward += d;
  }
  const double rows = static_cast<double>(mesh.vertices.rows());
  std::cout << "thin tube: mean distance " << sum / rows << ", mean offset " << outward / rows << "\n";
  EXPECT_LT(sum / rows, 0.003);
  EXPECT_LT(std::abs(outward / rows), 0.002);
}

TEST(SupportFit, ASparseScanOfADetailedModelKeepsItsSupportsNarrow) {
  // 3,000 points of 10 virtual range scans of the horse (the benchmark's scan10-3k), three
  // scans drawn with different seeds: a leaf's support holds about twice its cluster's points;
  // grown to hold 30, the supports of the small leaves on legs, ears and muzzle reach past where
  // their quadratics hold, and the blend leans on those rims. The default supports (12 points)
  // bring the surface closer on every scan, by about a quarter (seeds 1-3: 0.73-0.77 of the
  // 30-point supports' Chamfer). One scan's Chamfer moves by a tenth with the compiler's
  // rounding (a split decided otherwise), so the test compares the two on the same scans.
  const auto file = test::shared_data("meshes/horse.ply");
  if (!file) GTEST_SKIP() << "shared data meshes/horse.ply is absent";
  const TriangleMesh horse = read_triangle_mesh(*file);
  double narrow_sum = 0, wide_sum = 0;
  for (const std::uint64_t seed : {1, 2, 3}) {
    const PointCloud cloud = test::sparse_scan(horse, seed);
    ReconstructOptions wide;
    wide.build.support_points = 30;
    const Reconstruction narrow_r = reconstruct(cloud), wide_r = reconstruct(cloud, wide);
    ASSERT_TRUE(narrow_r.mesh.has_value() && wide_r.mesh.has_value());
    const double narrow = compare_surfaces(narrow_r.mesh->mesh, horse).chamfer;
    const double wide_c = compare_surfaces(wide_r.mesh->mesh, horse).chamfer;
    std::cout << "horse, 3,000 points of 10 scans, seed " << seed << ": Chamfer " << narrow
              << " of the diagonal (supports of 30 points: " << wide_c << ")\n";
    EXPECT_LT(narrow, wide_c);
    narrow_sum += narrow;
    wide_sum += wide_c;
  }
  EXPECT_LT(narrow_sum, 0.95 * wide_sum);
  EXPECT_LT(narrow_sum / 3, 16e-4);
}
