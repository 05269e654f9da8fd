// The PLY reader on hand-written files: every encoding and scalar type, normals and colors by
// their usual names, extra elements skipped (the Stanford scans' range_grid), faces, and a mesh
// read as a cloud taking its normals from its faces.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace clustersurf {
namespace {

using namespace clustersurf::test;

TEST(PlyReader, AsciiWithCommentsObjInfoAndCrlf) {
  TempDir dir;
  const std::string text =
      "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info num_cols 512\r\nelement vertex 3\r\n"
      "property float x\r\nproperty float y\r\nproperty float z\r\nend_header\r\n"
      "1 2 3\r\n-4.5 5e-1 +6\r\n  7\t8 9  \r\n";
  const PointCloud c = read_text(dir, "a.ply", text);
  EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}, {-4.5, 0.5, 6}, {7, 8, 9}})));
  EXPECT_FALSE(c.has_normals());
  EXPECT_FALSE(c.has_colors());
}

TEST(PlyReader, AllScalarTypesForCoordinatesInEveryEncoding) {
  TempDir dir;
  const std::vector<std::string> types = {"char", "uchar", "short", "ushort", "int",   "uint",   "float",   "double",
                                          "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  for (const std::string& type : types) {
    const bool is_unsigned = type.find('u') == 0;
    const bool is_float = type.find("float") == 0 || type == "double";
    Points expected(3, 3);
    if (is_float)
      expected << 1.5, -2.25, 100.125, 0, -0.5, 3e3, 7.75, 8, -9;
    else if (is_unsigned)
      expected << 1, 2, 100, 0, 5, 9, 127, 12, 3;
    else
      expected << -1, 2, -100, 0, -5, 9, 127, -128, 3;
    const std::string body =
        "element vertex 3\nproperty " + type + " x\nproperty " + type + " y\nproperty " + type + " z\n";
    for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
      SCOPED_TRACE(type + " " + format);
      std::string bytes = ply_header(format, body);
      if (format == "ascii") {
        for (Eigen::Index i = 0; i < 3; ++i)
          bytes += std::to_string(expected(i, 0)) + " " + std::to_string(expected(i, 1)) + " " +
                   std::to_string(expected(i, 2)) + "\n";
      } else {
        Bytes b;
        b.big = format == "binary_big_endian";
        for (Eigen::Index i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) b.put_as(type, expected(i, k));
        bytes += b.s;
      }
      const PointCloud c = read_text(dir, "t.ply", bytes);
      EXPECT_TRUE(mat_eq(c.positions, expected));
    }
  }
}

TEST(PlyReader, NormalsColorsAndExtraPropertiesBinaryBothEndians) {
  TempDir dir;
  const std::string body =
      "element vertex 2\nproperty double x\nproperty float confidence\nproperty double y\nproperty double z\n"
      "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\n"
      "property uchar blue\nproperty uchar alpha\nproperty int scan\n";
  for (bool big : {false, true}) {
    SCOPED_TRACE(big ? "big endian" : "little endian");
    Bytes b;
    b.big = big;
    b.put(0.1).put(0.5f).put(-0.2).put(1e10).floats({0, 0, 1}).put<std::uint8_t>(255).put<std::uint8_t>(0);
    b.put<std::uint8_t>(17).put<std::uint8_t>(99).put<std::int32_t>(-3);
    b.put(4.0).put(0.25f).put(5.0).put(6.0).floats({0.6f, 0.8f, 0}).put<std::uint8_t>(1).put<std::uint8_t>(2);
    b.put<std::uint8_t>(3).put<std::uint8_t>(4).put<std::int32_t>(7);
    const PointCloud c =
        read_text(dir, "n.ply", ply_header(big ? "binary_big_endian" : "binary_little_endian", body) + b.s);
    EXPECT_TRUE(mat_eq(c.positions, rows({{0.1, -0.2, 1e10}, {4, 5, 6}})));
    ASSERT_TRUE(c.has_normals());
    EXPECT_TRUE(mat_eq(c.normals, rows({{0, 0, 1}, {0.6f, 0.8f, 0}})));
    ASSERT_TRUE(c.has_colors());
    EXPECT_EQ(c.colors(0, 0), 255);
    EXPECT_EQ(c.colors(0, 1), 0);
    EXPECT_EQ(c.colors(0, 2), 17);
    EXPECT_EQ(c.colors(1, 0), 1);
    EXPECT_EQ(c.colors(1, 1), 2);
    EXPECT_EQ(c.colors(1, 2), 3);
  }
}

TEST(PlyReader, FloatAndUshortColorsAndAlternativeNames) {
  TempDir dir;
  const std::string text =
      ply_header("ascii", "element vertex 3\n" + kXyzFloat +
                              "property float normal_x\nproperty float normal_y\nproperty float normal_z\n"
                              "property float r\nproperty float g\nproperty float b\n") +
      "0 0 0 1 0 0 0 0.5 1\n1 1 1 0 1 0 1.5 -0.5 0.2\n2 2 2 0 0 -1 nan 0.999 0.001\n";
  const PointCloud c = read_text(dir, "f.ply", text);
  ASSERT_TRUE(c.has_colors());
  ASSERT_TRUE(c.has_normals());
  EXPECT_TRUE(mat_eq(c.normals, rows({{1, 0, 0}, {0, 1, 0}, {0, 0, -1}})));
  const std::vector<int> expected = {0, 128, 255, 255, 0, 51, 0, 255, 0};  // clamped, NaN → 0
  for (int i = 0; i < 9; ++i) EXPECT_EQ(c.colors(i / 3, i % 3), expected[static_cast<std::size_t>(i)]) << i;

  Bytes b;
  b.floats({0, 0, 0}).put<std::uint16_t>(65535).put<std::uint16_t>(0).put<std::uint16_t>(257 * 100);
  const PointCloud u =
      read_text(dir, "u.ply",
                ply_header("binary_little_endian", "element vertex 1\n" + kXyzFloat +
                                                       "property ushort diffuse_red\nproperty ushort diffuse_green\n"
                                                       "property ushort diffuse_blue\n") +
                    b.s);
  ASSERT_TRUE(u.has_colors());
  EXPECT_EQ(u.colors(0, 0), 255);
  EXPECT_EQ(u.colors(0, 1), 0);
  EXPECT_EQ(u.colors(0, 2), 100);
}

TEST(PlyReader, PartialNormalsOrColorsAreIgnored) {
  TempDir dir;
  const PointCloud c =
      read_text(dir, "p.ply",
                ply_header("ascii", "element vertex 1\n" + kXyzFloat + "property float nx\nproperty uchar red\n") +
                    "1 2 3 1 9\n");
  EXPECT_FALSE(c.has_normals());
  EXPECT_FALSE(c.has_colors());
}

TEST(PlyReader, SkipsRangeGridAfterVerticesLikeTheStanfordScans) {
  TempDir dir;
  const std::string body = "obj_info num_cols 2\nobj_info num_rows 2\nelement vertex 2\n" + kXyzFloat +
                           "element range_grid 4\nproperty list uchar int vertex_indices\n";
  // ascii
  const PointCloud a = read_text(dir, "a.ply", ply_header("ascii", body) + "1 2 3\n4 5 6\n1 0\n0\n0\n1 1\n");
  EXPECT_TRUE(mat_eq(a.positions, rows({{1, 2, 3}, {4, 5, 6}})));
  // binary, both endians
  for (bool big : {false, true}) {
    Bytes b;
    b.big = big;
    b.floats({1, 2, 3, 4, 5, 6});
    b.put<std::uint8_t>(1).put<std::int32_t>(0).put<std::uint8_t>(0).put<std::uint8_t>(0);
    b.put<std::uint8_t>(1).put<std::int32_t>(1);
    const PointCloud c =
        read_text(dir, "b.ply", ply_header(big ? "binary_big_endian" : "binary_little_endian", body) + b.s);
    EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}, {4, 5, 6}})));
  }
  // Elements before the vertices are skipped too, and a vertex element with a list property.
  Bytes b;
  b.put<std::uint8_t>(2).put<std::int16_t>(7).put<std::int16_t>(8).put<std::uint8_t>(0);  // 2 "junk" records
  b.floats({1, 2}).put<std::uint8_t>(3).put(1.0f).put(2.0f).put(3.0f).floats({3});
  b.floats({4, 5}).put<std::uint8_t>(0).floats({6});
  const PointCloud c = read_text(
      dir, "c.ply",
      ply_header("binary_little_endian",
                 "element junk 2\nproperty list uchar short v\nelement vertex 2\nproperty float x\nproperty float y\n"
                 "property list uchar float extra\nproperty float z\n") +
          b.s);
  EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}, {4, 5, 6}})));
}

TEST(PlyReader, FacesAreFanTriangulated) {
  TempDir dir;
  const std::string body =
      "element vertex 5\n" + kXyzFloat + "element face 3\nproperty list uchar int vertex_indices\n";
  const Triangles expected = (Triangles(4, 3) << 0, 1, 2, 0, 2, 3, 4, 0, 1, 1, 2, 4).finished();
  const TriangleMesh a = read_mesh_text(
      dir, "a.ply",
      ply_header("ascii", body) + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 2\n" + "4 0 1 2 3\n3 4 0 1\n3 1 2 4\n");
  EXPECT_EQ(a.vertices.rows(), 5);
  EXPECT_TRUE(mat_eq(a.triangles, expected));
  for (bool big : {false, true}) {
    Bytes b;
    b.big = big;
    b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 2, 2});
    b.put<std::uint8_t>(4).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2).put<std::int32_t>(3);
    b.put<std::uint8_t>(3).put<std::int32_t>(4).put<std::int32_t>(0).put<std::int32_t>(1);
    b.put<std::uint8_t>(3).put<std::int32_t>(1).put<std::int32_t>(2).put<std::int32_t>(4);
    const TriangleMesh m =
        read_mesh_text(dir, "b.ply", ply_header(big ? "binary_big_endian" : "binary_little_endian", body) + b.s);
    EXPECT_TRUE(mat_eq(m.triangles, expected));
  }
  // Faces may come before the vertices; "vertex_index" and other index types are accepted;
  // points and edges (fewer than 3 indices) carry no triangles.
  const TriangleMesh f = read_mesh_text(
      dir, "f.ply",
      ply_header("ascii", "element face 3\nproperty list int ushort vertex_index\nelement vertex 4\n" + kXyzFloat) +
          "4 0 1 2 3\n2 0 1\n1 3\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n");
  EXPECT_TRUE(mat_eq(f.triangles, (Triangles(2, 3) << 0, 1, 2, 0, 2, 3).finished()));
  // Read as a point cloud with its vertices, faces are skipped.
  ReadOptions vertices;
  vertices.mesh_samples = 0;
  EXPECT_EQ(read_point_cloud(dir / "f.ply", vertices).size(), 4);
}

namespace {

/// An ascii PLY tetrahedron (outward winding) with `extra` unreferenced vertices and the given
/// face lines.
std::string tetrahedron_ply(int extra = 0, const std::string& faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n") {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(4 + extra) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face 4\n"
                  "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  for (int i = 0; i < extra; ++i) s += "5 5 5\n";
  return s + faces;
}

}  // namespace

TEST(PlyReader, AMeshReadAsACloudTakesItsNormalsFromItsFaces) {
  ReadOptions vertices;
  vertices.mesh_samples = 0;
  const PointCloud c = parse_point_cloud(tetrahedron_ply(), FileFormat::Ply, "<memory>", vertices);
  ASSERT_EQ(c.normals.rows(), 4);
  // Outward: away from the tetrahedron's centroid at every vertex.
  const Eigen::RowVector3d centroid(0.25, 0.25, 0.25);
  for (Eigen::Index v = 0; v < 4; ++v) {
    EXPECT_NEAR(c.normals.row(v).norm(), 1, 1e-12);
    EXPECT_GT(c.normals.row(v).dot(c.positions.row(v) - centroid), 0) << "vertex " << v;
  }
  // The origin's three faces are the axis planes: equal weights, normal -(1,1,1)/√3.
  EXPECT_NEAR(c.normals(0, 0), -1 / std::sqrt(3.0), 1e-6);
  // Off by option, or where a vertex belongs to no face, or where the faces are broken: none.
  ReadOptions off = vertices;
  off.normals_from_faces = false;
  EXPECT_EQ(parse_point_cloud(tetrahedron_ply(), FileFormat::Ply, "<memory>", off).normals.rows(), 0);
  EXPECT_EQ(parse_point_cloud(tetrahedron_ply(1), FileFormat::Ply, "<memory>", vertices).normals.rows(), 0);
  const PointCloud broken = parse_point_cloud(tetrahedron_ply(0, "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 9\n"),
                                              FileFormat::Ply, "<memory>", vertices);
  EXPECT_EQ(broken.size(), 4);
  EXPECT_EQ(broken.normals.rows(), 0);
}

/// Distance from `p` to the surface of the tetrahedron (0,0,0), e_x, e_y, e_z: the smallest
/// distance to its four face planes, for a point on or near a face.
double distance_to_tetrahedron(const Eigen::Vector3d& p) {
  const double slanted = std::abs(p.sum() - 1) / std::sqrt(3.0);
  return std::min({std::abs(p.x()), std::abs(p.y()), std::abs(p.z()), slanted});
}

TEST(PlyReader, ASmallMeshIsReadAsSamplesOfItsFaces) {
  ReadOptions options;
  options.mesh_samples = 2000;
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& m) { warnings.push_back(m); };
  const PointCloud c = parse_point_cloud(tetrahedron_ply(), FileFormat::Ply, "tet.ply", options);
  ASSERT_EQ(c.size(), 2000);
  ASSERT_EQ(c.normals.rows(), 2000);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("tet.ply: a mesh of 4 vertices, read as 2000 points"), std::string::npos) << warnings[0];
  // On the faces, facing out, and covering all four of them (area-uniform: the slanted face,
  // √3 times the others' area, holds about 37 % of the points).
  const Eigen::Vector3d centroid(0.25, 0.25, 0.25);
  int slanted = 0;
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    const Eigen::Vector3d p = c.positions.row(i).transpose(), n = c.normals.row(i).transpose();
    EXPECT_LT(distance_to_tetrahedron(p), 1e-12) << "point " << i;
    EXPECT_GT(n.dot(p - centroid), 0) << "point " << i;
    slanted += std::abs(p.sum() - 1) < 1e-9;
  }
  EXPECT_NEAR(slanted / 2000.0, std::sqrt(3.0) / (3 + std::sqrt(3.0)), 0.04);
  // The same points on every read.
  EXPECT_TRUE(parse_point_cloud(tetrahedron_ply(), FileFormat::Ply, "tet.ply", options).positions == c.positions);
  // Vertex normals that disagree with the winding turn the faces: the samples follow the normals.
  const std::string inward_header =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\nelement face 4\nproperty list uchar int "
      "vertex_indices\n"
      "end_header\n0 0 0 -1 -1 -1\n1 0 0 1 0 0\n0 1 0 0 1 0\n0 0 1 0 0 1\n";
  const PointCloud flipped =
      parse_point_cloud(inward_header + "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n", FileFormat::Ply, "f.ply", options);
  ASSERT_EQ(flipped.size(), 2000);
  for (Eigen::Index i = 0; i < flipped.size(); ++i)
    EXPECT_GT(flipped.normals.row(i).dot(flipped.positions.row(i) - centroid.transpose()), 0) << "point " << i;
  // A mesh with as many vertices as the samples asked for, or none asked for: its vertices.
  options.mesh_samples = 4;
  EXPECT_EQ(parse_point_cloud(tetrahedron_ply(), FileFormat::Ply, "tet.ply", options).size(), 4);
  options.mesh_samples = 0;
  EXPECT_EQ(parse_point_cloud(tetrahedron_ply(), FileFormat::Ply, "tet.ply", options).size(), 4);
  // Faces that do not hold together: the vertices stand alone.
  options.mesh_samples = 2000;
  EXPECT_EQ(
      parse_point_cloud(tetrahedron_ply(0, "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 9\n"), FileFormat::Ply, "b.ply", options)
          .size(),
      4);
  EXPECT_EQ(
      parse_point_cloud(tetrahedron_ply(0, "3 0 0 1\n3 1 1 2\n3 2 2 3\n3 3 3 0\n"), FileFormat::Ply, "z.ply", options)
          .size(),
      4);
}

// Which scan saw each point, a "scan" property, is read as the cloud's scan of each point and
// written back the same way; a "scan" property holding anything but whole numbers >= 0 is some
// other property, skipped.
TEST(PlyReader, AScanPropertyNamesEachPointsScan) {
  TempDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar scan\nend_header\n";
  const PointCloud c = read_text(dir, "s.ply", header + "0 0 0 0\n1 0 0 2\n0 1 0 1\n");
  EXPECT_EQ(c.scanner_of_point, (std::vector<std::uint32_t>{0, 2, 1}));
  write_point_cloud(dir / "back.ply", c);
  EXPECT_EQ(read_point_cloud(dir / "back.ply").scanner_of_point, c.scanner_of_point);
  const std::string floats =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "property float scan\nend_header\n0 0 0 1\n1 0 0 1.5\n";
  const PointCloud other = read_text(dir, "other.ply", floats);
  EXPECT_EQ(other.size(), 2);
  EXPECT_FALSE(other.has_scanners());
}

TEST(PlyReader, AMeshFarFromZeroIsSampledWhereItIs) {
  const std::string far =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
      "5000000 7000000 100\n5000001 7000000 100\n5000000 7000001 100\n5000000 7000000 101\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  ReadOptions options;
  options.mesh_samples = 500;
  const PointCloud c = parse_point_cloud(far, FileFormat::Ply, "far.ply", options);
  ASSERT_EQ(c.size(), 500);
  EXPECT_GT(c.origin.norm(), 1e6);  // shifted next to zero, as the vertices would be
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    const Eigen::Vector3d p = c.positions.row(i).transpose() + c.origin - Eigen::Vector3d(5000000, 7000000, 100);
    EXPECT_LT(distance_to_tetrahedron(p), 1e-6) << "point " << i;
  }
}

}  // namespace
}  // namespace clustersurf
