// The vertices moved onto local fits of the input (src/mesh/vertex_refit.cpp): closer to the
// true surface where the blend errs above the noise (clean and sparse data), where it does not
// the noise left out, sharp edges kept, and the same vertices however the data is numbered.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/mesh/mesh_check.hpp>
#include <clustersurf/mesh/vertex_refit.hpp>
#include <clustersurf/pipeline/option_schema.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// Mean | |v| − 1 | over the mesh's vertices: their distance to the unit sphere.
double sphere_error(const TriangleMesh& mesh) {
  double sum = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) sum += std::abs(mesh.vertices.row(v).norm() - 1);
  return sum / static_cast<double>(std::max<Eigen::Index>(1, mesh.vertices.rows()));
}

/// n points drawn uniformly on the unit sphere, with Gaussian noise of `sigma` on each
/// coordinate and no normals (a scan that gives none).
PointCloud noisy_sphere(int n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, 1);
  PointCloud c;
  c.positions.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d u = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    c.positions.row(i) = (u + sigma * Eigen::Vector3d(g(rng), g(rng), g(rng))).transpose();
  }
  return c;
}

constexpr double kTube = 0.2;

/// Mean distance of the mesh's vertices to the torus of radii 1 and kTube around z.
double torus_error(const TriangleMesh& mesh) {
  double sum = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const Eigen::Vector3d p = mesh.vertices.row(v).transpose();
    sum += std::abs(std::hypot(std::hypot(p.x(), p.y()) - 1, p.z()) - kTube);
  }
  return sum / static_cast<double>(std::max<Eigen::Index>(1, mesh.vertices.rows()));
}

SurfaceMesh meshed(const PointCloud& cloud, std::uint32_t refit_points) {
  ReconstructOptions options;
  options.meshing.refit.points = refit_points;
  // The vertices where the fits put them: these tests measure the vertices' distance, which the
  // chord offset trades for the triangles'.
  options.meshing.refit.chord_offset = false;
  Reconstruction r = reconstruct(cloud, options);
  if (!r.mesh) throw std::runtime_error("no mesh");
  return std::move(*r.mesh);
}

}  // namespace

TEST(VertexRefit, ASparseCleanTorusComesCloser) {
  // A thin torus from few exact points: the leaves hold a dozen points each, a good part of the
  // tube's girth, and their blend, each quadratic extrapolated towards its support's rim, sags
  // between them; a quadratic around each vertex follows the tube. Denser, the blend errs less
  // and less of the moves stands above the fits' own error.
  for (const int n : {1000, 2000}) {
    const PointCloud cloud = test::sample_torus(n, 1.0, kTube);
    const SurfaceMesh blend = meshed(cloud, 0);
    const SurfaceMesh refitted = meshed(cloud, VertexRefitOptions{}.points);
    const double before = torus_error(blend.mesh), after = torus_error(refitted.mesh);
    std::cout << n << " points of a torus, mean distance of the vertices: blend " << before << ", refitted " << after
              << "; share taken " << refitted.refit.mean_share << "\n";
    EXPECT_LT(after, (n == 1000 ? 0.6 : 0.95) * before) << n;
    EXPECT_EQ(refitted.mesh.triangles, blend.mesh.triangles) << n;  // the vertices move, the mesh stays
  }
}

TEST(VertexRefit, NoiseAloneMovesNothingAndTheErrorFallsWithThePoints) {
  // 0.5 % noise: the local fits' moves are the noise's, and the blend already averages it.
  constexpr double kSigma = 0.005;
  double previous = 0;
  for (const int n : {5000, 40000}) {
    const PointCloud cloud = noisy_sphere(n, kSigma, 11);
    const SurfaceMesh blend = meshed(cloud, 0);
    const SurfaceMesh refitted = meshed(cloud, VertexRefitOptions{}.points);
    const double blend_mean = sphere_error(blend.mesh);
    const double mean = sphere_error(refitted.mesh);
    std::cout << n << " noisy points (sigma " << kSigma << "): mean distance blend " << blend_mean << ", refitted "
              << mean << ", share taken " << refitted.refit.mean_share << "\n";
    EXPECT_LT(refitted.refit.mean_share, 0.2) << n;
    EXPECT_LT(mean, 1.02 * blend_mean) << n;
    // Averaged noise: well under the noise itself, and falling as the points grow.
    EXPECT_LT(mean, 0.25 * kSigma) << n;
    if (previous > 0) {
      EXPECT_LT(mean, 0.8 * previous);
    }
    previous = mean;
  }
}

TEST(VertexRefit, AWiderFitIsTakenWhereItAgreesWithTheNarrowOne) {
  // 4,000 points of a thin torus: where the fit over twice the points lies within the narrow
  // fit's confidence interval its smaller variance is taken, and the vertices come closer than
  // the narrow fits alone bring them (under 0.8 of the blend's error; 0.9 with the narrow fits
  // alone); under light noise they come no farther than the blend.
  for (const double sigma : {0.0, 0.001}) {
    PointCloud cloud = test::sample_torus(4000, 1.0, kTube);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g(0, 1);
    if (sigma > 0)
      for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i)
        cloud.positions.row(i) += sigma * Eigen::RowVector3d(g(rng), g(rng), g(rng));
    const SurfaceMesh blend = meshed(cloud, 0);
    const SurfaceMesh refitted = meshed(cloud, VertexRefitOptions{}.points);
    const double before = torus_error(blend.mesh), after = torus_error(refitted.mesh);
    std::cout << "torus, sigma " << sigma << ": mean distance blend " << before << ", refitted " << after << "\n";
    if (sigma == 0)
      EXPECT_LT(after, 0.8 * before);
    else
      EXPECT_LE(after, before);
  }
}

TEST(VertexRefit, ACleanSurfaceIsNotHeldBackByRelief) {
  // 4,000 exact points of a thin torus. The tree reads part of the tube's curvature as noise (a
  // cluster's quadratic leaves relief); the narrowest fits around each vertex leave far less,
  // and with the noise they show the moves are taken almost whole: under half the blend's error
  // (0.72 of it with the tree's noise).
  const PointCloud cloud = test::sample_torus(4000, 1.0, kTube);
  const SurfaceMesh blend = meshed(cloud, 0);
  const SurfaceMesh refitted = meshed(cloud, VertexRefitOptions{}.points);
  const double before = torus_error(blend.mesh), after = torus_error(refitted.mesh);
  std::cout << "clean torus: mean distance blend " << before << ", refitted " << after << ", share taken "
            << refitted.refit.mean_share << "\n";
  EXPECT_LT(after, 0.5 * before);
}

TEST(VertexRefit, SharpEdgesStaySharp) {
  // A cube's faces, sampled exactly: crease leaves hold its edges, and no quadratic rounds them.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  PointCloud cloud;
  constexpr int kPerFace = 2500;
  cloud.positions.resize(6 * kPerFace, 3);
  for (int f = 0; f < 6; ++f)
    for (int i = 0; i < kPerFace; ++i) {
      Eigen::Vector3d p(u(rng), u(rng), u(rng));
      p(f / 2) = f % 2 ? 1.0 : -1.0;
      cloud.positions.row(f * kPerFace + i) = p.transpose();
    }
  const auto cube_distance = [](const TriangleMesh& mesh) {
    double worst = 0;
    for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
      worst = std::max(worst, std::abs(mesh.vertices.row(v).cwiseAbs().maxCoeff() - 1));
    return worst;
  };
  const SurfaceMesh blend = meshed(cloud, 0);
  const SurfaceMesh refitted = meshed(cloud, VertexRefitOptions{}.points);
  std::cout << "cube, largest distance of a vertex to it: blend " << cube_distance(blend.mesh) << ", refitted "
            << cube_distance(refitted.mesh) << "\n";
  EXPECT_LE(cube_distance(refitted.mesh), cube_distance(blend.mesh) * 1.001 + 1e-9);
}

TEST(VertexRefit, TheSameVerticesWhateverTheDataOrder) {
  const PointCloud cloud = test::sample_sphere(1500);
  const ClusterTree tree = reconstruct(cloud,
                                       [] {
                                         ReconstructOptions o;
                                         o.mesh = false;
                                         return o;
                                       }())
                               .tree;
  const ImplicitSurface surface(tree);
  SurfaceMeshOptions plain;
  plain.refit.points = 0;
  const TriangleMesh mesh = mesh_tree(tree, plain).mesh;
  // The data reversed, and the mesh's vertices renumbered (triangles following).
  Points reversed = cloud.positions.colwise().reverse();
  const KdTree forward_index(cloud.positions), reversed_index(reversed);
  TriangleMesh a = mesh, b = mesh;
  const Eigen::Index n = mesh.vertices.rows();
  b.vertices = mesh.vertices.colwise().reverse();
  b.normals = mesh.normals.colwise().reverse();
  for (Eigen::Index t = 0; t < b.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) b.triangles(t, k) = static_cast<std::int32_t>(n - 1 - mesh.triangles(t, k));
  refit_vertices(a, forward_index, surface);
  refit_vertices(b, reversed_index, surface);
  EXPECT_EQ(Points(b.vertices.colwise().reverse()), a.vertices);
}

TEST(VertexRefit, RefusesTooFewPointsNamingTheOption) {
  ReconstructOptions o;
  try {
    set_options(o, {{"refit_points", "3"}});
    FAIL() << "3 points accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "refit_points must be 0 or at least 6 (a quadratic's coefficients), not 3");
  }
  TriangleMesh mesh;
  const PointCloud cloud = test::sample_sphere(100);
  const KdTree index(cloud.positions);
  const ClusterTree tree = reconstruct(cloud).tree;
  EXPECT_THROW(refit_vertices(mesh, index, ImplicitSurface(tree), VertexRefitOptions{5, 2}), OptionError);
}

TEST(VertexRefit, NoMovePushesTheSurfaceThroughAnotherPart) {
  // The default input's 1,839 vertices: the ears are thinner than their spacing, and the fits on
  // one side ask some vertices to move past the mesh of the other side. Those moves are undone:
  // the blend does not intersect itself there, nor does the refitted mesh.
  const auto file = test::default_bunny();
  if (!file) GTEST_SKIP() << "data/bunny.ply is absent: run scripts/setup";
  ReadOptions read;
  read.mesh_samples = 0;
  const PointCloud cloud = read_point_cloud(*file, read);
  const SurfaceMesh blend = meshed(cloud, 0);
  const SurfaceMesh refitted = meshed(cloud, VertexRefitOptions{}.points);
  ASSERT_EQ(find_self_intersections(blend.mesh).count, 0U);
  EXPECT_EQ(find_self_intersections(refitted.mesh).count, 0U);
  // The vertices the moves would not push through are still moved.
  EXPECT_GT(refitted.refit.mean_move, 0.0);
}
