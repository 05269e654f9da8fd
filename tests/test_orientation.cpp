// Orientation: by normals, and by propagation on the bunny with its normals stripped.

#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <array>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// Agreement of leaf proxies with true normals. A leaf whose points have no common true
/// orientation (|mean normal| < 0.5: a cluster straddling both sides of a part thinner than
/// the sampling, like the ears of the 1,839-point bunny) gives no orientation to agree with;
/// such leaves are counted apart.
struct Agreement {
  double leaves = 0;  ///< share of oriented leaves that agree
  double points = 0;  ///< share of their points
  std::size_t straddling = 0;
};

Agreement agreement(const ClusterTree& t, const Points& normals) {
  std::vector<Eigen::Vector3d> sum(t.nodes.size(), Eigen::Vector3d::Zero());
  for (std::size_t p = 0; p < t.point_leaf.size(); ++p)
    sum[static_cast<std::size_t>(t.point_leaf[p])] += normals.row(static_cast<Eigen::Index>(p)).transpose();
  Agreement a;
  std::size_t ok = 0, oriented = 0;
  double ok_points = 0, oriented_points = 0;
  for (auto i : t.leaves()) {
    const auto& n = t.nodes[static_cast<std::size_t>(i)];
    if (sum[static_cast<std::size_t>(i)].norm() < 0.5 * n.point_count) {
      ++a.straddling;
      continue;
    }
    ++oriented;
    oriented_points += n.point_count;
    if (n.proxy.normal().dot(sum[static_cast<std::size_t>(i)]) > 0) ++ok, ok_points += n.point_count;
  }
  a.leaves = static_cast<double>(ok) / static_cast<double>(oriented);
  a.points = ok_points / oriented_points;
  return a;
}

}  // namespace

TEST(Orientation, FollowsInputNormals) {
  const PointCloud c = test::sample_torus(20000);
  ClusterTree t = build_cluster_tree(c, {});
  const OrientationReport r = orient_tree(t, c);
  EXPECT_TRUE(r.used_normals);
  EXPECT_EQ(agreement(t, c.normals).leaves, 1.0);
}

TEST(Orientation, PropagationOrientsSphereAndTorus) {
  for (const PointCloud& c : {test::sample_sphere(20000), test::sample_torus(20000)}) {
    PointCloud stripped;
    stripped.positions = c.positions;
    for (const PointCloud* given : std::array<const PointCloud*, 2>{&stripped, nullptr}) {
      // With the points (cluster adjacency) and without (support overlap).
      ClusterTree t = build_cluster_tree(c, {});
      const OrientationReport r = orient_tree(t, given != nullptr ? *given : PointCloud{});
      EXPECT_FALSE(r.used_normals);
      EXPECT_EQ(r.components, 1u);
      EXPECT_EQ(agreement(t, c.normals).leaves, 1.0);
    }
  }
}

TEST(Orientation, BunnyWithNormalsStrippedAgreesWithTrueNormals) {
  const auto file = test::default_bunny();
  if (!file) GTEST_SKIP() << "data/bunny.ply is absent: run scripts/setup";
  const TriangleMesh mesh = read_triangle_mesh(*file);
  const Points truth = vertex_normals(mesh);  // a closed outward mesh: the true normals
  PointCloud cloud;
  cloud.positions = mesh.vertices;  // no normals
  for (double threshold : {0.001, 0.0005}) {
    BuildOptions o;
    o.threshold_mode = ThresholdMode::Relative;
    o.tolerance = threshold;
    o.min_points = 10;
    ClusterTree t = build_cluster_tree(cloud, o);
    orient_tree(t, cloud);
    const Agreement a = agreement(t, truth);
    std::cout << "bunny, threshold " << threshold << ": " << t.leaves().size() << " leaves (" << a.straddling
              << " straddling a thin part), " << 100 * a.leaves << " % of the others agree with the true normals\n";
    EXPECT_GE(a.leaves, 0.99);
    EXPECT_LE(a.straddling, t.leaves().size() / 8);
  }
}

TEST(Orientation, ScannedBunnyWithNormalsStripped) {
  const auto file = test::shared_data("bunny/bunny_scans_aligned.ply");
  if (!file) GTEST_SKIP() << "../shared/data/bunny/bunny_scans_aligned.ply is absent";
  const PointCloud full = read_point_cloud(*file);
  PointCloud stripped;
  stripped.positions = full.positions;
  ClusterTree t = build_cluster_tree(stripped, {});
  orient_tree(t, stripped);
  const Agreement a = agreement(t, full.normals);
  std::cout << "bunny scans: " << t.leaves().size() << " leaves (" << a.straddling << " straddling), " << 100 * a.leaves
            << " % of the others agree with the scanner normals, " << 100 * a.points << " % of their points\n";
  EXPECT_GE(a.leaves, 0.98);
  EXPECT_GE(a.points, 0.99);
}

// Without normals but with the scanners' positions (PTX, E57, PCD viewpoints), each leaf faces
// the scanner that saw its points: a plane seen from above faces up, the same plane seen from
// below faces down (propagation cannot tell the two apart), and a sphere seen by six scanners
// around it faces out.
TEST(Orientation, TowardsTheScanners) {
  for (const double side : {1.0, -1.0}) {
    PointCloud c = test::sample_plane(60, 60);
    c.normals.resize(0, 3);
    c.scanner_positions = Points(1, 3);
    c.scanner_positions << 0.3, 0.6, 2.0 * side;
    c.scanner_of_point.assign(static_cast<std::size_t>(c.size()), 0);
    ClusterTree t = build_cluster_tree(c, {});
    const OrientationReport r = orient_tree(t, c);
    EXPECT_TRUE(r.used_scanners);
    for (auto i : t.leaves())
      EXPECT_GT(side * t.nodes[static_cast<std::size_t>(i)].proxy.normal().z(), 0) << "leaf " << i;
  }
  const PointCloud sphere = test::sample_sphere(20000);
  PointCloud seen;
  seen.positions = sphere.positions;
  seen.scanner_positions = Points(6, 3);
  seen.scanner_positions << 5, 0, 0, -5, 0, 0, 0, 5, 0, 0, -5, 0, 0, 0, 5, 0, 0, -5;
  // Each point is seen by the scanner facing it most squarely (a scanner sees the front only).
  for (Eigen::Index p = 0; p < sphere.size(); ++p) {
    Eigen::Index best = 0;
    Eigen::VectorXd facing = (seen.scanner_positions.rowwise() - sphere.positions.row(p)).rowwise().normalized() *
                             sphere.normals.row(p).transpose();
    facing.maxCoeff(&best);
    seen.scanner_of_point.push_back(static_cast<std::uint32_t>(best));
  }
  ClusterTree t = build_cluster_tree(seen, {});
  EXPECT_TRUE(orient_tree(t, seen).used_scanners);
  EXPECT_EQ(agreement(t, sphere.normals).leaves, 1.0);
}
