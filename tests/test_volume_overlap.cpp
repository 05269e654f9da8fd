// The volumetric IoU of two closed meshes, against solids whose overlap is known in closed form.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/evaluation/volume_overlap.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "test_support.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

using namespace clustersurf;

namespace {

/// The volume a closed, outward-facing mesh bounds (divergence theorem).
double enclosed_volume(const TriangleMesh& m) {
  double v = 0;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d a = m.vertices.row(m.triangles(t, 0)), b = m.vertices.row(m.triangles(t, 1)),
                          c = m.vertices.row(m.triangles(t, 2));
    v += a.dot(b.cross(c)) / 6;
  }
  return v;
}

/// The mesh without its triangles whose centroid lies within `angle` of the +z pole.
TriangleMesh without_cap(const TriangleMesh& m, double angle) {
  TriangleMesh out = m;
  Eigen::Index kept = 0;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d c =
        (m.vertices.row(m.triangles(t, 0)) + m.vertices.row(m.triangles(t, 1)) + m.vertices.row(m.triangles(t, 2)))
            .transpose() /
        3;
    if (c.normalized().z() < std::cos(angle)) out.triangles.row(kept++) = m.triangles.row(t);
  }
  out.triangles.conservativeResize(kept, 3);
  return out;
}

}  // namespace

TEST(VolumeOverlap, TwoSpheresOverlapAsTheLensBetweenThemSays) {
  // Unit spheres 0.8 apart: the lens between them holds π (4r + d)(2r − d)² / 12.
  const double d = 0.8;
  const TriangleMesh a = test::icosphere(5), b = test::icosphere(5, 1.0, Eigen::Vector3d(d, 0, 0));
  const double sphere = 4 * std::numbers::pi / 3, lens = std::numbers::pi * (4 + d) * (2 - d) * (2 - d) / 12;
  VolumeOverlapOptions million;
  million.samples = 1'000'000;
  const VolumeOverlap o = volume_overlap(a, b, million);
  EXPECT_NEAR(o.iou, lens / (2 * sphere - lens), 0.004);
  EXPECT_NEAR(o.reconstruction_volume, enclosed_volume(a), 0.01 * enclosed_volume(a));
  EXPECT_NEAR(o.reference_volume, enclosed_volume(b), 0.01 * enclosed_volume(b));
  EXPECT_GE(o.samples, 900'000u);
}

TEST(VolumeOverlap, TheSameSolidIsOneAndSeparateSolidsAreZero) {
  const TriangleMesh a = test::icosphere(3);
  EXPECT_EQ(volume_overlap(a, a).iou, 1.0);
  EXPECT_EQ(volume_overlap(a, test::icosphere(3, 1.0, Eigen::Vector3d(2.5, 0, 0))).iou, 0.0);
}

TEST(VolumeOverlap, MeshesInOtherFramesAreComparedWhereTheyLie) {
  // The same sphere, its vertices stored relative to another origin.
  const TriangleMesh a = test::icosphere(4);
  TriangleMesh b = a;
  b.origin = Eigen::Vector3d(1e6, -2e6, 3e5);
  b.vertices.rowwise() -= b.origin.transpose();
  EXPECT_GT(volume_overlap(b, a).iou, 0.999);
}

TEST(VolumeOverlap, AMissingCapSwaysOneRayNotTheVote) {
  // A cap of about 2 % of the sphere missing: a single ray's parity would call every point whose
  // ray leaves through the opening outside (about 8 % of the ball); the vote of three rays in
  // directions far apart calls outside only the points two of whose rays leave through it.
  const TriangleMesh whole = test::icosphere(5);
  const TriangleMesh open = without_cap(whole, 0.29);
  ASSERT_LT(open.triangles.rows(), whole.triangles.rows() * 99 / 100);
  EXPECT_GT(volume_overlap(open, whole).iou, 0.99);
}

TEST(VolumeOverlap, TheFiguresDoNotDependOnTheThreadCount) {
  const TriangleMesh a = test::icosphere(4), b = test::icosphere(4, 0.9, Eigen::Vector3d(0.3, 0.2, 0.1));
  VolumeOverlapOptions options;
  options.samples = 200'000;
  const VolumeOverlap many = volume_overlap(a, b, options);
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const VolumeOverlap single = volume_overlap(a, b, options);
  EXPECT_EQ(many.iou, single.iou);
  EXPECT_EQ(many.reconstruction_volume, single.reconstruction_volume);
}

TEST(VolumeOverlap, BadMeshesAndNoSamplesAreRefused) {
  const TriangleMesh a = test::icosphere(2);
  TriangleMesh cloud;
  cloud.vertices = a.vertices;
  EXPECT_THROW(volume_overlap(cloud, a), OptionError);
  EXPECT_THROW(volume_overlap(a, cloud), OptionError);
  VolumeOverlapOptions none;
  none.samples = 0;
  EXPECT_THROW(volume_overlap(a, a, none), OptionError);
  TriangleMesh broken = a;
  broken.vertices(3, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(volume_overlap(broken, a), OptionError);
  EXPECT_THROW(volume_overlap(a, broken), OptionError);
  TriangleMesh dangling = a;
  dangling.triangles(0, 2) = static_cast<std::int32_t>(a.vertices.rows());
  EXPECT_THROW(volume_overlap(dangling, a), OptionError);
  dangling.triangles(0, 2) = -1;
  EXPECT_THROW(volume_overlap(a, dangling), OptionError);
}

TEST(VolumeOverlap, AMeshOfDegenerateTrianglesBoundsNothing) {
  // Every vertex at one point: triangles without area, a box without extent.
  TriangleMesh point = test::icosphere(1);
  point.vertices.setZero();
  VolumeOverlapOptions options;
  options.samples = 1000;
  const VolumeOverlap o = volume_overlap(point, test::icosphere(1), options);
  EXPECT_EQ(o.reconstruction_volume, 0.0);
  EXPECT_EQ(o.iou, 0.0);
}

TEST(VolumeOverlap, CompareSurfacesReportsItOnlyForTwoClosedMeshes) {
  const TriangleMesh a = test::icosphere(4), b = test::icosphere(4, 1.0, Eigen::Vector3d(0.5, 0, 0));
  ComparisonOptions options;
  options.samples = 20'000;
  const double iou = compare_surfaces(a, b, options).volume_iou;
  EXPECT_DOUBLE_EQ(iou, volume_overlap(a, b, VolumeOverlapOptions{options.volume_samples, options.seed}).iou);
  EXPECT_TRUE(std::isnan(compare_surfaces(without_cap(a, 0.3), b, options).volume_iou));
  options.volume_samples = 0;
  EXPECT_TRUE(std::isnan(compare_surfaces(a, b, options).volume_iou));
}
