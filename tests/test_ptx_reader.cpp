// The PTX reader: PDAL's samples (colors, several scans, transforms), a scan written here whose
// transform and no-return cells are checked point by point, and hostile headers.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <gtest/gtest.h>

#include <string>

namespace clustersurf::test {
namespace {

PointCloud parse_ptx(const std::string& text) { return parse_point_cloud(text, FileFormat::Ptx, "t.ptx"); }

/// A PTX scan header: columns, rows, the scanner at `t` with identity axes, and the transform
/// rotating 90 degrees about z then translating by `t`.
std::string header(int columns, int rows, const std::string& t) {
  return std::to_string(columns) + "\n" + std::to_string(rows) + "\n" + t + "\n1 0 0\n0 1 0\n0 0 1\n" +
         "0 1 0 0\n-1 0 0 0\n0 0 1 0\n" + t + " 1\n";
}

void expect_error(const std::string& text, const std::string& message, std::uint64_t line) {
  try {
    parse_ptx(text);
    ADD_FAILURE() << "accepted; expected: " << message;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    EXPECT_EQ(e.where().line, line) << e.what();
  }
}

TEST(PtxReader, TransformsScansSkipsNoReturnsAndKeepsScanners) {
  // Two scans: the first 2 x 2 with one empty cell, the second 1 x 1.
  const std::string text = header(2, 2, "10 20 30") + "1 0 0 0.5\n0 0 0 0.5\n0 2 0 0.25\n0 0 3 1\n" +
                           header(1, 1, "-5 0 0") + "1 1 1 0.75\n";
  const PointCloud c = parse_ptx(text);
  ASSERT_EQ(c.size(), 4);
  // Row vectors times the matrix: (1,0,0) -> (0,1,0), (0,2,0) -> (-2,0,0); then translated.
  EXPECT_TRUE(mat_eq(c.positions, rows({{10, 21, 30}, {8, 20, 30}, {10, 20, 33}, {-6, 1, 1}})));
  EXPECT_TRUE(mat_eq(c.scanner_positions, rows({{10, 20, 30}, {-5, 0, 0}})));
  EXPECT_EQ(c.scanner_of_point, (std::vector<std::uint32_t>{0, 0, 0, 1}));
  ASSERT_EQ(c.attributes.size(), 1u);
  EXPECT_EQ(c.attributes[0].name, "intensity");
  EXPECT_FLOAT_EQ(c.attributes[0].values(3), 0.75f);
  EXPECT_FALSE(c.has_colors());
}

// Blank lines between scans (and at the end) are only blank lines: a blank line used to read
// as the end of the file, and the scans after it were silently lost.
TEST(PtxReader, ScansSeparatedByBlankLinesAreAllRead) {
  const std::string text =
      header(1, 2, "0 0 0") + "1 0 0 0.5\n0 2 0 0.25\n\n\n" + header(1, 1, "-5 0 0") + "1 1 1 0.75\n\n";
  const PointCloud c = parse_ptx(text);
  EXPECT_EQ(c.size(), 3);
  EXPECT_EQ(c.scanner_positions.rows(), 2);
}

TEST(PtxReader, HostileFiles) {
  const std::string h = header(2, 1, "0 0 0");
  expect_error(h + "1 2 3 0.5\n", "scan 1 ends after 1 of 2 points", 11);
  expect_error(h + "1 2 3 0.5\n1 2\n", "expected 3 (x y z), 4 (x y z intensity) or 7", 12);
  expect_error(h + "1 2 3 0.5 1 2 3\n1 2 3 0.5\n", "no color where earlier points have one", 12);
  expect_error(h + "1 x 3 0.5\n1 2 3 0.5\n", "expected a number in column 2", 11);
  expect_error("2\n1\n0 0 0\n1 0 0\n0 1 0\n", "file ends where the scan header's scanner axis was expected", 5);
  expect_error("2\n1\n0 0 nan\n", "expected a finite number in the scanner position", 3);
  expect_error("-2\n", "expected the scan's column count", 1);
  expect_error("100000\n100000\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n",
               "more than the file can hold", 1);
  // A NaN coordinate is named by its line through the dispatcher's check.
  try {
    parse_ptx(h + "1 2 3 0.5\nnan 2 3 0.5\n");
    ADD_FAILURE() << "NaN accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 12u) << e.what();
  }
}

TEST(PtxReader, PdalSamples) {
  const auto dir = shared_data("formats/ptx");
  if (!dir) GTEST_SKIP() << "the shared PTX samples (formats/ptx) are not here";
  const PointCloud color = read_point_cloud(*dir / "1.2-with-color.ptx");
  EXPECT_EQ(color.size(), 1065);
  EXPECT_TRUE(color.has_colors());
  EXPECT_FALSE(read_point_cloud(*dir / "no-color.ptx").has_colors());
  // Two scans of the same points, the second placed by a transform that also scales z by 2:
  // both land on the first's coordinates.
  const PointCloud two = read_point_cloud(*dir / "multiple-and-transform.ptx");
  ASSERT_EQ(two.scanner_positions.rows(), 2);
  ASSERT_EQ(two.size() % 2, 0);
  const Eigen::Index half = two.size() / 2;
  EXPECT_LT((two.positions.topRows(half) - two.positions.bottomRows(half)).cwiseAbs().maxCoeff(), 1e-6);
  const Eigen::RowVector3d first = two.positions.row(0) + two.origin.transpose();
  EXPECT_NEAR(first.x(), 637012.24, 1e-6);
  EXPECT_NEAR(first.z(), 431.66, 1e-6);
  EXPECT_GT(read_point_cloud(*dir / "complex-transform.ptx").size(), 0);
}

}  // namespace
}  // namespace clustersurf::test
