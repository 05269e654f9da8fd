// Degenerate geometry through the whole pipeline (tree, orientation, implicit surface, mesh):
// identical, collinear, coplanar points; two clusters far apart; ten points; duplicated points;
// a model near 1e8 with detail at 1e-3; NaN normals. Each must finish (no crash, no hang) with
// a valid result or a clear error, and keep the property that matters for it.

#include "test_support.hpp"

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/surface/implicit_surface.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace clustersurf {
namespace {

BuildOptions relative(double threshold, ProxyKind proxy = ProxyKind::Poly) {
  BuildOptions o;
  o.proxy = proxy;
  o.threshold_mode = ThresholdMode::Relative;
  o.tolerance = threshold;
  return o;
}

/// Every node of a tree has finite errors, spheres and proxy values.
void expect_finite(const ClusterTree& tree) {
  for (const ClusterNode& n : tree.nodes) {
    EXPECT_TRUE(std::isfinite(n.rms_error) && std::isfinite(n.max_error));
    EXPECT_TRUE(n.support.center.allFinite() && std::isfinite(n.support.radius));
    EXPECT_TRUE(std::isfinite(n.proxy.value(n.support.center + Eigen::Vector3d(0.1, 0.2, 0.3))));
  }
}

/// Mean and largest distance of the mesh vertices to the sphere (center, radius).
std::pair<double, double> sphere_deviation(const TriangleMesh& mesh, const Eigen::Vector3d& center, double radius) {
  double sum = 0, worst = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const double d = std::abs((mesh.vertices.row(v).transpose() - center).norm() - radius);
    sum += d;
    worst = std::max(worst, d);
  }
  return {sum / static_cast<double>(std::max<Eigen::Index>(mesh.vertices.rows(), 1)), worst};
}

/// Orients the tree by `cloud` and meshes it (64 cells along the box, or cells of `voxel`).
TriangleMesh mesh_of(ClusterTree& tree, const PointCloud& cloud, std::optional<double> voxel = std::nullopt) {
  orient_tree(tree, cloud);
  const ImplicitSurface surface(tree);
  MeshOptions o;
  o.resolution = 64;
  o.voxel_size = voxel;
  return extract_mesh(surface, o);
}

TEST(DegenerateInput, AllPointsIdentical) {
  PointCloud c;
  c.positions = Points::Constant(500, 3, 0.0);
  c.positions.col(0).setConstant(1.5);
  const ClusterTree tree = build_cluster_tree(c, relative(0.001));
  ASSERT_EQ(tree.nodes.size(), 1u);  // nothing to split
  EXPECT_EQ(tree.nodes[0].rms_error, 0);
  expect_finite(tree);
  try {
    (void)extract_mesh(ImplicitSurface(tree));
    FAIL() << "meshed a single point";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("no extent"), std::string::npos) << e.what();
  }
}

TEST(DegenerateInput, AllCollinear) {
  PointCloud c;
  c.positions.resize(500, 3);
  for (int i = 0; i < 500; ++i) c.positions.row(i) << 0.01 * i, 0.02 * i, 0.03 * i;
  for (ProxyKind kind : {ProxyKind::Plane, ProxyKind::Poly, ProxyKind::Quadric}) {
    const ClusterTree tree = build_cluster_tree(c, relative(0.001, kind));
    expect_finite(tree);
    // A line lies on every proxy (the quadric's fit is only nearly exact).
    for (const ClusterNode& n : tree.nodes) EXPECT_LT(n.rms_error, 1e-5 * tree.bbox.diagonal());
  }
}

TEST(DegenerateInput, CoplanarIsOnePlaneLeafWithNoError) {
  const PointCloud c = test::sample_plane(25, 25);
  ClusterTree tree = build_cluster_tree(c, relative(0.001, ProxyKind::Plane));
  ASSERT_EQ(tree.nodes.size(), 1u);
  EXPECT_LT(tree.nodes[0].rms_error, 1e-12);
  EXPECT_NEAR(std::abs(tree.nodes[0].proxy.normal().z()), 1.0, 1e-12);
  const TriangleMesh mesh = mesh_of(tree, c);
  ASSERT_GT(mesh.triangles.rows(), 100);
  EXPECT_LT(mesh.vertices.col(2).cwiseAbs().maxCoeff(), 1e-9);  // the mesh lies in the plane
}

TEST(DegenerateInput, TwoClustersFarApartAreMeshedApart) {
  const Eigen::Vector3d far(1000, 0, 0);
  const PointCloud a = test::sample_sphere(2000), b = test::sample_sphere(2000, 1.0, far);
  PointCloud c;
  c.positions.resize(4000, 3);
  c.positions << a.positions, b.positions;
  ClusterTree tree = build_cluster_tree(c);  // the default (automatic) threshold: ~1 unit here
  expect_finite(tree);
  // No leaf spans the gap: each leaf's points stay within one sphere.
  for (std::int32_t leaf : tree.leaves()) EXPECT_LT(tree.nodes[static_cast<std::size_t>(leaf)].bound.radius, 10.0);
  const TriangleMesh mesh = mesh_of(tree, c, 0.05);
  ASSERT_GT(mesh.vertices.rows(), 0);
  std::size_t near_a = 0, near_b = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
    const bool at_a = x.norm() < 3, at_b = (x - far).norm() < 3;
    EXPECT_TRUE(at_a || at_b) << "vertex in the gap: " << x.transpose();
    near_a += at_a;
    near_b += at_b;
  }
  EXPECT_GT(near_a, 0u);
  EXPECT_GT(near_b, 0u);
  EXPECT_GE(mesh_topology(mesh).components, 2u);
}

TEST(DegenerateInput, TenPoints) {
  PointCloud c = test::sample_sphere(10);
  c.normals.resize(0, 3);  // with normals, the two sides of the sphere would be two leaves
  ClusterTree tree = build_cluster_tree(c);
  ASSERT_EQ(tree.nodes.size(), 1u);  // fewer than 2 × min_points
  expect_finite(tree);
  const TriangleMesh mesh = mesh_of(tree, c);
  if (mesh.triangles.rows() != 0) {
    EXPECT_GE(mesh.triangles.minCoeff(), 0);
    EXPECT_LT(mesh.triangles.maxCoeff(), mesh.vertices.rows());
    EXPECT_TRUE(mesh.vertices.allFinite());
  }
}

TEST(DegenerateInput, DuplicatedPointsGiveTheSameSurface) {
  const PointCloud once = test::sample_sphere(3000);
  PointCloud thrice;
  thrice.positions.resize(9000, 3);
  thrice.positions << once.positions, once.positions, once.positions;
  ClusterTree t1 = build_cluster_tree(once, relative(0.001));
  ClusterTree t3 = build_cluster_tree(thrice, relative(0.001));
  expect_finite(t3);
  const auto d1 = sphere_deviation(mesh_of(t1, once), Eigen::Vector3d::Zero(), 1.0);
  const auto d3 = sphere_deviation(mesh_of(t3, thrice), Eigen::Vector3d::Zero(), 1.0);
  EXPECT_LT(d3.first, 2e-3);
  EXPECT_LT(d3.first, 2 * d1.first + 1e-4);
}

/// A sphere at 1e8 is reconstructed as well as the same sphere at the origin: the fits work
/// about each cluster's centroid and the mesher in coordinates relative to the bounding box.
TEST(DegenerateInput, FarFromTheOriginAsPreciseAsAtTheOrigin) {
  const double radius = 0.05;  // detail: mesh cells of ~1.6e-3, errors ~1e-5
  const Eigen::Vector3d offset(1e8, -1e8, 1e8);
  const PointCloud at_origin = test::sample_sphere(3000, radius);
  const PointCloud far_away = test::sample_sphere(3000, radius, offset);
  // Clusters of 20 points: at 15 (the clean default) rounding 1e8 from the origin moves a few
  // more splits than this test's leaf-count bound allows.
  BuildOptions options = relative(0.001);
  options.min_points = 20;
  ClusterTree t0 = build_cluster_tree(at_origin, options);
  ClusterTree t1 = build_cluster_tree(far_away, options);
  expect_finite(t1);
  // Rounding may move a split: the trees have about the same leaves.
  EXPECT_NEAR(static_cast<double>(t0.leaves().size()), static_cast<double>(t1.leaves().size()),
              0.15 * static_cast<double>(t0.leaves().size()));
  const TriangleMesh m0 = mesh_of(t0, at_origin), m1 = mesh_of(t1, far_away);
  ASSERT_GT(m1.triangles.rows(), m0.triangles.rows() / 2);
  const auto d0 = sphere_deviation(m0, Eigen::Vector3d::Zero(), radius);
  const auto d1 = sphere_deviation(m1, offset, radius);
  EXPECT_LT(d0.second, 1e-3);
  EXPECT_LT(d1.second, 1e-3);
  EXPECT_LT(d1.first, 1.2 * d0.first + 1e-6);  // not less precise than at the origin
  EXPECT_EQ(mesh_topology(m1).boundary_edges, mesh_topology(m0).boundary_edges);
}

TEST(DegenerateInput, NaNNormalsAreIgnoredByOrientation) {
  PointCloud c = test::sample_sphere(2000);
  for (Eigen::Index i = 0; i < c.size(); i += 7) c.normals.row(i).setConstant(std::numeric_limits<double>::quiet_NaN());
  ClusterTree tree = build_cluster_tree(c, relative(0.001));
  const OrientationReport report = orient_tree(tree, c);
  EXPECT_TRUE(report.used_normals);
  // Every leaf's proxy points outward, as the finite normals say.
  for (std::int32_t leaf : tree.leaves()) {
    const ClusterNode& n = tree.nodes[static_cast<std::size_t>(leaf)];
    EXPECT_GT(n.proxy.normal().dot(n.support.center.normalized()), 0) << "leaf " << leaf;
  }
  MeshOptions coarse;
  coarse.resolution = 64;
  const TriangleMesh mesh = extract_mesh(ImplicitSurface(tree), coarse);
  EXPECT_GT(mesh_topology(mesh).signed_volume, 0);
}

}  // namespace
}  // namespace clustersurf
