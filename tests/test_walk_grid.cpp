// The mesher's walk state: corners queued once with their values, cells visited once.

#include "mesh/walk_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

using namespace clustersurf::detail;

TEST(WalkGrid, CornersAreQueuedOnceAndKeepTheirValues) {
  WalkGrid walk;
  const GridIndex far = {-1'048'576, 1'048'574, 7};  // near the ends of the mesher's key range
  // Every corner of the cell at `far` is queued; one of them twice.
  for (const auto& c : kCellCorner) EXPECT_TRUE(walk.queue({far[0] + c[0], far[1] + c[1], far[2] + c[2]}));
  EXPECT_FALSE(walk.queue(far));
  std::vector<float> values;
  for (const auto& c : kCellCorner) values.push_back(-0.25f * static_cast<float>(c[0] + 2 * c[1] + 4 * c[2]));
  values[0] = std::numeric_limits<float>::quiet_NaN();  // the corner at `far`
  EXPECT_THROW(walk.set_values(std::span<const float>(values).first(7)), std::logic_error);
  walk.set_values(values);
  SurfaceCell cell{far, {}};
  walk.values({&cell, 1});
  EXPECT_TRUE(std::isnan(cell.values[0]));
  for (std::size_t c = 1; c < 8; ++c) EXPECT_EQ(cell.values[c], -0.25f * static_cast<float>(c));
  EXPECT_FALSE(walk.queue(far));  // a value keeps the corner queued
  EXPECT_EQ(walk.queued(), 8u);
  SurfaceCell unqueued{{0, 0, 0}, {}};
  EXPECT_THROW(walk.values({&unqueued, 1}), std::logic_error);
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
  std::vector<float> values;
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 1; ++j)
      for (int k = 0; k <= 1; ++k) {
        ASSERT_TRUE(walk.queue({i, j, k}));
        values.push_back(code(i, j, k));
      }
  walk.set_values(values);
  for (const GridIndex corner : {GridIndex{0, 0, 0}, GridIndex{1, 0, 0}}) {
    SurfaceCell cell{corner, {}};
    walk.values({&cell, 1});
    for (std::size_t c = 0; c < 8; ++c)
      EXPECT_EQ(cell.values[c], code(cell.corner[0] + kCellCorner[c][0], cell.corner[1] + kCellCorner[c][1],
                                     cell.corner[2] + kCellCorner[c][2]));
  }
  SurfaceCell beyond{{2, 0, 0}, {}};  // its far corners were never queued
  EXPECT_THROW(walk.values({&beyond, 1}), std::logic_error);
}
