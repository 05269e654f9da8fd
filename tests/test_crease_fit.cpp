// Crease leaves (src/cluster/crease_fit.cpp): the builder fits the two planes of a sharp edge
// and refuses what is not one; a sampled cube reconstructed with crease leaves keeps its edges
// within a small bound of the true ones, where smooth leaves round them off.

#include <clustersurf/pipeline/reconstruct.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// The tree of `points` (no normals, no noise estimate: the tolerance alone decides).
ClusterTree tree_of(const Points& points, bool creases = true) {
  PointCloud c;
  c.positions = points;
  BuildOptions o;
  o.threshold_mode = ThresholdMode::Relative;
  o.creases = creases;
  return build_cluster_tree(c, o);
}

/// Points on the two faces z = −slope·|x| of a roof along y, |x|, |y| ≤ 1.
Points roof(int n, double slope) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  Points p(n, 3);
  for (int i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    p.row(i) << x, y, -slope * std::abs(x);
  }
  return p;
}

/// About n points on the surface of the cube [-1, 1]³ (a grid on each face), outward normals.
PointCloud cube(int per_side) {
  PointCloud c;
  const int n = 6 * per_side * per_side;
  c.positions.resize(n, 3);
  c.normals.resize(n, 3);
  int k = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {-1.0, 1.0})
      for (int i = 0; i < per_side; ++i)
        for (int j = 0; j < per_side; ++j) {
          Eigen::Vector3d x;
          x[axis] = side;
          x[(axis + 1) % 3] = -1 + 2 * (i + 0.5) / per_side;
          x[(axis + 2) % 3] = -1 + 2 * (j + 0.5) / per_side;
          c.positions.row(k) = x.transpose();
          c.normals.row(k) = side * Eigen::RowVector3d::Unit(axis);
          ++k;
        }
  return c;
}

/// Distance from x to the surface of the cube [-1, 1]³.
double cube_distance(const Eigen::Vector3d& x) {
  const Eigen::Vector3d q = x.cwiseAbs() - Eigen::Vector3d::Ones();
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

}  // namespace

TEST(CreaseFit, RecoversTheTwoFacesOfAnEdge) {
  for (double slope : {0.3, 0.8}) {
    // One crease leaf holds the whole roof; smooth leaves need many to meet the tolerance.
    const ClusterTree t = tree_of(roof(400, slope));
    ASSERT_EQ(t.nodes.size(), 1u) << "slope " << slope;
    ASSERT_EQ(t.nodes[0].proxy.kind(), ProxyKind::Crease) << "slope " << slope;
    EXPECT_LT(t.nodes[0].max_error, 1e-9) << "slope " << slope;
    EXPECT_GT(tree_of(roof(400, slope), false).nodes.size(), 1u);
    const Proxy& crease = t.nodes[0].proxy;
    // The zero set is the roof: a point above the ridge is on the other side from one below.
    EXPECT_LT(crease.value(Eigen::Vector3d(0, 0, 0.2)) * crease.value(Eigen::Vector3d(0, 0, -0.2)), 0);
    EXPECT_NEAR(crease.value(Eigen::Vector3d(0.5, 0.5, -slope * 0.5)), 0, 1e-9);
  }
}

// A right angle, and the slightly obtuse ones of machined parts (normals 100 and 113 degrees
// apart), are creases: a limit at 90 degrees refused them, or refused a right angle whenever
// its fitted faces came out a hair beyond it.
TEST(CreaseFit, RightAndSlightlyWiderAnglesAreCreases) {
  for (double slope : {1.0, std::tan(50 * std::numbers::pi / 180), 1.5}) {
    const ClusterTree t = tree_of(roof(400, slope));
    ASSERT_EQ(t.nodes.size(), 1u) << "slope " << slope;
    EXPECT_EQ(t.nodes[0].proxy.kind(), ProxyKind::Crease) << "slope " << slope;
    EXPECT_LT(t.nodes[0].max_error, 1e-9) << "slope " << slope;
  }
}

// Faces facing far apart (a wedge sharper than 60 degrees: here normals 143 degrees apart) are
// as likely both sides of a thin part: the splits deal with them, as the sheet split does with
// input normals.
TEST(CreaseFit, LeavesFacesFacingApartToTheSplits) {
  for (const ClusterNode& n : tree_of(roof(400, 3.0)).nodes) EXPECT_NE(n.proxy.kind(), ProxyKind::Crease);
}

TEST(CreaseFit, RefusesAStepBetweenParallelFaces) {
  Points p(200, 3);
  for (int i = 0; i < 200; ++i) p.row(i) << (i % 20) / 10.0 - 1, (i / 20) / 5.0 - 1, (i % 20) < 10 ? 0.0 : 0.3;
  for (const ClusterNode& n : tree_of(p).nodes) EXPECT_NE(n.proxy.kind(), ProxyKind::Crease);
}

// A face must pin its plane down: a row of points (the last scan line of the other side of a
// thin plate, at its rim) fits every plane through it, among them one meeting the plate's
// face along an edge, with no error at all.
TEST(CreaseFit, RefusesAFaceThatIsARowOfPoints) {
  Points p(10 * 10 + 12, 3);
  Eigen::Index r = 0;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) p.row(r++) << i * 0.1, j * 0.1, 0.0;
  for (int j = 0; j < 12; ++j) p.row(r++) << 0.95, j * 0.08, 0.4;
  for (const ClusterNode& n : tree_of(p).nodes) EXPECT_NE(n.proxy.kind(), ProxyKind::Crease);
}

TEST(CreaseFit, CubeEdgesStaySharp) {
  const PointCloud c = cube(40);  // 9,600 points, 0.05 apart
  ReconstructOptions sharp;
  ReconstructOptions smooth;
  smooth.build.creases = false;
  double rms[2] = {0, 0}, rms_edges[2] = {0, 0}, worst_off_corners[2] = {0, 0};
  std::size_t creases = 0;
  for (int run = 0; run < 2; ++run) {
    const Reconstruction r = reconstruct(c, run == 0 ? sharp : smooth);
    if (run == 0)
      for (const ClusterNode& n : r.tree.nodes) creases += n.is_leaf() && n.proxy.kind() == ProxyKind::Crease;
    const Points& v = r.mesh->mesh.vertices;
    double sum = 0, sum_edges = 0;
    std::size_t edges = 0;
    for (Eigen::Index i = 0; i < v.rows(); ++i) {
      const double d = cube_distance(v.row(i).transpose());
      sum += d * d;
      // Within 0.1 (two point spacings) of an edge: the two smallest |1 − |xₖ||.
      Eigen::Vector3d off = (v.row(i).transpose().cwiseAbs() - Eigen::Vector3d::Ones()).cwiseAbs();
      std::sort(off.data(), off.data() + 3);
      if (std::hypot(off[0], off[1]) < 0.1) sum_edges += d * d, ++edges;
      if (off.norm() > 0.2) worst_off_corners[run] = std::max(worst_off_corners[run], std::abs(d));
    }
    ASSERT_GT(edges, 100u);
    rms[run] = std::sqrt(sum / static_cast<double>(v.rows()));
    rms_edges[run] = std::sqrt(sum_edges / static_cast<double>(edges));
  }
  EXPECT_GT(creases, 12u);  // the cube's 12 edges hold crease leaves
  // Smooth leaves round the edges off (RMS 0.014 within two spacings of an edge, 0.007
  // overall); crease leaves keep them at half that or less.
  EXPECT_LT(rms_edges[0], 0.6 * rms_edges[1]) << "near edges: crease " << rms_edges[0] << ", smooth " << rms_edges[1];
  EXPECT_LT(rms[0], 0.6 * rms[1]) << "crease " << rms[0] << ", smooth " << rms[1];
  // No lip along the edges: the leaves beside an edge take the crease their supports reach, so
  // away from the corners the mesh stays within 1 % of the side (smooth leaves: 2.4 %).
  EXPECT_LT(worst_off_corners[0], 0.02) << "smooth leaves: " << worst_off_corners[1];
}
