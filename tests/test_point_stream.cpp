// PointStream: a binary PLY of points, a LAS, E57 or PCD file, XYZ or PTX text read in place a
// block at a time give the reader's points; other files are read whole; damaged files are
// refused with the byte offset or line, and nothing is read past a refused point until a rewind.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/io/point_stream.hpp>

#include <gtest/gtest.h>
#include <lzf.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "e57_writer.hpp"
#include "io_test_files.hpp"

using namespace clustersurf;

namespace {

/// Every point of the stream, in blocks of `block`.
PointCloud read_all(PointStream& stream, std::size_t block) {
  PointCloud all, part;
  std::vector<Eigen::RowVector3d> p, n;
  std::vector<Eigen::Matrix<std::uint8_t, 1, 3>> c;
  while (stream.read(block, part)) {
    EXPECT_LE(part.size(), static_cast<Eigen::Index>(block));
    EXPECT_EQ(part.has_colors(), stream.has_colors() && part.size() > 0);
    for (Eigen::Index i = 0; i < part.size(); ++i) {
      p.push_back(part.positions.row(i));
      if (part.has_normals()) n.push_back(part.normals.row(i));
      if (part.has_colors()) c.push_back(part.colors.row(i));
    }
  }
  all.colors.resize(static_cast<Eigen::Index>(c.size()), 3);
  for (std::size_t i = 0; i < c.size(); ++i) all.colors.row(static_cast<Eigen::Index>(i)) = c[i];
  all.positions.resize(static_cast<Eigen::Index>(p.size()), 3);
  for (std::size_t i = 0; i < p.size(); ++i) all.positions.row(static_cast<Eigen::Index>(i)) = p[i];
  if (!n.empty()) {
    all.normals.resize(static_cast<Eigen::Index>(n.size()), 3);
    for (std::size_t i = 0; i < n.size(); ++i) all.normals.row(static_cast<Eigen::Index>(i)) = n[i];
  }
  return all;
}

/// The shared sample `name` (under formats/) read in place in blocks of `block` gives the
/// reader's points, to within `tolerance` (the reader moves a far cloud next to zero), its
/// colors exactly and its up axis; false, with nothing checked, when the sample is absent.
bool streams_as_read(const std::string& name, std::size_t block, double tolerance) {
  const auto file = test::shared_data("formats/" + name);
  if (!file) return false;
  PointStream stream(*file);
  EXPECT_TRUE(stream.streamed()) << name;
  const PointCloud whole = read_point_cloud(*file);
  Points world = whole.positions;
  world.rowwise() += whole.origin.transpose();
  const PointCloud blocks = read_all(stream, block);
  EXPECT_EQ(blocks.size(), whole.size()) << name;
  if (blocks.size() == whole.size()) {
    EXPECT_LE((blocks.positions - world).cwiseAbs().maxCoeff(), tolerance) << name;
  }
  EXPECT_EQ(stream.has_colors(), whole.has_colors()) << name;
  if (stream.has_colors() && whole.has_colors() && blocks.size() == whole.size()) {
    EXPECT_EQ(blocks.colors, whole.colors) << name;
  }
  EXPECT_EQ(stream.up(), whole.up) << name;
  return true;
}

}  // namespace

TEST(PointStream, BinaryPlyInBlocksIsTheReadersCloud) {
  const test::TempDir dir;
  PointCloud cloud = test::sample_torus(1000);
  cloud.positions.rowwise() += Eigen::RowVector3d(5e6, -3e6, 100);  // far from zero: no shift in the stream
  cloud.colors.resize(cloud.size(), 3);
  for (Eigen::Index i = 0; i < cloud.size(); ++i) cloud.colors.row(i) << i % 256, (7 * i) % 256, 255 - i % 256;
  cloud.up = UpAxis::Z;
  write_ply(dir / "t.ply", cloud);
  PointStream stream(dir / "t.ply");
  EXPECT_TRUE(stream.streamed());
  EXPECT_EQ(stream.size(), 1000u);
  EXPECT_TRUE(stream.has_normals());
  EXPECT_TRUE(stream.has_colors());
  EXPECT_EQ(stream.up(), UpAxis::Z);  // the "comment up z" line
  const PointCloud read = read_point_cloud(dir / "t.ply");
  const PointCloud streamed = read_all(stream, 64);
  Points world = read.positions;
  world.rowwise() += read.origin.transpose();
  EXPECT_EQ(streamed.positions, world);
  EXPECT_EQ(streamed.normals, read.normals);
  EXPECT_EQ(streamed.colors, cloud.colors);
  EXPECT_EQ(read.up, UpAxis::Z);
  stream.rewind();
  EXPECT_EQ(read_all(stream, 1000).positions, world);
}

TEST(PointStream, OtherFilesAreReadWhole) {
  const test::TempDir dir;
  const PointCloud cloud = test::sample_sphere(300);
  PlyWriteOptions ascii;
  ascii.binary = false;
  write_ply(dir / "s.ply", cloud, ascii);
  TriangleMesh vertices;
  vertices.vertices = cloud.positions;
  write_obj(dir / "s.obj", vertices);
  for (const char* name : {"s.ply", "s.obj"}) {
    PointStream stream(dir / name);
    EXPECT_FALSE(stream.streamed()) << name;
    EXPECT_EQ(read_all(stream, 50).positions, read_point_cloud(dir / name).positions) << name;
  }
}

// XYZ text, the commonest export, is read in place: the reader's points and normals, block by
// block, again after a rewind.
TEST(PointStream, XyzTextInBlocksIsTheReadersCloud) {
  const test::TempDir dir;
  const PointCloud cloud = test::sample_sphere(300);
  write_xyz(dir / "s.xyz", cloud);
  PointStream stream(dir / "s.xyz");
  EXPECT_TRUE(stream.streamed());
  EXPECT_EQ(stream.size(), 300u);
  EXPECT_TRUE(stream.has_normals());
  const PointCloud read = read_point_cloud(dir / "s.xyz");
  const PointCloud streamed = read_all(stream, 64);
  EXPECT_EQ(streamed.positions, read.positions);
  EXPECT_EQ(streamed.normals, read.normals);
  stream.rewind();
  EXPECT_EQ(read_all(stream, 7).positions, read.positions);
  // A PTS file: its count line, comments, blank lines, comma separators, intensity and colour.
  test::write_file(dir / "p.pts", "3\n# scan 1\n1 2 3 10 255 0 0\n\n4,5,6,11,0,255,0\n7 8 9 12 0 0 255\n");
  PointStream pts(dir / "p.pts");
  EXPECT_EQ(pts.size(), 3u);
  EXPECT_FALSE(pts.has_normals());
  const PointCloud p = read_all(pts, 2);
  ASSERT_EQ(p.size(), 3);
  EXPECT_EQ(p.positions.row(2), Eigen::RowVector3d(7, 8, 9));
  EXPECT_EQ(p.colors, read_point_cloud(dir / "p.pts").colors);
  // Colors and normals told apart over the whole file, as the reader tells them.
  test::write_file(dir / "c.xyz", "1 2 3 0 0 1 0 0 1\n4 5 6 255 128 0 1 0 0\n7 8 9 0 1 0 0 1 0\n");
  PointStream colored(dir / "c.xyz");
  EXPECT_TRUE(colored.has_colors() && colored.has_normals());
  const PointCloud c = read_all(colored, 2), whole = read_point_cloud(dir / "c.xyz");
  EXPECT_EQ(c.colors, whole.colors);
  EXPECT_EQ(c.normals, whole.normals);
  EXPECT_EQ(c.colors.row(1), (Eigen::Matrix<std::uint8_t, 1, 3>(255, 128, 0)));
}

// A broken text file is refused when opened, at the reader's line, before any block is read; a
// non-finite value at its line when read, or dropped on request.
TEST(PointStream, DamagedXyzIsRefusedWithTheLine) {
  const test::TempDir dir;
  const auto line_of_error = [&](const std::string& text) -> std::optional<std::uint64_t> {
    test::write_file(dir / "bad.xyz", text);
    try {
      PointStream stream(dir / "bad.xyz");
    } catch (const InputError& e) {
      return e.where().line;
    }
    return std::nullopt;
  };
  EXPECT_EQ(line_of_error("1 2 3\n4 5 6\n7 8\n"), std::optional<std::uint64_t>(3));
  EXPECT_EQ(line_of_error("1 2 3\n4 five 6\n"), std::optional<std::uint64_t>(2));
  EXPECT_EQ(line_of_error("5\n1 2 3\n"), std::optional<std::uint64_t>(1));  // the count line says 5
  test::write_file(dir / "nan.xyz", "1 2 3\n4 nan 6\n7 8 9\n");
  PointStream strict(dir / "nan.xyz");
  EXPECT_EQ(strict.size(), 3u);
  try {
    read_all(strict, 2);
    FAIL() << "a NaN was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, std::optional<std::uint64_t>(2)) << e.what();
  }
  // The parser is past the refused point: reading on is refused too, until a rewind.
  PointCloud block;
  EXPECT_THROW(strict.read(2, block), InputError);
  strict.rewind();
  ASSERT_TRUE(strict.read(1, block));
  EXPECT_EQ(block.positions.row(0), Eigen::RowVector3d(1, 2, 3));
  ReadOptions drop;
  drop.drop_non_finite = true;
  PointStream lenient(dir / "nan.xyz", drop);
  EXPECT_EQ(read_all(lenient, 2).size(), 2);
}

TEST(PointStream, ElementsBeforeTheVerticesAndBigEndian) {
  const test::TempDir dir;
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\nelement camera 1\nproperty float k\nelement vertex 2\nproperty float x\n"
      "property float y\nproperty float z\nproperty uchar red\nend_header\n";
  const auto put = [&](float v) {
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    for (int s = 24; s >= 0; s -= 8) bytes.push_back(static_cast<char>((u >> s) & 0xff));
  };
  put(9);  // the camera
  for (const float v : {1.f, 2.f, 3.f}) put(v);
  bytes.push_back(7);
  for (const float v : {4.f, 5.f, 6.f}) put(v);
  bytes.push_back(8);
  test::write_file(dir / "b.ply", bytes);
  PointStream stream(dir / "b.ply");
  ASSERT_TRUE(stream.streamed());
  const PointCloud all = read_all(stream, 1);
  ASSERT_EQ(all.size(), 2);
  EXPECT_EQ(all.positions.row(1), Eigen::RowVector3d(4, 5, 6));
}

TEST(PointStream, DamagedFilesAreRefusedWithTheByteOffset) {
  const test::TempDir dir;
  PointCloud cloud = test::sample_sphere(10);
  cloud.normals.resize(0, 3);
  write_ply(dir / "p.ply", cloud);
  const std::string good = test::read_file(dir / "p.ply");
  // Truncated inside the last point: refused when opened, before any point is read.
  test::write_file(dir / "cut.ply", good.substr(0, good.size() - 5));
  try {
    PointStream stream(dir / "cut.ply");
    FAIL() << "a truncated file was opened";
  } catch (const InputError& e) {
    EXPECT_TRUE(e.where().byte_offset.has_value()) << e.what();
  }
  // A NaN coordinate: refused at its record, or dropped on request.
  std::string bad = good;
  const std::size_t header = good.find("end_header\n") + 11;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(bad.data() + header + 3 * 12 + 4, &nan, 4);  // point 3's y
  test::write_file(dir / "nan.ply", bad);
  PointStream strict(dir / "nan.ply");
  try {
    read_all(strict, 4);
    FAIL() << "a NaN was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().byte_offset, std::optional<std::uint64_t>(header + 3 * 12)) << e.what();
  }
  ReadOptions drop;
  drop.drop_non_finite = true;
  PointStream lenient(dir / "nan.ply", drop);
  EXPECT_EQ(read_all(lenient, 4).size(), 9);
  EXPECT_THROW(PointStream(dir / "missing.ply"), IoError);
}

// LAS color fields left 0 in every record are no colors in blocks too, as the reader has it.
TEST(PointStream, LasColorFieldsLeftEmptyAreNoColors) {
  const test::TempDir dir;
  for (const bool lit : {false, true}) {
    test::LasFile las(7, 36, 3);
    for (std::int32_t i = 0; i < 3; ++i)
      las.record(36, i, 2 * i, 3 * i, 5, {{34, lit && i == 1 ? std::uint16_t{60000} : std::uint16_t{0}}});
    test::write_file(dir / "c.las", las.bytes);
    PointStream stream(dir / "c.las");
    ASSERT_EQ(stream.has_colors(), lit);
    const PointCloud streamed = read_all(stream, 2);
    EXPECT_EQ(streamed.colors, read_point_cloud(dir / "c.las").colors);
  }
}

// LAS, the surveys' format, is read in place too: the same points as the reader's, in the file's
// coordinates (the reader moves them next to zero and keeps the shift as the origin).
TEST(PointStream, LasInBlocksIsTheReadersCloud) {
  const test::TempDir dir;
  test::LasFile las(6, 30, 5, {0.001, 0.001, 0.01}, {636000, 849000, 400});
  for (std::int32_t i = 0; i < 5; ++i) las.record(30, 1000 * i, -7 * i, 3 + i, 0);
  test::write_file(dir / "s.las", las.bytes);
  PointStream stream(dir / "s.las");
  EXPECT_TRUE(stream.streamed());
  EXPECT_EQ(stream.size(), 5u);
  EXPECT_FALSE(stream.has_normals());
  const PointCloud read = read_point_cloud(dir / "s.las");
  Points world = read.positions;
  world.rowwise() += read.origin.transpose();
  const PointCloud streamed = read_all(stream, 2);
  EXPECT_EQ(streamed.positions, world);
  EXPECT_LT((streamed.positions.row(4) - Eigen::RowVector3d(636004, 849000 - 0.028, 400.07)).cwiseAbs().maxCoeff(),
            1e-9);

  const auto real = test::shared_data("formats/las/autzen_trim.las");
  if (!real) GTEST_SKIP() << "the shared LAS sample formats/las/autzen_trim.las is not here";
  PointStream autzen(*real);
  EXPECT_TRUE(autzen.streamed());
  const PointCloud whole = read_point_cloud(*real);
  Points whole_world = whole.positions;
  whole_world.rowwise() += whole.origin.transpose();
  const PointCloud blocks = read_all(autzen, 4096);
  ASSERT_EQ(blocks.size(), 110000);
  EXPECT_LT((blocks.positions - whole_world).cwiseAbs().maxCoeff(), 1e-9);  // the reader's shift is exact to rounding
  // Its RGB, and a survey's up axis.
  ASSERT_TRUE(autzen.has_colors());
  EXPECT_EQ(blocks.colors, whole.colors);
  EXPECT_EQ(autzen.up(), UpAxis::Z);
  EXPECT_EQ(whole.up, UpAxis::Z);
  std::string absent;
  for (const char* name : {"las/1.2-with-color.las", "las/simple.las"})
    if (!streams_as_read(name, 100, 1e-9)) absent += std::string(" ") + name;
  if (!absent.empty()) GTEST_SKIP() << "shared samples absent under formats/:" << absent;
}

// A LAS header that promises more points than the file holds is refused when opened, with the
// byte offset of the count, as the reader refuses it.
TEST(PointStream, DamagedLasIsRefusedWhenOpened) {
  const test::TempDir dir;
  test::LasFile las(6, 30, 5);
  for (std::int32_t i = 0; i < 4; ++i) las.record(30, i, i, i, 0);
  test::write_file(dir / "short.las", las.bytes);
  try {
    PointStream stream(dir / "short.las");
    FAIL() << "a LAS file short of its points was opened";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().byte_offset, std::optional<std::uint64_t>(107)) << e.what();
  }
}

// E57, the terrestrial scanners' format, is decoded in place a block of records at a time: the
// same points as the reader's (every scan posed, spherical ones made cartesian, the invalid
// records left out), however the blocks fall on scans, packets and pages.
TEST(PointStream, E57InBlocksIsTheReadersCloud) {
  using namespace clustersurf::test;
  const test::TempDir dir;
  const int n = 3000;
  std::vector<std::int64_t> x, y, z, state;
  std::vector<double> range, az, el;
  for (int i = 0; i < n; ++i) {
    x.push_back(-4000 + (i * 37) % 8001), y.push_back(4000 - (i * 91) % 8001), z.push_back((i * i) % 8001 - 4000);
    state.push_back(i % 10 == 3 ? 2 : i % 10 == 7 ? 1 : 0);
    range.push_back(1 + 0.01 * i), az.push_back(0.002 * i), el.push_back(0.3 - 0.0001 * i);
  }
  const std::string scale = "scale=\"0.001\" offset=\"10\"";
  const std::string pose =
      "<pose type=\"Structure\"><rotation type=\"Structure\"><w type=\"Float\">0.9</w><x type=\"Float\">0.1</x>"
      "<y type=\"Float\">-0.3</y><z type=\"Float\">0.2</z></rotation><translation type=\"Structure\"><x "
      "type=\"Float\">500000</x>"
      "<y type=\"Float\">4e6</y><z type=\"Float\">120</z></translation></pose>";
  const TestScan cartesian{
      {int_field("cartesianX", -4000, 4000, x, scale), int_field("cartesianY", -4000, 4000, y, scale),
       int_field("cartesianZ", -4000, 4000, z, scale), int_field("cartesianInvalidState", 0, 2, state)},
      pose};
  const TestScan empty{{float_field("cartesianX", {}), float_field("cartesianY", {}), float_field("cartesianZ", {})}};
  const TestScan spherical{
      {float_field("sphericalRange", range), float_field("sphericalAzimuth", az), float_field("sphericalElevation", el),
       int_field("sphericalInvalidState", 0, 0, std::vector<std::int64_t>(n, 0))},
      pose};
  WriteOptions small;  // values straddle packets, packets straddle pages
  small.page = 64;
  small.chunk = 7;
  small.extra_packets = true;
  write_file(dir / "s.e57", write_e57({cartesian, empty, spherical}, small).bytes);

  PointStream stream(dir / "s.e57");
  EXPECT_TRUE(stream.streamed());
  EXPECT_EQ(stream.size(), 2u * n);
  EXPECT_FALSE(stream.has_normals());
  const PointCloud read = read_point_cloud(dir / "s.e57");
  ASSERT_EQ(read.size(), n - n / 5 + n);
  Points world = read.positions;
  world.rowwise() += read.origin.transpose();
  for (const std::size_t block : {std::size_t{7}, std::size_t{1000}, std::size_t{3 * n}}) {
    stream.rewind();
    const PointCloud streamed = read_all(stream, block);
    ASSERT_EQ(streamed.size(), read.size()) << block;
    EXPECT_LT((streamed.positions - world).cwiseAbs().maxCoeff(), 1e-9)
        << block;  // the reader's shift is exact to rounding
  }

  std::string absent;
  for (const char* name : {"e57/A_B.e57", "e57/A_moved_B.e57", "e57/A_B_different_dims.e57", "e57/B2.e57"})
    if (!streams_as_read(name, 4096, 1e-6)) absent += std::string(" ") + name;
  if (!absent.empty()) GTEST_SKIP() << "shared samples absent under formats/:" << absent;
}

// A damaged E57 file: a broken XML is refused when opened; a non-finite coordinate and a
// section that ends before its records are refused when read, with their byte offset, and
// nothing is read on until a rewind.
TEST(PointStream, DamagedE57IsRefusedWithTheByteOffset) {
  using namespace clustersurf::test;
  const test::TempDir dir;
  const TestFile nan =
      write_e57({TestScan{{float_field("cartesianX", {1, 2, std::nan(""), 4}), float_field("cartesianY", {4, 5, 6, 7}),
                           float_field("cartesianZ", {7, 8, 9, 10})}}});
  write_file(dir / "nan.e57", nan.bytes);
  PointStream stream(dir / "nan.e57");
  PointCloud block;
  EXPECT_TRUE(stream.read(2, block));
  EXPECT_EQ(block.size(), 2);
  try {
    stream.read(2, block);
    FAIL() << "a NaN coordinate was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().byte_offset, std::optional<std::uint64_t>(nan.packets[0] + 12 + 16))
        << e.what();  // the third double of X
    EXPECT_NE(std::string(e.what()).find("point 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(stream.read(2, block), InputError);
  stream.rewind();
  EXPECT_TRUE(stream.read(2, block));
  ReadOptions drop;
  drop.drop_non_finite = true;
  PointStream dropping(dir / "nan.e57", drop);
  EXPECT_EQ(read_all(dropping, 3).positions, (Points(3, 3) << 1, 4, 7, 2, 5, 8, 4, 7, 10).finished());

  // A NaN in a record the scanner marked invalid is no error; the valid NaN after it is named
  // by its own byte, streamed and read whole alike.
  const TestFile masked = write_e57(
      {TestScan{{float_field("cartesianX", {std::nan(""), 1, std::nan(""), 4}), float_field("cartesianY", {4, 5, 6, 7}),
                 float_field("cartesianZ", {7, 8, 9, 10}), int_field("cartesianInvalidState", 0, 2, {2, 0, 0, 0})}}});
  write_file(dir / "masked.e57", masked.bytes);
  const std::uint64_t third_x = masked.packets[0] + 6 + 2 * 4 + 16;  // header, 4 buffer lengths, 2 doubles
  PointStream masked_stream(dir / "masked.e57");
  try {
    read_all(masked_stream, 4);
    FAIL() << "a NaN coordinate was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().byte_offset, std::optional<std::uint64_t>(third_x)) << e.what();
  }
  try {
    read_point_cloud(dir / "masked.e57");
    FAIL() << "a NaN coordinate was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().byte_offset, std::optional<std::uint64_t>(third_x)) << e.what();
  }

  TestScan short_scan{
      {float_field("cartesianX", {1, 2}), float_field("cartesianY", {4, 5}), float_field("cartesianZ", {7, 8})}};
  short_scan.record_count = "3";
  WriteOptions slack;
  slack.extra_packets = true;
  write_file(dir / "short.e57", write_e57({short_scan}, slack).bytes);
  PointStream truncated(dir / "short.e57");
  EXPECT_EQ(truncated.size(), 3u);
  try {
    truncated.read(3, block);
    FAIL() << "a section short of its records was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("section ends before all 3 records"), std::string::npos) << e.what();
    EXPECT_TRUE(e.where().byte_offset.has_value()) << e.what();
  }
  EXPECT_THROW(truncated.read(3, block), InputError);

  std::string broken = nan.bytes;
  broken.replace(nan.xml, 5, "<x57R");
  refresh_crcs(broken);
  write_file(dir / "broken.e57", broken);
  EXPECT_THROW(PointStream(dir / "broken.e57"), InputError);
}

// PTX, the terrestrial scanners' text export, is read in place like XYZ: every scan posed by
// its transform, the cells without a return left out, the reader's points block by block.
TEST(PointStream, PtxInBlocksIsTheReadersCloud) {
  const test::TempDir dir;
  const auto scan = [](int columns, int rows, const std::string& t) {
    return std::to_string(columns) + "\n" + std::to_string(rows) + "\n" + t + "\n1 0 0\n0 1 0\n0 0 1\n" +
           "0 1 0 0\n-1 0 0 0\n0 0 1 0\n" + t + " 1\n";
  };
  std::string text = scan(3, 2, "600000 4000000 12.5");
  for (int i = 0; i < 6; ++i)
    text += i == 2 ? "0 0 0 0.5\n" : std::to_string(i) + ".25 " + std::to_string(-i) + " 1.5 0.5\n";
  text += "\n" + scan(1, 3, "-5 7 0");
  text += "1 2 3 0.1\n0 0 0 0\n4 5 6 0.2\n";
  test::write_file(dir / "s.ptx", text);
  PointStream stream(dir / "s.ptx");
  EXPECT_TRUE(stream.streamed());
  EXPECT_EQ(stream.size(), 7u);
  EXPECT_FALSE(stream.has_normals());
  const PointCloud read = read_point_cloud(dir / "s.ptx");
  Points world = read.positions;
  world.rowwise() += read.origin.transpose();
  for (const std::size_t block : {std::size_t{1}, std::size_t{3}, std::size_t{100}}) {
    stream.rewind();
    EXPECT_EQ(read_all(stream, block).positions, world) << block;
  }
  EXPECT_EQ(world.row(0), Eigen::RowVector3d(600000, 4000000 + 0.25, 14));  // (x, y) turned 90°, then moved

  std::string absent;
  for (const char* name : {"ptx/multiple-and-transform.ptx", "ptx/complex-transform.ptx", "ptx/1.2-with-color.ptx"})
    if (!streams_as_read(name, 2, 1e-6)) absent += std::string(" ") + name;
  if (!absent.empty()) GTEST_SKIP() << "shared samples absent under formats/:" << absent;
}

// A damaged PTX file is refused when opened, with the line, as the reader refuses it; a NaN
// coordinate when its block is read.
TEST(PointStream, DamagedPtxIsRefusedWithTheLine) {
  const test::TempDir dir;
  const std::string header = "2\n2\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  test::write_file(dir / "short.ptx", header + "1 2 3 0.5\n4 5 6 0.5\n7 8 9 0.5\n");
  try {
    PointStream stream(dir / "short.ptx");
    FAIL() << "a scan short of its grid was opened";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, std::optional<std::uint64_t>(13)) << e.what();
    EXPECT_NE(std::string(e.what()).find("ends after 3 of 4 points"), std::string::npos) << e.what();
  }
  test::write_file(dir / "nan.ptx", header + "1 2 3 0.5\n4 5 6 0.5\nnan 8 9 0.5\n1 1 1 0.5\n");
  PointStream stream(dir / "nan.ptx");
  PointCloud block;
  EXPECT_TRUE(stream.read(2, block));
  try {
    stream.read(2, block);
    FAIL() << "a NaN coordinate was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, std::optional<std::uint64_t>(13)) << e.what();
  }
  EXPECT_THROW(stream.read(2, block), InputError);
  ReadOptions drop;
  drop.drop_non_finite = true;
  PointStream dropping(dir / "nan.ptx", drop);
  EXPECT_EQ(read_all(dropping, 3).size(), 3);
}

// PCD, PCL's format, ascii and binary, is read in place: the reader's points and normals block
// by block (a NaN position, PCL's "no point", left out); binary_compressed, whose fields lie one
// after another, is read whole.
TEST(PointStream, PcdInBlocksIsTheReadersCloud) {
  const test::TempDir dir;
  const std::string header =
      "VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z label\nSIZE 8 8 4 4 4 4 2\nTYPE F F F F F F U\n"
      "COUNT 1 1 1 1 1 1 1\nWIDTH 5\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 5\n";
  std::string binary = header + "DATA binary\n", ascii = header + "DATA ascii\n";
  for (int i = 0; i < 5; ++i) {
    const double x = 600000 + 0.25 * i, y = i == 3 ? std::nan("") : 4e6 - i;
    const float z = 1.5f * static_cast<float>(i), n[3] = {0, 0.6f, 0.8f};
    const std::uint16_t label = static_cast<std::uint16_t>(i);
    binary.append(reinterpret_cast<const char*>(&x), 8).append(reinterpret_cast<const char*>(&y), 8);
    binary.append(reinterpret_cast<const char*>(&z), 4).append(reinterpret_cast<const char*>(n), 12);
    binary.append(reinterpret_cast<const char*>(&label), 2);
    char line[160];
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.9g,0,0.6,0.8,%d\n", x, y, static_cast<double>(z), i);
    ascii += line;
  }
  test::write_file(dir / "b.pcd", binary);
  test::write_file(dir / "a.pcd", ascii);
  for (const char* name : {"b.pcd", "a.pcd"}) {
    PointStream stream(dir / name);
    EXPECT_TRUE(stream.streamed()) << name;
    EXPECT_EQ(stream.size(), 5u) << name;
    EXPECT_TRUE(stream.has_normals()) << name;
    const PointCloud read = read_point_cloud(dir / name);
    ASSERT_EQ(read.size(), 4) << name;
    Points world = read.positions;
    world.rowwise() += read.origin.transpose();
    for (const std::size_t block : {std::size_t{2}, std::size_t{5}}) {
      stream.rewind();
      const PointCloud streamed = read_all(stream, block);
      EXPECT_EQ(streamed.positions, world) << name << " " << block;
      EXPECT_EQ(streamed.normals, read.normals) << name << " " << block;
    }
  }

  std::string absent;
  for (const char* name : {"pcd/autzen-utm.pcd", "pcd/utm17_comma.pcd"})
    if (!streams_as_read(name, 100, 1e-6)) absent += std::string(" ") + name;
  if (!absent.empty()) GTEST_SKIP() << "shared samples absent under formats/:" << absent;
}

// binary_compressed PCD (LZF, each field's values one after another) is streamed too: one
// decoder per field, each resumed where its field begins, so no block needs the whole file
// decompressed. 30 k points in blocks of 777 and whole, after a rewind, are the reader's cloud.
TEST(PointStream, CompressedPcdInBlocksIsTheReadersCloud) {
  const test::TempDir dir;
  constexpr std::size_t n = 30000;
  std::vector<char> raw;
  auto put = [&raw](float v) {
    raw.insert(raw.end(), reinterpret_cast<const char*>(&v), reinterpret_cast<const char*>(&v) + 4);
  };
  for (int f = 0; f < 6; ++f)
    for (std::size_t i = 0; i < n; ++i) {
      const float values[6] = {static_cast<float>(i % 1000) * 0.25f,    static_cast<float>(i / 1000),
                               std::sin(static_cast<float>(i) * 0.01f), 0.0f,
                               i == 5 ? std::nanf("") : 0.6f,           0.8f};
      put(f == 0 && i == 9 ? std::nanf("") : values[f]);  // point 9 is PCL's "no point"
    }
  std::vector<char> packed(raw.size() + raw.size() / 16 + 64);
  const unsigned size =
      lzf_compress(raw.data(), static_cast<unsigned>(raw.size()), packed.data(), static_cast<unsigned>(packed.size()));
  ASSERT_GT(size, 0u);
  std::string bytes =
      "VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\n"
      "WIDTH 30000\nHEIGHT 1\nPOINTS 30000\nDATA binary_compressed\n";
  const std::uint32_t sizes[2] = {size, static_cast<std::uint32_t>(raw.size())};
  bytes.append(reinterpret_cast<const char*>(sizes), 8).append(packed.data(), size);
  test::write_file(dir / "c.pcd", bytes);

  ReadOptions drop;
  drop.drop_non_finite = true;  // point 5's normal is NaN
  PointStream stream(dir / "c.pcd", drop);
  EXPECT_TRUE(stream.streamed());
  EXPECT_EQ(stream.size(), n);
  EXPECT_TRUE(stream.has_normals());
  const PointCloud read = read_point_cloud(dir / "c.pcd", drop);
  ASSERT_EQ(read.size(), static_cast<Eigen::Index>(n) - 2);
  Points world = read.positions;
  world.rowwise() += read.origin.transpose();
  for (const std::size_t block : {std::size_t{777}, n}) {
    stream.rewind();
    const PointCloud streamed = read_all(stream, block);
    EXPECT_EQ(streamed.positions, world) << block;
    EXPECT_EQ(streamed.normals, read.normals) << block;
  }
  // Damaged LZF data is refused when the stream is opened, with its byte offset.
  bytes.erase(bytes.size() - size / 2);
  const std::uint32_t cut[1] = {size - size / 2};
  std::memcpy(bytes.data() + bytes.find("binary_compressed\n") + 18, cut, 4);
  test::write_file(dir / "cut.pcd", bytes);
  try {
    PointStream cut_stream(dir / "cut.pcd");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(e.where().byte_offset) << e.what();
    EXPECT_NE(std::string(e.what()).find("LZF data is corrupt"), std::string::npos) << e.what();
  }
}

// A damaged PCD file: binary records short of POINTS are refused when opened, with the byte
// offset of the data; an ascii line of the wrong width when its block is read, with its line.
TEST(PointStream, DamagedPcdIsRefusedWhereItIsDamaged) {
  const test::TempDir dir;
  const std::string header =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\n";
  test::write_file(dir / "short.pcd", header + "DATA binary\n" + std::string(30, '\0'));
  try {
    PointStream stream(dir / "short.pcd");
    FAIL() << "binary records short of POINTS were opened";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().byte_offset, std::optional<std::uint64_t>(header.size() + 12)) << e.what();
  }
  test::write_file(dir / "wide.pcd", header + "DATA ascii\n1 2 3\n4 5 6\n7 8 9 10\n");
  PointStream stream(dir / "wide.pcd");
  PointCloud block;
  EXPECT_TRUE(stream.read(2, block));
  EXPECT_EQ(block.size(), 2);
  try {
    stream.read(2, block);
    FAIL() << "a line of 4 values was read as a point of 3 fields";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, std::optional<std::uint64_t>(12)) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected 3 values, found 4"), std::string::npos) << e.what();
  }
  EXPECT_THROW(stream.read(2, block), InputError);  // not read on past the refused line
  stream.rewind();
  EXPECT_TRUE(stream.read(2, block));
}
