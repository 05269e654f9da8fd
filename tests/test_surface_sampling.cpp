// Area-uniform sampling of meshes: placement, uniformity, noise level, outliers, determinism.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/surface_sampling.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace clustersurf;

namespace {

/// Two triangles in z = 0: a unit right triangle and one with three times its area.
TriangleMesh two_triangles() {
  TriangleMesh m;
  m.vertices.resize(6, 3);
  m.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0,  //
      5, 0, 0, 8, 0, 0, 5, 1, 0;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 3, 4, 5;
  return m;
}

}  // namespace

TEST(SurfaceSampling, PointsLieOnTheTrianglesInProportionToArea) {
  SurfaceSamplingOptions o;
  o.count = 100000;
  const PointCloud c = sample_surface(two_triangles(), o);
  ASSERT_EQ(c.size(), 100000);
  ASSERT_TRUE(c.has_normals());
  std::size_t in_small = 0;
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    const Eigen::Vector3d p = c.positions.row(i).transpose();
    EXPECT_EQ(p.z(), 0.0);
    EXPECT_NEAR(std::abs(c.normals(i, 2)), 1.0, 1e-12);
    if (p.x() <= 1) {
      ++in_small;
      EXPECT_LE(p.x() + p.y(), 1 + 1e-12);
    } else {
      EXPECT_GE(p.x(), 5 - 1e-12);
      EXPECT_LE((p.x() - 5) / 3 + p.y(), 1 + 1e-12);
    }
    EXPECT_GE(p.y(), 0.0);
  }
  // Expected share 1/4; binomial standard deviation ≈ 0.0014.
  EXPECT_NEAR(static_cast<double>(in_small) / 100000.0, 0.25, 0.006);
}

TEST(SurfaceSampling, SameSeedSamePointsOtherSeedOtherPoints) {
  SurfaceSamplingOptions o;
  o.count = 1000;
  const PointCloud a = sample_surface(two_triangles(), o);
  const PointCloud b = sample_surface(two_triangles(), o);
  EXPECT_TRUE(a.positions == b.positions);
  o.seed = 2;
  const PointCloud c = sample_surface(two_triangles(), o);
  EXPECT_FALSE(a.positions == c.positions);
}

TEST(SurfaceSampling, NoiseHasTheRequestedStandardDeviation) {
  const TriangleMesh m = two_triangles();
  SurfaceSamplingOptions o;
  o.count = 50000;
  o.noise = 0.01;
  const PointCloud c = sample_surface(m, o);
  const double diagonal = std::sqrt(8.0 * 8.0 + 1.0);
  double ss = 0;
  for (Eigen::Index i = 0; i < c.size(); ++i) ss += c.positions(i, 2) * c.positions(i, 2);
  EXPECT_NEAR(std::sqrt(ss / 50000.0), 0.01 * diagonal, 0.02 * 0.01 * diagonal);
}

TEST(SurfaceSampling, OutliersComeOnTopInsideTheEnlargedBox) {
  SurfaceSamplingOptions o;
  o.count = 10000;
  o.outliers = 0.01;
  const PointCloud c = sample_surface(two_triangles(), o);
  ASSERT_EQ(c.size(), 10100);
  std::size_t off_plane = 0;
  for (Eigen::Index i = 10000; i < c.size(); ++i) {
    off_plane += c.positions(i, 2) != 0;
    EXPECT_GE(c.positions(i, 0), -0.4 - 1e-12);
    EXPECT_LE(c.positions(i, 0), 8.4 + 1e-12);
    EXPECT_NEAR(c.normals.row(i).norm(), 1.0, 1e-12);
  }
  EXPECT_EQ(off_plane, 0u);  // the box of a planar mesh is flat: outliers stay in its plane
}

TEST(SurfaceSampling, DegenerateInputIsRefused) {
  TriangleMesh m;
  m.vertices.resize(3, 3);
  m.vertices << 0, 0, 0, 1, 1, 1, 2, 2, 2;  // collinear: zero area
  m.triangles.resize(1, 3);
  m.triangles << 0, 1, 2;
  EXPECT_THROW(sample_surface(m), OptionError);
  SurfaceSamplingOptions o;
  o.noise = -1;
  EXPECT_THROW(sample_surface(two_triangles(), o), OptionError);
  m.triangles << 0, 1, 3;
  EXPECT_THROW(sample_surface(m), OptionError);
}
