// The virtual range scanner: points on the surface, seen from outside, with the noise and the
// misregistration asked for, the same on every run and for any thread count.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/range_scan.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace clustersurf;

namespace {

/// A UV sphere of radius 1 about the origin, outward-facing triangles.
TriangleMesh uv_sphere(int rings = 96, int segments = 192) {
  TriangleMesh m;
  m.vertices.resize(2 + (rings - 1) * segments, 3);
  m.vertices.row(0) << 0, 0, 1;
  m.vertices.row(1) << 0, 0, -1;
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
      m.vertices.row(2 + (r - 1) * segments + s) << std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
          std::cos(theta);
    }
  const auto at = [&](int r, int s) { return 2 + (r - 1) * segments + (s % segments); };
  std::vector<Eigen::Vector3i> tris;
  for (int s = 0; s < segments; ++s) {
    tris.emplace_back(0, at(1, s), at(1, s + 1));
    tris.emplace_back(1, at(rings - 1, s + 1), at(rings - 1, s));
    for (int r = 1; r + 1 < rings; ++r) {
      tris.emplace_back(at(r, s), at(r + 1, s), at(r + 1, s + 1));
      tris.emplace_back(at(r, s), at(r + 1, s + 1), at(r, s + 1));
    }
  }
  m.triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t t = 0; t < tris.size(); ++t) m.triangles.row(static_cast<Eigen::Index>(t)) = tris[t].transpose();
  return m;
}

/// RMS of |p| − 1 over the cloud.
double radial_rms(const PointCloud& c) {
  double sum = 0;
  for (Eigen::Index i = 0; i < c.size(); ++i) sum += std::pow(c.positions.row(i).norm() - 1, 2);
  return std::sqrt(sum / static_cast<double>(c.size()));
}

}  // namespace

TEST(RangeScan, PointsOnTheSurfaceWithNormalsTowardsTheScanners) {
  const TriangleMesh sphere = uv_sphere();
  RangeScanOptions o;
  o.scans = 6;
  o.count = 30000;
  const PointCloud c = scan_surface(sphere, o);
  EXPECT_GT(c.size(), 20000);
  EXPECT_LT(c.size(), 40000);
  ASSERT_EQ(c.normals.rows(), c.size());
  // The facets lie within 1 - cos(π/192) of the sphere; nothing comes from off the surface.
  EXPECT_LT(radial_rms(c), 2e-4);
  // A convex shape seen from outside: every normal points outward, and the grid normals
  // follow the sphere closely. (No ray slips through the mesh between two triangles: rows of
  // the grid run exactly along the sphere's seam.)
  double worst = 1;
  for (Eigen::Index i = 0; i < c.size(); ++i)
    worst = std::min(worst, c.normals.row(i).dot(c.positions.row(i).normalized()));
  EXPECT_GT(worst, 0.9);
  // Each point names the scan that saw it, in scan order, every scan seeing some.
  ASSERT_EQ(c.scanner_of_point.size(), static_cast<std::size_t>(c.size()));
  EXPECT_TRUE(std::is_sorted(c.scanner_of_point.begin(), c.scanner_of_point.end()));
  EXPECT_EQ(c.scanner_of_point.front(), 0u);
  EXPECT_EQ(c.scanner_of_point.back(), 5u);
}

TEST(RangeScan, NoiseAlongTheLineOfSightAndMisregistration) {
  const TriangleMesh sphere = uv_sphere();
  const double diagonal = 2 * std::sqrt(3.0);
  RangeScanOptions o;
  o.scans = 6;
  o.count = 30000;
  o.noise = 0.001;
  // Range noise σ along rays that meet the sphere at up to 80°: radial deviations between
  // σ cos 80° and σ, most near σ (returns face the scanner).
  const double noisy = radial_rms(scan_surface(sphere, o));
  EXPECT_GT(noisy, 0.5 * o.noise * diagonal);
  EXPECT_LT(noisy, 1.05 * o.noise * diagonal);
  // Each scan moved rigidly: the scans no longer lie on one sphere.
  o.noise = 0;
  o.registration = 0.002;
  const double moved = radial_rms(scan_surface(sphere, o));
  EXPECT_GT(moved, 0.2 * o.registration * diagonal);
  EXPECT_LT(moved, 3 * o.registration * diagonal);
}

TEST(RangeScan, OcclusionLeavesHolesWhereNoScannerSees) {
  // Two spheres, one inside the other: the inner one is never seen.
  TriangleMesh two = uv_sphere(32, 64);
  const TriangleMesh inner = uv_sphere(32, 64);
  const Eigen::Index nv = two.vertices.rows(), nt = two.triangles.rows();
  two.vertices.conservativeResize(2 * nv, 3);
  two.triangles.conservativeResize(2 * nt, 3);
  two.vertices.bottomRows(nv) = 0.5 * inner.vertices;
  two.triangles.bottomRows(nt) = inner.triangles.array() + static_cast<std::int32_t>(nv);
  RangeScanOptions o;
  o.count = 5000;
  const PointCloud c = scan_surface(two, o);
  EXPECT_GT(c.positions.rowwise().norm().minCoeff(), 0.9);
}

TEST(RangeScan, SamePointsForAnySeedRunAndThreadCount) {
  const TriangleMesh sphere = uv_sphere(32, 64);
  RangeScanOptions o;
  o.count = 5000;
  o.noise = 0.001;
  o.registration = 0.001;
  const PointCloud a = scan_surface(sphere, o);
  PointCloud b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    b = scan_surface(sphere, o);
  }
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  o.seed = 2;
  EXPECT_NE(scan_surface(sphere, o).positions, a.positions);
}

TEST(RangeScan, FlippedNormalsAreAShareOfTheReturnsAndNothingElseChanges) {
  const TriangleMesh sphere = uv_sphere();
  RangeScanOptions o;
  o.scans = 4;
  o.count = 20000;
  const PointCloud straight = scan_surface(sphere, o);
  o.flipped_normals = 0.1;
  const PointCloud flipped = scan_surface(sphere, o);
  ASSERT_EQ(flipped.size(), straight.size());
  EXPECT_EQ(flipped.positions, straight.positions);
  Eigen::Index away = 0;
  for (Eigen::Index i = 0; i < flipped.size(); ++i) {
    const bool same = flipped.normals.row(i) == straight.normals.row(i);
    const bool negated = flipped.normals.row(i) == -straight.normals.row(i);
    EXPECT_TRUE(same || negated) << "return " << i;
    away += negated;
  }
  // 10 % of about 20,000 draws: within 5 standard deviations (about 2 %).
  const double share = static_cast<double>(away) / static_cast<double>(flipped.size());
  EXPECT_NEAR(share, 0.1, 0.02);
}

/// The range errors of a noisy scan of the unit sphere against the same scan without noise
/// (the same returns, in the same order): their mean square over σ², and the mean product of
/// consecutive returns of a grid row over their mean square (the lag-one correlation).
std::pair<double, double> range_error_statistics(double sigma, double correlation) {
  const TriangleMesh sphere = uv_sphere(64, 128);
  RangeScanOptions o;
  o.scans = 1;
  o.count = 40000;
  const PointCloud clean = scan_surface(sphere, o);
  o.noise = sigma;
  o.noise_correlation = correlation;
  const PointCloud noisy = scan_surface(sphere, o);
  EXPECT_EQ(noisy.size(), clean.size());
  const double diagonal = 2 * std::sqrt(3.0);
  double squares = 0, products = 0;
  Eigen::Index pairs = 0;
  for (Eigen::Index i = 0; i < clean.size(); ++i) {
    const Eigen::Vector3d e = (noisy.positions.row(i) - clean.positions.row(i)).transpose();
    squares += e.squaredNorm();
    // The next return in the same row lies about one grid step away (the rays are near parallel,
    // so the product of the errors is that of the range errors).
    if (i + 1 < clean.size() && (clean.positions.row(i + 1) - clean.positions.row(i)).norm() < 0.05) {
      products += e.dot((noisy.positions.row(i + 1) - clean.positions.row(i + 1)).transpose());
      ++pairs;
    }
  }
  const double mean_square = squares / static_cast<double>(clean.size());
  std::cout << "correlation " << correlation << ": mean square " << mean_square / (sigma * diagonal * sigma * diagonal)
            << " of sigma squared, lag-one correlation " << products / static_cast<double>(pairs) / mean_square
            << " over " << pairs << " pairs\n";
  return {mean_square / (sigma * diagonal * sigma * diagonal), products / static_cast<double>(pairs) / mean_square};
}

TEST(RangeScan, CorrelatedNoiseKeepsItsSpreadAndFollowsTheGrid) {
  // Independent noise: σ² per return, no correlation between neighbours. Smoothed over 2 grid
  // steps: the same σ², and neighbours correlated as Gaussian-smoothed white noise is at one
  // step, exp(−1 / (4 · 2²)) = 0.94.
  const auto [independent_spread, independent_correlation] = range_error_statistics(0.002, 0);
  EXPECT_NEAR(independent_spread, 1, 0.05);
  EXPECT_NEAR(independent_correlation, 0, 0.05);
  const auto [spread, correlation] = range_error_statistics(0.002, 2);
  EXPECT_NEAR(spread, 1, 0.15);
  EXPECT_NEAR(correlation, std::exp(-1.0 / 16), 0.03);
}

TEST(RangeScan, RejectsBadOptions) {
  const TriangleMesh sphere = uv_sphere(8, 16);
  for (auto bad : std::initializer_list<void (*)(RangeScanOptions&)>{
           [](RangeScanOptions& o) { o.scans = 0; }, [](RangeScanOptions& o) { o.count = 0; },
           [](RangeScanOptions& o) { o.distance = 0.2; }, [](RangeScanOptions& o) { o.noise = -1; },
           [](RangeScanOptions& o) { o.registration = std::nan(""); },
           [](RangeScanOptions& o) { o.max_incidence_degrees = 0; },
           [](RangeScanOptions& o) { o.flipped_normals = 1.5; },
           [](RangeScanOptions& o) { o.flipped_normals = std::nan(""); },
           [](RangeScanOptions& o) { o.noise_correlation = -1; },
           [](RangeScanOptions& o) { o.noise_correlation = std::nan(""); },
           [](RangeScanOptions& o) { o.noise_correlation = 1000; }}) {
    RangeScanOptions o;
    bad(o);
    EXPECT_THROW(scan_surface(sphere, o), OptionError);
  }
  EXPECT_THROW(scan_surface(TriangleMesh{}, {}), OptionError);
}
