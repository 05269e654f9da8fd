// The XYZ/PTS reader on hand-written files: comments, commas, normals and a PTS count line, and
// what the extra columns hold (normals, colors, intensity) told from the whole file.

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

// Six columns are normals, or colors where the last three are whole numbers from 0 to 255 on
// every line and above 1 on one (x y z r g b, as CloudCompare writes a colored cloud); nine are
// colors and normals in either order; four carry an intensity.
TEST(XyzReader, ColumnsAreToldApartOverTheWholeFile) {
  TempDir dir;
  const PointCloud rgb = read_text(dir, "rgb.xyz", "1 2 3 0 0 1\n4 5 6 255 128 0\n7 8 9 0 1 0\n");
  EXPECT_FALSE(rgb.has_normals());
  ASSERT_TRUE(rgb.has_colors());
  EXPECT_EQ(rgb.colors.row(1), (Eigen::Matrix<std::uint8_t, 1, 3>(255, 128, 0)));
  EXPECT_EQ(rgb.colors.row(0), (Eigen::Matrix<std::uint8_t, 1, 3>(0, 0, 1)));  // a dark blue, not a normal
  // Unit vectors with whole components, or any fraction, are normals.
  for (const char* text :
       {"1 2 3 0 0 1\n4 5 6 1 0 0\n", "1 2 3 0 0 1\n4 5 6 0.6 0.8 0\n", "1 2 3 0 0 2\n4 5 6 0 -1 0\n"}) {
    const PointCloud n = read_text(dir, "n.xyz", text);
    EXPECT_TRUE(n.has_normals()) << text;
    EXPECT_FALSE(n.has_colors()) << text;
  }
  const PointCloud both = read_text(dir, "both.xyz", "1 2 3 10 20 30 0 0 1\n4 5 6 40 50 60 0 1 0\n");
  ASSERT_TRUE(both.has_colors() && both.has_normals());
  EXPECT_EQ(both.colors.row(1), (Eigen::Matrix<std::uint8_t, 1, 3>(40, 50, 60)));
  EXPECT_TRUE(mat_eq(both.normals, rows({{0, 0, 1}, {0, 1, 0}})));
  const PointCloud swapped = read_text(dir, "swapped.xyz", "1 2 3 0 0 1 10 20 30\n4 5 6 0.6 0.8 0 40 50 60\n");
  ASSERT_TRUE(swapped.has_colors() && swapped.has_normals());
  EXPECT_EQ(swapped.colors.row(0), (Eigen::Matrix<std::uint8_t, 1, 3>(10, 20, 30)));
  EXPECT_TRUE(mat_eq(swapped.normals, rows({{0, 0, 1}, {0.6, 0.8, 0}})));
  const PointCloud intensity = read_text(dir, "i.xyz", "1 2 3 1200\n4 5 6 40\n");
  ASSERT_EQ(intensity.attributes.size(), 1u);
  EXPECT_EQ(intensity.attributes[0].name, "intensity");
  EXPECT_EQ(intensity.attributes[0].values(0), 1200.0f);
  // A normal that is not a number is found on its line, whichever columns hold the normals.
  try {
    (void)read_text(dir, "nan.xyz", "1 2 3 10 20 30 0 0 1\n4 5 6 40 50 60 nan 0 1\n");
    ADD_FAILURE() << "a NaN normal was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace clustersurf
