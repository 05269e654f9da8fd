// The mesher's walk state: corners queued once with their values, cells visited once.

#include "mesh/walk_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using namespace clustersurf::detail;

TEST(WalkGrid, CornersAreQueuedOnceAndKeepTheirValues) {
  WalkGrid walk;
  const GridIndex far = {-1'048'576, 1'048'575, 7};  // the ends of the mesher's key range
  EXPECT_TRUE(walk.queue({0, 0, 0}));
  EXPECT_TRUE(walk.queue(far));
  EXPECT_FALSE(walk.queue({0, 0, 0}));
  EXPECT_FALSE(walk.queue(far));
  walk.set_value({0, 0, 0}, -0.25f);
  walk.set_value(far, std::numeric_limits<float>::quiet_NaN());
  EXPECT_EQ(walk.value({0, 0, 0}), -0.25f);
  EXPECT_TRUE(std::isnan(walk.value(far)));
  EXPECT_FALSE(walk.queue({0, 0, 0}));  // a value keeps the corner queued
  EXPECT_EQ(walk.queued(), 2u);
  EXPECT_THROW(walk.value({1, 0, 0}), std::logic_error);
}

TEST(WalkGrid, CellsAreVisitedOnce) {
  WalkGrid walk;
  EXPECT_TRUE(walk.visit({3, -4, 5}));
  EXPECT_FALSE(walk.visit({3, -4, 5}));
  EXPECT_TRUE(walk.visit({3, -4, 6}));
  EXPECT_EQ(walk.queued(), 0u);  // cells are not corners
}

TEST(WalkGrid, SurfaceCellsGetTheirCornersInOrder) {
  WalkGrid walk;
  // Two cells sharing a face; every corner's value encodes its coordinates.
  const auto code = [](int i, int j, int k) { return static_cast<float>(100 * i + 10 * j + k); };
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 1; ++j)
      for (int k = 0; k <= 1; ++k) {
        ASSERT_TRUE(walk.queue({i, j, k}));
        walk.set_value({i, j, k}, code(i, j, k));
      }
  std::vector<SurfaceCell> cells(2);
  cells[0].corner = {0, 0, 0};
  cells[1].corner = {1, 0, 0};
  walk.corner_values(cells);
  for (const SurfaceCell& cell : cells)
    for (int c = 0; c < 8; ++c)
      EXPECT_EQ(cell.values[static_cast<std::size_t>(c)],
                code(cell.corner[0] + kCellCorner[c][0], cell.corner[1] + kCellCorner[c][1], cell.corner[2] + kCellCorner[c][2]));
  std::vector<SurfaceCell> beyond(1);
  beyond[0].corner = {2, 0, 0};  // its far corners were never queued
  EXPECT_THROW(walk.corner_values(beyond), std::logic_error);
}
