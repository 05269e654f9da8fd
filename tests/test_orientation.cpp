// Orientation: by normals, and by propagation on the bunny with its normals stripped.

#include <clustersurf/orientation.hpp>
#include <clustersurf/point_cloud_io.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// Area-weighted vertex normals of a closed outward mesh: the true normals.
Points vertex_normals(const TriangleMesh& m) {
  Points n = Points::Zero(m.vertices.rows(), 3);
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    const Eigen::Vector3d a = m.vertices.row(m.triangles(f, 0)).transpose();
    const Eigen::Vector3d b = m.vertices.row(m.triangles(f, 1)).transpose();
    const Eigen::Vector3d c = m.vertices.row(m.triangles(f, 2)).transpose();
    const Eigen::Vector3d fn = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) n.row(m.triangles(f, k)) += fn.transpose();
  }
  n.rowwise().normalize();
  return n;
}

/// Share of leaves whose proxy normal agrees with the mean true normal of their points.
double agreement(const ClusterTree& t, const Points& normals) {
  std::vector<Eigen::Vector3d> sum(t.nodes.size(), Eigen::Vector3d::Zero());
  for (std::size_t p = 0; p < t.point_leaf.size(); ++p)
    sum[static_cast<std::size_t>(t.point_leaf[p])] += normals.row(static_cast<Eigen::Index>(p)).transpose();
  const auto leaves = t.leaves();
  std::size_t ok = 0;
  for (auto i : leaves) ok += t.nodes[static_cast<std::size_t>(i)].proxy.normal().dot(sum[static_cast<std::size_t>(i)]) > 0;
  return static_cast<double>(ok) / static_cast<double>(leaves.size());
}

}  // namespace

TEST(Orientation, FollowsInputNormals) {
  const PointCloud c = test::sample_torus(20000);
  ClusterTree t = build_cluster_tree(c, {});
  const OrientationReport r = orient_tree(t, c);
  EXPECT_TRUE(r.used_normals);
  EXPECT_EQ(agreement(t, c.normals), 1.0);
}

TEST(Orientation, PropagationOrientsSphereAndTorus) {
  for (const PointCloud& c : {test::sample_sphere(20000), test::sample_torus(20000)}) {
    ClusterTree t = build_cluster_tree(c, {});
    const OrientationReport r = orient_tree(t, PointCloud{});
    EXPECT_FALSE(r.used_normals);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(agreement(t, c.normals), 1.0);
  }
}

TEST(Orientation, BunnyWithNormalsStrippedAgreesWithTrueNormals) {
  const auto file = test::default_bunny();
  if (!file) GTEST_SKIP() << "data/bunny.ply is absent: run scripts/setup";
  const TriangleMesh mesh = read_triangle_mesh(*file);
  const Points truth = vertex_normals(mesh);
  PointCloud cloud;
  cloud.positions = mesh.vertices;  // no normals
  for (double threshold : {0.001, 0.0005}) {
    BuildOptions o;
    o.threshold_mode = ThresholdMode::Relative;
    o.threshold = threshold;
    o.min_points = 10;
    ClusterTree t = build_cluster_tree(cloud, o);
    orient_tree(t, cloud);
    const double share = agreement(t, truth);
    std::cout << "bunny, threshold " << threshold << ": " << t.leaves().size() << " leaves, " << 100 * share
              << " % agree with the true normals\n";
    EXPECT_GE(share, 0.99);
  }
}

TEST(Orientation, ScannedBunnyWithNormalsStripped) {
  const auto file = test::shared_data("bunny/bunny_scans_aligned.ply");
  if (!file) GTEST_SKIP() << "../shared/data/bunny/bunny_scans_aligned.ply is absent";
  const PointCloud full = read_point_cloud(*file);
  ClusterTree t = build_cluster_tree(full, {});
  orient_tree(t, PointCloud{});
  const double share = agreement(t, full.normals);
  std::cout << "bunny scans: " << t.leaves().size() << " leaves, " << 100 * share << " % agree with the scanner normals\n";
  EXPECT_GE(share, 0.99);
}
