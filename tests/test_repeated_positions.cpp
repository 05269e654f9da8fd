// first_of_each_position(): one row per position, the first in the rows' order; the outlier
// test's flags only narrow the search.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/spatial/outliers.hpp>
#include <clustersurf/spatial/repeated_positions.hpp>

#include <gtest/gtest.h>

#include "test_support.hpp"

using namespace clustersurf;

TEST(RepeatedPositions, KeepsTheFirstRowOfEachPositionInTheRowsOrder) {
  Points p(6, 3);
  p << 0, 0, 0, 1, 0, 0, 0, 0, 0, 2, 0, 0, 1, 0, 0, 0, 0, 0;
  EXPECT_EQ(first_of_each_position(p, test::all_rows(6)), (std::vector<std::uint32_t>{0, 1, 3}));
  EXPECT_EQ(first_of_each_position(p, {5, 4, 3, 2, 1, 0}), (std::vector<std::uint32_t>{5, 4, 3}));
  EXPECT_EQ(first_of_each_position(p, {3, 1}), (std::vector<std::uint32_t>{3, 1}));
  // Positions that differ in one coordinate's last bit are two positions.
  p(2, 2) = std::nextafter(0.0, 1.0);
  EXPECT_EQ(first_of_each_position(p, test::all_rows(6)), (std::vector<std::uint32_t>{0, 1, 2, 3}));
}

TEST(RepeatedPositions, TheOutlierTestsFlagsGiveTheSameRows) {
  const PointCloud sphere = test::sample_sphere(3000);
  // Every third point three times, the copies spread through the rows.
  std::vector<Eigen::Index> order;
  for (Eigen::Index i = 0; i < sphere.size(); ++i) order.push_back(i);
  for (Eigen::Index i = 0; i < sphere.size(); i += 3) order.push_back(i), order.push_back(i);
  const Points p = sphere.positions(order, Eigen::all);
  const OutlierReport found = find_outliers(p, KdTree(p));
  ASSERT_EQ(found.coincident.size(), order.size());
  EXPECT_EQ(std::count(found.coincident.begin(), found.coincident.end(), 1), 3 * 1000);
  const std::vector<std::uint32_t> kept = first_of_each_position(p, test::all_rows(p.rows()), found.coincident);
  EXPECT_EQ(kept, test::all_rows(sphere.size()));
  EXPECT_EQ(first_of_each_position(p, test::all_rows(p.rows())), kept);
  // The nearest point at another position: the copies leave the spacing as it was.
  const OutlierReport distinct = find_outliers(sphere.positions, KdTree(sphere.positions));
  for (Eigen::Index i = 0; i < sphere.size(); ++i)
    EXPECT_EQ(found.nearest[static_cast<std::size_t>(i)], distinct.nearest[static_cast<std::size_t>(i)]);
}

TEST(RepeatedPositions, DistinctPointsKeepEveryRow) {
  const PointCloud sphere = test::sample_sphere(2000);
  EXPECT_EQ(first_of_each_position(sphere.positions, test::all_rows(sphere.size())), test::all_rows(sphere.size()));
  EXPECT_EQ(first_of_each_position(sphere.positions, {}), std::vector<std::uint32_t>{});
}

TEST(RepeatedPositions, RefusesFlagsOfAnotherCloud) {
  const PointCloud sphere = test::sample_sphere(100);
  const std::vector<std::uint8_t> flags(99, 1);
  EXPECT_THROW(first_of_each_position(sphere.positions, test::all_rows(100), flags), OptionError);
}
