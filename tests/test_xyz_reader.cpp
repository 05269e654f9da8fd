// The XYZ/PTS reader on hand-written files: comments, commas, normals and a PTS count line.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <gtest/gtest.h>

namespace clustersurf {
namespace {

using namespace clustersurf::test;

TEST(XyzReader, CommentsCommasAndSixColumns) {
  TempDir dir;
  const PointCloud c = read_text(dir, "c.xyz",
                                 "# a comment\n\n1,2,3, 0,0,1\n  4 , 5 , 6 , 1 , 0 , 0   # trailing comment\n"
                                 "7\t8\t9\t0\t1\t0\n");
  EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}, {4, 5, 6}, {7, 8, 9}})));
  ASSERT_TRUE(c.has_normals());
  EXPECT_TRUE(mat_eq(c.normals, rows({{0, 0, 1}, {1, 0, 0}, {0, 1, 0}})));
  EXPECT_FALSE(c.has_colors());

  const PointCloud t = read_text(dir, "p.txt", "1 2 3\r\n4 5 6\r\n");
  EXPECT_TRUE(mat_eq(t.positions, rows({{1, 2, 3}, {4, 5, 6}})));
  EXPECT_FALSE(t.has_normals());

  const PointCloud csv = read_text(dir, "p.csv", "1,2,3,0.5\n4,5,6,0.25\n");  // x y z intensity
  EXPECT_TRUE(mat_eq(csv.positions, rows({{1, 2, 3}, {4, 5, 6}})));
}

TEST(XyzReader, PtsWithCountLineAndSevenColumns) {
  TempDir dir;
  const PointCloud c = read_text(dir, "s.pts", "2\n1 2 3 -120 255 0 10\n4 5 6 7 1e300 -4 127.5\n");
  EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}, {4, 5, 6}})));
  ASSERT_TRUE(c.has_colors());
  EXPECT_EQ(c.colors(0, 0), 255);
  EXPECT_EQ(c.colors(0, 1), 0);
  EXPECT_EQ(c.colors(0, 2), 10);
  EXPECT_EQ(c.colors(1, 0), 255);  // clamped
  EXPECT_EQ(c.colors(1, 1), 0);
  EXPECT_EQ(c.colors(1, 2), 128);
  EXPECT_FALSE(c.has_normals());
}

}  // namespace
}  // namespace clustersurf
