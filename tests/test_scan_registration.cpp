// measure_registration(): two scans of a plane and of a sphere, one moved off the other along
// the normal, measure that move; registered scans measure their noise's share only; scans that
// do not overlap, a single scan and unlabelled points measure nothing; the pipeline reports it.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/spatial/scan_registration.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// `n` points on z = 0 over [0, 1]², every other one from scan 1, which lies `offset` above scan
/// 0; Gaussian noise of `sigma` along z.
PointCloud two_scans_of_a_plane(int n, double offset, double sigma, std::uint32_t seed = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> noise(0, sigma > 0 ? sigma : 1);
  PointCloud c;
  c.positions.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const std::uint32_t scan = static_cast<std::uint32_t>(i % 2);
    c.positions.row(i) << u(rng), u(rng), scan * offset + (sigma > 0 ? noise(rng) : 0.0);
    c.scanner_of_point.push_back(scan);
  }
  return c;
}

ScanRegistration measured(const PointCloud& c) { return measure_registration(c, KdTree(c.positions)); }

}  // namespace

TEST(ScanRegistration, ScansMovedAlongTheNormalMeasureTheMove) {
  for (const double offset : {0.002, 0.01}) {
    const ScanRegistration r = measured(two_scans_of_a_plane(20000, offset, 0));
    EXPECT_EQ(r.scans, 2u);
    EXPECT_GT(r.overlaps, 15000u);
    EXPECT_NEAR(r.median_offset, offset, 0.02 * offset);
    EXPECT_NEAR(r.rms_offset, offset, 0.02 * offset);
  }
  // Two scans of a unit sphere, the second 0.01 farther out: curved, still the move.
  PointCloud sphere = test::sample_sphere(30000, 1.0);
  for (Eigen::Index i = 0; i < sphere.size(); ++i) {
    const std::uint32_t scan = static_cast<std::uint32_t>(i % 2);
    if (scan == 1) sphere.positions.row(i) *= 1.01;
    sphere.scanner_of_point.push_back(scan);
  }
  const ScanRegistration r = measured(sphere);
  EXPECT_NEAR(r.median_offset, 0.01, 0.001);
}

// Registered scans under noise σ measure the noise of a mean over a few points, well under σ.
TEST(ScanRegistration, RegisteredScansMeasureOnlyTheirNoise) {
  const double sigma = 0.002;
  const ScanRegistration r = measured(two_scans_of_a_plane(20000, 0, sigma));
  EXPECT_GT(r.overlaps, 15000u);
  EXPECT_LT(r.median_offset, 0.5 * sigma);
  const ScanRegistration moved = measured(two_scans_of_a_plane(20000, 4 * sigma, sigma));
  EXPECT_NEAR(moved.median_offset, 4 * sigma, sigma);
}

TEST(ScanRegistration, NothingToMeasureWithoutOverlappingScans) {
  PointCloud halves = two_scans_of_a_plane(20000, 0, 0);
  for (Eigen::Index i = 0; i < halves.size(); ++i)
    halves.scanner_of_point[static_cast<std::size_t>(i)] = halves.positions(i, 0) < 0.5 ? 0 : 1;
  const ScanRegistration apart = measured(halves);
  EXPECT_EQ(apart.scans, 2u);
  EXPECT_LT(apart.overlaps, 1000u);  // only along the seam
  PointCloud one = two_scans_of_a_plane(5000, 0.01, 0);
  std::fill(one.scanner_of_point.begin(), one.scanner_of_point.end(), 7u);
  EXPECT_EQ(measured(one).scans, 1u);
  EXPECT_EQ(measured(one).overlaps, 0u);
  one.scanner_of_point.clear();
  EXPECT_EQ(measured(one).overlaps, 0u);
  RegistrationOptions bad;
  bad.min_points = 2;
  EXPECT_THROW(measure_registration(one, KdTree(one.positions), bad), OptionError);
}

TEST(ScanRegistration, ThePipelineReportsIt) {
  const PointCloud c = two_scans_of_a_plane(20000, 0.004, 0.0005);
  ReconstructOptions options;
  options.mesh = false;
  const Reconstruction r = reconstruct(c, options);
  EXPECT_EQ(r.registration.scans, 2u);
  EXPECT_NEAR(r.registration.median_offset, 0.004, 0.001);
  EXPECT_EQ(reconstruct(test::sample_sphere(3000), options).registration.scans, 0u);
}
