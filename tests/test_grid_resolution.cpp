// The mesh grid matched to the input's sampling density (cell_size_for_points).

#include <clustersurf/errors.hpp>
#include <clustersurf/mesh_extraction.hpp>

#include <gtest/gtest.h>

#include <limits>

#include "test_support.hpp"

using namespace clustersurf;

TEST(GridResolution, CellIsTheLatticeSpacingTimesTheFactor) {
  const PointCloud c = test::sample_plane(101, 51);  // spacing 0.01 along x, 0.02 along y
  EXPECT_NEAR(cell_size_for_points(c), kSpacingsPerCell * 0.01, 1e-12);
  EXPECT_NEAR(cell_size_for_points(c, 2.5), 0.025, 1e-12);
}

TEST(GridResolution, FourTimesTheSamplesHalveTheCell) {
  const double sparse = cell_size_for_points(test::sample_sphere(20000));
  const double dense = cell_size_for_points(test::sample_sphere(80000));
  EXPECT_NEAR(sparse / dense, 2.0, 0.1);
}

TEST(GridResolution, CoincidentPointsOrABadFactorAreOptionErrors) {
  PointCloud same;
  same.positions = Points::Constant(100, 3, 0.5);
  EXPECT_THROW(cell_size_for_points(same), OptionError);
  const PointCloud c = test::sample_plane(10, 10);
  EXPECT_THROW(cell_size_for_points(c, 0.0), OptionError);
  EXPECT_THROW(cell_size_for_points(c, std::numeric_limits<double>::quiet_NaN()), OptionError);
}
