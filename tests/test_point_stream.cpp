// PointStream: a binary PLY of points read in place a block at a time gives the reader's
// points; other files are read whole; damaged files are refused with the byte offset.

#include <clustersurf/errors.hpp>
#include <clustersurf/point_cloud_io.hpp>
#include <clustersurf/point_stream.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// Every point of the stream, in blocks of `block`.
PointCloud read_all(PointStream& stream, std::size_t block) {
  PointCloud all, part;
  std::vector<Eigen::RowVector3d> p, n;
  while (stream.read(block, part)) {
    EXPECT_LE(part.size(), static_cast<Eigen::Index>(block));
    for (Eigen::Index i = 0; i < part.size(); ++i) {
      p.push_back(part.positions.row(i));
      if (part.has_normals()) n.push_back(part.normals.row(i));
    }
  }
  all.positions.resize(static_cast<Eigen::Index>(p.size()), 3);
  for (std::size_t i = 0; i < p.size(); ++i) all.positions.row(static_cast<Eigen::Index>(i)) = p[i];
  if (!n.empty()) {
    all.normals.resize(static_cast<Eigen::Index>(n.size()), 3);
    for (std::size_t i = 0; i < n.size(); ++i) all.normals.row(static_cast<Eigen::Index>(i)) = n[i];
  }
  return all;
}

}  // namespace

TEST(PointStream, BinaryPlyInBlocksIsTheReadersCloud) {
  const test::TempDir dir;
  PointCloud cloud = test::sample_torus(1000);
  cloud.positions.rowwise() += Eigen::RowVector3d(5e6, -3e6, 100);  // far from zero: no shift in the stream
  write_ply(dir / "t.ply", cloud);
  PointStream stream(dir / "t.ply");
  EXPECT_TRUE(stream.streamed());
  EXPECT_EQ(stream.size(), 1000u);
  EXPECT_TRUE(stream.has_normals());
  const PointCloud read = read_point_cloud(dir / "t.ply");
  const PointCloud streamed = read_all(stream, 64);
  Points world = read.positions;
  world.rowwise() += read.origin.transpose();
  EXPECT_EQ(streamed.positions, world);
  EXPECT_EQ(streamed.normals, read.normals);
  stream.rewind();
  EXPECT_EQ(read_all(stream, 1000).positions, world);
}

TEST(PointStream, OtherFilesAreReadWhole) {
  const test::TempDir dir;
  const PointCloud cloud = test::sample_sphere(300);
  write_xyz(dir / "s.xyz", cloud);
  PlyWriteOptions ascii;
  ascii.binary = false;
  write_ply(dir / "s.ply", cloud, ascii);
  for (const char* name : {"s.xyz", "s.ply"}) {
    PointStream stream(dir / name);
    EXPECT_FALSE(stream.streamed()) << name;
    EXPECT_EQ(read_all(stream, 50).positions, read_point_cloud(dir / name).positions) << name;
  }
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
