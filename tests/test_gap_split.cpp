// Splitting a cluster at an empty gap (src/cluster/gap_split.cpp): groups of points apart are
// never one leaf, whether the gap lies along the cluster's length or between two of its parts
// side by side (two legs of a sparse scan).

#include <clustersurf/cluster/cluster_tree.hpp>

#include "cluster/splitters.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <vector>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// Points along two parallel rows `apart` apart: `first` points in one, `second` in the other,
/// consecutive points `step` apart within a row, the second row shifted half a step.
Points two_rows(int first, int second, double step, double apart) {
  Points p(first + second, 3);
  for (int i = 0; i < first; ++i) p.row(i) << step * i, 0, 0;
  for (int i = 0; i < second; ++i) p.row(first + i) << step * (i + 0.5), apart, 0;
  return p;
}

}  // namespace

TEST(LinkageGapSplit, TwoRowsApartAreTwoGroups) {
  // Ten points and five, a unit apart within each row, five units between the rows: the rows.
  const Points p = two_rows(10, 5, 1.0, 5.0);
  std::vector<std::uint32_t> rows = test::all_rows(p.rows());
  const std::size_t k = detail::split_at_linkage_gap(p, rows, 3);
  ASSERT_TRUE(k == 10 || k == 5) << k;
  const auto first = std::span(rows).subspan(0, k), second = std::span(rows).subspan(k);
  const auto in_row = [&](std::uint32_t r) { return p(r, 1) > 0; };
  EXPECT_TRUE(std::all_of(first.begin(), first.end(), in_row) || std::none_of(first.begin(), first.end(), in_row));
  EXPECT_EQ(std::count_if(first.begin(), first.end(), in_row) + std::count_if(second.begin(), second.end(), in_row), 5);
  EXPECT_NE(in_row(first.front()), in_row(second.front()));
}

TEST(LinkageGapSplit, ASparserStretchOfOneRowIsNoGap) {
  // One row whose spacing grows from 1 to 1.8: no edge is twice every other.
  Points p(12, 3);
  double x = 0;
  for (int i = 0; i < 12; ++i) {
    p.row(i) << x, 0.1 * (i % 2), 0;
    x += i < 6 ? 1.0 : 1.8;
  }
  std::vector<std::uint32_t> rows = test::all_rows(p.rows());
  EXPECT_EQ(detail::split_at_linkage_gap(p, rows, 3), 0u);
  // Rows 2.0 apart with a unit step: the gap is not twice the step within them.
  const Points near = two_rows(8, 8, 1.0, 1.9);
  rows = test::all_rows(near.rows());
  EXPECT_EQ(detail::split_at_linkage_gap(near, rows, 3), 0u);
}

TEST(LinkageGapSplit, AGroupBelowTheSmallestSideStays) {
  // Two stray points far from a row: fewer than the three a side keeps.
  const Points p = two_rows(10, 2, 1.0, 5.0);
  std::vector<std::uint32_t> rows = test::all_rows(p.rows());
  EXPECT_EQ(detail::split_at_linkage_gap(p, rows, 3), 0u);
}

TEST(LinkageGapSplit, ALeafOfTwoPatchesApartIsTwoLeaves) {
  // Fourteen points, fewer than two leaves of min_points: ten on a bent strip and four on a
  // tilted one beside it, 0.7 away (about five spacings). Along the cluster's length the two
  // overlap, so no gap shows there; no quadratic holds both, and a leaf of both would bridge
  // the gap. Each strip is a leaf of its own.
  PointCloud c;
  c.positions.resize(14, 3);
  c.normals.resize(14, 3);
  for (int i = 0; i < 10; ++i) {
    const double x = -0.3 + 0.15 * (i / 2), y = 0.12 * (i % 2);
    c.positions.row(i) << x, y, x * x;
    c.normals.row(i) = Eigen::Vector3d(-2 * x, 0, 1).normalized().transpose();
  }
  for (int i = 0; i < 4; ++i) {
    const double x = -0.1 + 0.2 * (i / 2);
    c.positions.row(10 + i) << x, 0.8 + 0.12 * (i % 2), 0.3 + 0.2 * x;
    c.normals.row(10 + i) = Eigen::Vector3d(-0.2, 0, 1).normalized().transpose();
  }
  const ClusterTree tree = build_cluster_tree(c);
  std::vector<int> sides(tree.nodes.size(), 0);
  for (std::size_t p = 0; p < tree.point_leaf.size(); ++p)
    if (tree.point_leaf[p] >= 0) sides[static_cast<std::size_t>(tree.point_leaf[p])] |= p < 10 ? 1 : 2;
  int mixed = 0, leaves = 0;
  for (std::size_t i = 0; i < sides.size(); ++i)
    if (tree.nodes[i].is_leaf()) ++leaves, mixed += sides[i] == 3 ? 1 : 0;
  std::cout << leaves << " leaves, " << mixed << " on both strips (min_points " << tree.parameters.min_points << ")\n";
  EXPECT_EQ(mixed, 0);
}
