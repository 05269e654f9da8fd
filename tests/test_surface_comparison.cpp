// Point-to-mesh distance and the reconstruction scores, against cases with known answers.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/mesh_distance.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/io/surface_sampling.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// A square [0, 1]² at height z, as two triangles, facing +z.
TriangleMesh square(double z) {
  TriangleMesh m;
  m.vertices.resize(4, 3);
  m.vertices << 0, 0, z, 1, 0, z, 1, 1, z, 0, 1, z;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 0, 2, 3;
  return m;
}

/// Random triangles in the unit cube.
TriangleMesh soup(int triangles, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  TriangleMesh m;
  m.vertices.resize(3 * triangles, 3);
  m.triangles.resize(triangles, 3);
  for (int t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      m.vertices.row(3 * t + k) << u(rng), u(rng), u(rng);
      m.triangles(t, k) = 3 * t + k;
    }
  }
  return m;
}

}  // namespace

TEST(MeshDistance, ClosestPointOnTriangleBeatsEveryPointOfTheTriangle) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 2);
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0.2), c(0.3, 1, -0.1);
  for (int q = 0; q < 200; ++q) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const Eigen::Vector3d x = closest_point_on_triangle(p, a, b, c);
    const double d = (p - x).norm();
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; i + j <= 40; ++j) {
        const Eigen::Vector3d y = a + (b - a) * (i / 40.0) + (c - a) * (j / 40.0);
        ASSERT_LE(d, (p - y).norm() + 1e-12);
      }
  }
}

TEST(MeshDistance, EqualsBruteForceOverAllTriangles) {
  const TriangleMesh m = soup(300, 5);
  const MeshDistance md(m);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (int q = 0; q < 500; ++q) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
      const Eigen::Vector3d x = closest_point_on_triangle(p, m.vertices.row(m.triangles(t, 0)).transpose(),
                                                          m.vertices.row(m.triangles(t, 1)).transpose(),
                                                          m.vertices.row(m.triangles(t, 2)).transpose());
      best = std::min(best, (x - p).squaredNorm());
    }
    const ClosestPoint c = md.closest(p);
    ASSERT_GE(c.triangle, 0);
    EXPECT_EQ(c.distance_squared, best);
    EXPECT_NEAR((c.point - p).squaredNorm(), best, 1e-15);
  }
}

TEST(SurfaceComparison, IdenticalSurfacesScorePerfectly) {
  const TriangleMesh m = square(0);
  ComparisonOptions o;
  o.samples = 20000;
  const SurfaceComparison e = compare_surfaces(m, m, o);
  EXPECT_LT(e.chamfer, 1e-12);
  EXPECT_LT(e.hausdorff, 1e-12);
  EXPECT_NEAR(e.normal_consistency, 1.0, 1e-12);
  for (const FScore& f : e.fscores) EXPECT_EQ(f.fscore, 1.0);
}

TEST(SurfaceComparison, ParallelSquaresAreTheirOffsetApart) {
  const double d = 0.004;
  ComparisonOptions o;
  o.samples = 20000;
  const SurfaceComparison e = compare_surfaces(square(d), square(0), o);
  const double diagonal = std::sqrt(2.0);  // the reference's box is flat
  EXPECT_NEAR(e.diagonal, diagonal, 1e-15);
  EXPECT_NEAR(e.accuracy, d / diagonal, 1e-12);
  EXPECT_NEAR(e.completeness, d / diagonal, 1e-12);
  EXPECT_NEAR(e.chamfer, d / diagonal, 1e-12);
  EXPECT_NEAR(e.hausdorff, d / diagonal, 1e-12);
  EXPECT_NEAR(e.distance_p95, d / diagonal, 1e-12);
  ASSERT_EQ(e.fscores.size(), 2u);
  EXPECT_EQ(e.fscores[0].fscore, 1.0);  // τ = 0.5 % of √2 ≈ 0.0071 > d
  const SurfaceComparison far = compare_surfaces(square(0.02), square(0), o);
  EXPECT_EQ(far.fscores[1].fscore, 0.0);  // τ = 1 % of √2 ≈ 0.014 < 0.02
}

// The 95th percentile is the error of all but the worst 5 % of both sides' samples: a stray flap
// of 2 % of the square's area (1 % of the samples) leaves it at 0 while the Hausdorff distance
// jumps to the flap; one of 20 % (8 % of the samples) raises it to the flap's height.
TEST(SurfaceComparison, NinetyFifthPercentileIgnoresTheWorstFivePercent) {
  const auto with_flap = [](double side) {
    TriangleMesh m = square(0);
    m.vertices.conservativeResize(8, 3);
    m.vertices.bottomRows(4) << 0, 0, 0.3, side, 0, 0.3, side, side, 0.3, 0, side, 0.3;
    m.triangles.conservativeResize(4, 3);
    m.triangles.bottomRows(2) << 4, 5, 6, 4, 6, 7;
    return m;
  };
  ComparisonOptions o;
  o.samples = 40000;
  const double diagonal = std::sqrt(2.0);
  const SurfaceComparison small = compare_surfaces(with_flap(std::sqrt(0.02)), square(0), o);
  EXPECT_LT(small.distance_p95, 1e-12);
  EXPECT_NEAR(small.hausdorff, 0.3 / diagonal, 1e-12);
  const SurfaceComparison large = compare_surfaces(with_flap(std::sqrt(0.2)), square(0), o);
  EXPECT_NEAR(large.distance_p95, 0.3 / diagonal, 1e-12);
}

TEST(SurfaceComparison, NoisyCloudAgainstItsMeshMeasuresTheNoise) {
  const TriangleMesh m = square(0);
  SurfaceSamplingOptions s;
  s.count = 40000;
  s.noise = 0.002;
  s.seed = 4;
  const PointCloud cloud = sample_surface(m, s);
  TriangleMesh as_cloud;
  as_cloud.vertices = cloud.positions;
  ComparisonOptions o;
  o.samples = 40000;
  const SurfaceComparison e = compare_surfaces(as_cloud, m, o);
  // Mean |N(0, σ)| = σ √(2/π); σ = 0.002 of the diagonal.
  EXPECT_NEAR(e.accuracy, 0.002 * std::sqrt(2 / M_PI), 0.03 * 0.002);
  EXPECT_TRUE(std::isnan(e.normal_consistency));  // the cloud has no normals
  EXPECT_EQ(e.reconstruction_topology.triangles, 0u);
}

TEST(SurfaceComparison, FlippedNormalsStillConsistentButTopologyIsReported) {
  TriangleMesh a = square(0);
  a.triangles.col(1).swap(a.triangles.col(2));  // reversed winding: |n·n'| is unchanged
  ComparisonOptions o;
  o.samples = 5000;
  const SurfaceComparison e = compare_surfaces(a, square(0), o);
  EXPECT_NEAR(e.normal_consistency, 1.0, 1e-12);
  EXPECT_EQ(e.reference_topology.boundary_edges, 4u);
  EXPECT_EQ(e.reference_topology.components, 1u);
  EXPECT_FALSE(is_watertight(e.reference_topology));
}

TEST(SurfaceComparison, EmptyInputsAreRefused) {
  EXPECT_THROW(compare_surfaces(TriangleMesh{}, square(0)), OptionError);
  EXPECT_THROW(compare_surfaces(square(0), TriangleMesh{}), OptionError);
}

// Against a scan without a true surface: a flap standing 0.3 above a cloud of spacing 0.01 (30
// spacings) is surface the data does not support, and far_share is its share of the area; the
// square itself lies within a spacing of the points.
TEST(SurfaceComparison, FarShareIsTheSurfaceAwayFromAReferenceCloud) {
  TriangleMesh cloud;
  const int n = 101;
  cloud.vertices.resize(n * n, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) cloud.vertices.row(i * n + j) << i / 100.0, j / 100.0, 0;
  TriangleMesh m = square(0);
  const double side = std::sqrt(0.25);  // a flap of a quarter of the square's area: 20 % of the mesh
  m.vertices.conservativeResize(8, 3);
  m.vertices.bottomRows(4) << 0, 0, 0.3, side, 0, 0.3, side, side, 0.3, 0, side, 0.3;
  m.triangles.conservativeResize(4, 3);
  m.triangles.bottomRows(2) << 4, 5, 6, 4, 6, 7;
  ComparisonOptions o;
  o.samples = 40000;
  const SurfaceComparison e = compare_surfaces(m, cloud, o);
  EXPECT_NEAR(e.reference_spacing, 0.01, 1e-12);
  EXPECT_NEAR(e.far_share, 0.2, 0.01);
  EXPECT_EQ(compare_surfaces(square(0), cloud, o).far_share, 0.0);
  EXPECT_TRUE(std::isnan(compare_surfaces(m, square(0), o).far_share));  // a mesh reference
}

// The rim and the debris of a mesh: a unit square has a boundary of 4 and an area of 1; a speck
// of under 0.1 % of the area beside it is a loose fragment, a second square is not.
TEST(SurfaceComparison, BoundaryLengthAndLooseFragmentsAreReported) {
  const auto with_square = [](double side) {
    TriangleMesh m = square(0);
    m.vertices.conservativeResize(8, 3);
    m.vertices.bottomRows(4) << 2, 0, 0, 2 + side, 0, 0, 2 + side, side, 0, 2, side, 0;
    m.triangles.conservativeResize(4, 3);
    m.triangles.bottomRows(2) << 4, 5, 6, 4, 6, 7;
    return m;
  };
  const MeshTopology one = mesh_topology(square(0));
  EXPECT_NEAR(one.area, 1.0, 1e-12);
  EXPECT_NEAR(one.boundary_length, 4.0, 1e-12);
  EXPECT_EQ(one.small_components, 0u);
  const MeshTopology speck = mesh_topology(with_square(0.01));  // area 1e-4 of 1.0001
  EXPECT_EQ(speck.components, 2u);
  EXPECT_EQ(speck.small_components, 1u);
  EXPECT_NEAR(speck.boundary_length, 4.04, 1e-12);
  const MeshTopology two = mesh_topology(with_square(1));
  EXPECT_EQ(two.components, 2u);
  EXPECT_EQ(two.small_components, 0u);
}

// Surfaces are compared where they are in their files' coordinates, whatever origin each is
// stored relative to: a georeferenced mesh against itself, stored about another origin, is at
// distance zero.
TEST(SurfaceComparison, SurfacesStoredAboutDifferentOriginsCompareInPlace) {
  const Eigen::Vector3d site(636590.49, 849216.55, 400.25);
  TriangleMesh reference = test::icosphere(3);
  reference.origin = site;
  TriangleMesh moved = reference;
  const Eigen::Vector3d other(636000, 849000, 0);
  moved.vertices.rowwise() += (site - other).transpose();
  moved.origin = other;
  ComparisonOptions options;
  options.samples = 20000;
  const SurfaceComparison same = compare_surfaces(moved, reference, options);
  EXPECT_LT(same.chamfer, 1e-9);
  EXPECT_GT(same.fscores.front().fscore, 0.999);
  // A unit sphere moved by δ along z lies δ |cos θ| from itself: δ / 2 on average.
  moved.origin.z() += 0.1;
  EXPECT_NEAR(compare_surfaces(moved, reference, options).chamfer * same.diagonal, 0.05, 0.002);
  moved.origin.z() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(compare_surfaces(moved, reference, options), OptionError);
}
