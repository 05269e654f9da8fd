// Point-cloud and mesh I/O: round trips through every writer, the readers on hand-written files
// (every PLY encoding and scalar type, XYZ/PTS, OBJ), a table of malformed files with the exact
// error location each must report, and the real scans of the shared data folder.

#include "test_support.hpp"

#include <clustersurf/errors.hpp>
#include <clustersurf/point_cloud_io.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace clustersurf {
namespace {

using test::TempDir;
using test::write_file;

// ---------------------------------------------------------------------------------------------
// Helpers

/// Bit-exact comparison (distinguishes -0.0 from 0.0 and compares NaN payloads).
::testing::AssertionResult same_bits(const Points& a, const Points& b) {
  if (a.rows() != b.rows()) return ::testing::AssertionFailure() << "rows " << a.rows() << " != " << b.rows();
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (int c = 0; c < 3; ++c)
      if (std::bit_cast<std::uint64_t>(a(i, c)) != std::bit_cast<std::uint64_t>(b(i, c)))
        return ::testing::AssertionFailure() << "(" << i << ", " << c << "): " << a(i, c) << " vs " << b(i, c);
  return ::testing::AssertionSuccess();
}

/// Exact equality of two matrices, sizes first (Eigen's == requires equal sizes).
template <class A, class B>
::testing::AssertionResult mat_eq(const A& a, const B& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    return ::testing::AssertionFailure() << "size " << a.rows() << "x" << a.cols() << " vs " << b.rows() << "x" << b.cols();
  if (a != b) return ::testing::AssertionFailure() << "\n" << a.template cast<double>() << "\nvs\n" << b.template cast<double>();
  return ::testing::AssertionSuccess();
}

/// A cloud whose values need every bit of a double: random, tiny, huge, negative zero.
PointCloud awkward_cloud(int n, bool normals, bool colors, unsigned seed = 3) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::uniform_int_distribution<int> byte(0, 255);
  PointCloud c;
  c.positions.resize(n, 3);
  for (int i = 0; i < n; ++i) c.positions.row(i) << u(rng), u(rng) * 1e-3, u(rng) * 1e5;
  if (n >= 4) {
    c.positions.row(0) << 0.1, 1.0 / 3.0, -0.0;
    c.positions.row(1) << 1e-300, -1e300, 5e-324;  // includes a denormal
    c.positions.row(2) << 123456789.123456789, -2.5, 0.0;
    c.positions.row(3) << std::nextafter(1.0, 2.0), std::nextafter(1.0, 0.0), -std::numeric_limits<double>::max();
  }
  if (normals) {
    c.normals.resize(n, 3);
    for (int i = 0; i < n; ++i) {
      Eigen::Vector3d v(u(rng), u(rng), u(rng));
      c.normals.row(i) = v.normalized().transpose();
    }
  }
  if (colors) {
    c.colors.resize(n, 3);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) c.colors(i, k) = static_cast<std::uint8_t>(byte(rng));
  }
  return c;
}

/// Little- or big-endian byte builder for binary PLY data.
struct Bytes {
  bool big = false;
  std::string s;

  template <class T>
  Bytes& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
    return *this;
  }
  /// Appends `v` converted to the PLY scalar type `type`.
  Bytes& put_as(std::string type, double v) {
    static const std::map<std::string, std::string> alias = {{"int8", "char"},   {"uint8", "uchar"}, {"int16", "short"},
                                                             {"uint16", "ushort"}, {"int32", "int"},  {"uint32", "uint"},
                                                             {"float32", "float"}, {"float64", "double"}};
    if (const auto it = alias.find(type); it != alias.end()) type = it->second;
    if (type == "char") return put(static_cast<std::int8_t>(v));
    if (type == "uchar") return put(static_cast<std::uint8_t>(v));
    if (type == "short") return put(static_cast<std::int16_t>(v));
    if (type == "ushort") return put(static_cast<std::uint16_t>(v));
    if (type == "int") return put(static_cast<std::int32_t>(v));
    if (type == "uint") return put(static_cast<std::uint32_t>(v));
    if (type == "float") return put(static_cast<float>(v));
    if (type == "double") return put(v);
    ADD_FAILURE() << "unknown type " << type;
    return *this;
  }
  Bytes& floats(std::initializer_list<float> v) {
    for (float f : v) put(f);
    return *this;
  }
};

std::string ply_header(const std::string& format, const std::string& body) {
  return "ply\nformat " + format + " 1.0\n" + body + "end_header\n";
}
const std::string kXyzFloat = "property float x\nproperty float y\nproperty float z\n";

PointCloud read_text(const TempDir& dir, const std::string& name, const std::string& bytes, const ReadOptions& o = {}) {
  write_file(dir / name, bytes);
  return read_point_cloud(dir / name, o);
}
TriangleMesh read_mesh_text(const TempDir& dir, const std::string& name, const std::string& bytes) {
  write_file(dir / name, bytes);
  return read_triangle_mesh(dir / name);
}

Points rows(std::initializer_list<std::array<double, 3>> r) {
  Points p(static_cast<Eigen::Index>(r.size()), 3);
  Eigen::Index i = 0;
  for (const auto& row : r) p.row(i++) << row[0], row[1], row[2];
  return p;
}

// ---------------------------------------------------------------------------------------------
// Round trips

TEST(PlyRoundTrip, DoublePrecisionIsBitExactBinaryAndAscii) {
  TempDir dir;
  const PointCloud c = awkward_cloud(500, true, true);
  for (bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    PlyWriteOptions o;
    o.binary = binary;
    o.double_precision = true;
    const auto file = dir / (binary ? "b.ply" : "a.ply");
    write_ply(file, c, o);
    const PointCloud r = read_point_cloud(file);
    EXPECT_TRUE(same_bits(r.positions, c.positions));
    EXPECT_TRUE(same_bits(r.normals, c.normals));
    ASSERT_TRUE(r.has_colors());
    EXPECT_TRUE(mat_eq(r.colors, c.colors));
  }
}

TEST(PlyRoundTrip, FloatModeKeepsFloatPrecision) {
  TempDir dir;
  PointCloud c = awkward_cloud(300, true, true);
  c.positions.row(1) << 1e-30, -1e30, 7.0;  // stay inside float range
  c.positions.row(3) << 1.0, 2.0, -3.0e38;
  for (bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    PlyWriteOptions o;
    o.binary = binary;
    const auto file = dir / (binary ? "b.ply" : "a.ply");
    write_ply(file, c, o);
    const std::string bytes = test::read_file(file);
    EXPECT_NE(bytes.find("property float x"), std::string::npos);
    const PointCloud r = read_point_cloud(file);
    ASSERT_EQ(r.size(), c.size());
    for (Eigen::Index i = 0; i < c.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const float pf = static_cast<float>(c.positions(i, k)), nf = static_cast<float>(c.normals(i, k));
        if (binary) {
          // Binary float is exactly the float the value rounds to.
          EXPECT_EQ(r.positions(i, k), static_cast<double>(pf));
          EXPECT_EQ(r.normals(i, k), static_cast<double>(nf));
        } else {
          // Text holds the shortest decimal that reads back as that float.
          EXPECT_EQ(static_cast<float>(r.positions(i, k)), pf) << i << "," << k;
          EXPECT_EQ(static_cast<float>(r.normals(i, k)), nf) << i << "," << k;
        }
        EXPECT_NEAR(r.positions(i, k), c.positions(i, k), 1e-7 * std::max(1.0, std::abs(c.positions(i, k))));
      }
    EXPECT_TRUE(mat_eq(r.colors, c.colors));
  }
}

TEST(PlyRoundTrip, WithoutNormalsOrColors) {
  TempDir dir;
  const PointCloud c = awkward_cloud(50, false, false);
  PlyWriteOptions o;
  o.double_precision = true;
  write_ply(dir / "p.ply", c, o);
  const PointCloud r = read_point_cloud(dir / "p.ply");
  EXPECT_TRUE(same_bits(r.positions, c.positions));
  EXPECT_FALSE(r.has_normals());
  EXPECT_FALSE(r.has_colors());
}

TEST(XyzRoundTrip, IsBitExact) {
  TempDir dir;
  for (bool normals : {false, true}) {
    SCOPED_TRACE(normals ? "with normals" : "positions only");
    const PointCloud c = awkward_cloud(400, normals, false);
    write_xyz(dir / "c.xyz", c);
    const PointCloud r = read_point_cloud(dir / "c.xyz");
    EXPECT_TRUE(same_bits(r.positions, c.positions));
    EXPECT_EQ(r.has_normals(), normals);
    if (normals) {
      EXPECT_TRUE(same_bits(r.normals, c.normals));
    }
  }
}

TriangleMesh small_mesh(bool normals, bool colors) {
  TriangleMesh m;
  const PointCloud c = awkward_cloud(6, normals, colors, 11);
  m.vertices = c.positions;
  m.normals = c.normals;
  m.colors = c.colors;
  m.triangles.resize(4, 3);
  m.triangles << 0, 1, 2, 2, 1, 3, 3, 4, 5, 5, 0, 3;
  return m;
}

TEST(ObjRoundTrip, VerticesNormalsColorsAndFaces) {
  TempDir dir;
  for (bool normals : {false, true}) {
    SCOPED_TRACE(normals ? "with normals" : "without normals");
    const TriangleMesh m = small_mesh(normals, true);
    write_obj(dir / "m.obj", m);
    const TriangleMesh r = read_triangle_mesh(dir / "m.obj");
    EXPECT_TRUE(same_bits(r.vertices, m.vertices));
    EXPECT_TRUE(mat_eq(r.triangles, m.triangles));
    EXPECT_EQ(r.normals.rows(), normals ? m.vertices.rows() : 0);
    if (normals) {
      EXPECT_TRUE(same_bits(r.normals, m.normals));
    }
    EXPECT_TRUE(mat_eq(r.colors, m.colors));  // written as c/255 with 4 decimals: rounds back exactly
    // The same file read as a point cloud gives the vertices.
    EXPECT_TRUE(same_bits(read_point_cloud(dir / "m.obj").positions, m.vertices));
  }
}

TEST(PlyRoundTrip, MeshBinaryAndAscii) {
  TempDir dir;
  const TriangleMesh m = small_mesh(true, true);
  for (bool binary : {true, false}) {
    PlyWriteOptions o;
    o.binary = binary;
    o.double_precision = true;
    write_ply(dir / "m.ply", m, o);
    const TriangleMesh r = read_triangle_mesh(dir / "m.ply");
    EXPECT_TRUE(same_bits(r.vertices, m.vertices));
    EXPECT_TRUE(same_bits(r.normals, m.normals));
    EXPECT_TRUE(mat_eq(r.colors, m.colors));
    EXPECT_TRUE(mat_eq(r.triangles, m.triangles));
  }
}

TEST(Writers, WritePointCloudDispatchesByExtension) {
  TempDir dir;
  const PointCloud c = awkward_cloud(20, true, false);
  for (const char* name : {"c.ply", "c.xyz", "c.obj", "c.PTS"}) {
    SCOPED_TRACE(name);
    PlyWriteOptions o;
    o.double_precision = true;
    write_point_cloud(dir / name, c, o);
    const PointCloud r = read_point_cloud(dir / name);
    EXPECT_TRUE(same_bits(r.positions, c.positions));
    EXPECT_TRUE(same_bits(r.normals, c.normals));
  }
  EXPECT_THROW(write_point_cloud(dir / "c.vtk", c), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "c.vtk"));
}

TEST(Writers, FailedWriteLeavesNoFileBehind) {
  TempDir dir;
  const PointCloud c = awkward_cloud(5, false, false);
  EXPECT_THROW(write_ply(dir / "missing-folder" / "c.ply", c), IoError);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// ---------------------------------------------------------------------------------------------
// Readers on hand-written files

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
  const std::vector<std::string> types = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double",
                                          "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  for (const std::string& type : types) {
    const bool is_unsigned = type.find('u') == 0;
    const bool is_float = type.find("float") == 0 || type == "double";
    Points expected(3, 3);
    if (is_float) expected << 1.5, -2.25, 100.125, 0, -0.5, 3e3, 7.75, 8, -9;
    else if (is_unsigned) expected << 1, 2, 100, 0, 5, 9, 127, 12, 3;
    else expected << -1, 2, -100, 0, -5, 9, 127, -128, 3;
    const std::string body = "element vertex 3\nproperty " + type + " x\nproperty " + type + " y\nproperty " + type +
                             " z\n";
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
  const std::string text = ply_header("ascii",
                                      "element vertex 3\n" + kXyzFloat +
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
  const PointCloud u = read_text(
      dir, "u.ply",
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
  const PointCloud c = read_text(
      dir, "p.ply",
      ply_header("ascii", "element vertex 1\n" + kXyzFloat + "property float nx\nproperty uchar red\n") + "1 2 3 1 9\n");
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
  const TriangleMesh a = read_mesh_text(dir, "a.ply",
                                        ply_header("ascii", body) + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 2\n" +
                                            "4 0 1 2 3\n3 4 0 1\n3 1 2 4\n");
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
      ply_header("ascii",
                 "element face 3\nproperty list int ushort vertex_index\nelement vertex 4\n" + kXyzFloat) +
          "4 0 1 2 3\n2 0 1\n1 3\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n");
  EXPECT_TRUE(mat_eq(f.triangles, (Triangles(2, 3) << 0, 1, 2, 0, 2, 3).finished()));
  // Read as a point cloud, faces are skipped.
  EXPECT_EQ(read_point_cloud(dir / "f.ply").size(), 4);
}

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

TEST(ObjReader, ColorsNormalsAndNegativeIndices) {
  TempDir dir;
  const std::string text =
      "# cube corner\nmtllib none.mtl\no thing\n"
      "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 0.5 0.5 0.5\n"
      "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 -1\nvt 0 0\ns off\n"
      "f 1/1/1 2/1/2 3/1/3 4/1/4\nf -4//-4 -2//-2 -1//-1\nl 1 2\n";
  const TriangleMesh m = read_mesh_text(dir, "m.obj", text);
  EXPECT_TRUE(mat_eq(m.vertices, rows({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}})));
  EXPECT_TRUE(mat_eq(m.triangles, (Triangles(3, 3) << 0, 1, 2, 0, 2, 3, 0, 2, 3).finished()));
  EXPECT_TRUE(mat_eq(m.normals, rows({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, -1}})));
  EXPECT_EQ(m.colors.rows(), 4);
  EXPECT_EQ(m.colors(0, 0), 255);
  EXPECT_EQ(m.colors(1, 1), 255);
  EXPECT_EQ(m.colors(2, 2), 255);
  EXPECT_EQ(m.colors(3, 0), 128);
  // Negative indices count back from the vertices defined so far.
  const TriangleMesh n = read_mesh_text(dir, "n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf -1 -2 -3\n");
  EXPECT_TRUE(mat_eq(n.triangles, (Triangles(2, 3) << 0, 1, 2, 3, 2, 1).finished()));
  EXPECT_EQ(n.colors.rows(), 0);   // no colors at all
  EXPECT_EQ(n.normals.rows(), 0);  // no normals
  // v with a w component, mixed colored/uncolored vertices: no colors.
  const PointCloud c = read_text(dir, "c.obj", "v 1 2 3 1\nv 4 5 6 0.1 0.2 0.3\n");
  EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}, {4, 5, 6}})));
  EXPECT_FALSE(c.has_colors());
}

TEST(Readers, PlyIsRecognisedByMagicWhateverTheExtension) {
  TempDir dir;
  const PointCloud c = read_text(dir, "cloud.xyz", ply_header("ascii", "element vertex 1\n" + kXyzFloat) + "1 2 3\n");
  EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}})));
  EXPECT_EQ(format_from_extension("A.PLY"), FileFormat::Ply);
  EXPECT_EQ(format_from_extension("a.pts"), FileFormat::Xyz);
  EXPECT_EQ(format_from_extension("a.Obj"), FileFormat::Obj);
  EXPECT_THROW(format_from_extension("a"), InputError);
}

// ---------------------------------------------------------------------------------------------
// Malformed files

enum class Expect { Input, Io };
enum class Kind { File, Directory, Missing };

struct BadFile {
  std::string label;
  std::string name;  // file name (its extension picks the format)
  std::string bytes;
  Expect type = Expect::Input;
  std::string message;  // expected substring of what()
  std::optional<std::uint64_t> line = std::nullopt;
  std::optional<std::uint64_t> byte = std::nullopt;
  bool mesh = false;  // read with read_triangle_mesh instead of read_point_cloud
  Kind kind = Kind::File;
};

std::ostream& operator<<(std::ostream& os, const BadFile& f) { return os << f.label; }

const std::string kAsciiXyzHeader = ply_header("ascii", "element vertex 2\n" + kXyzFloat);  // 7 lines
const std::string kBinXyzHeader = ply_header("binary_little_endian", "element vertex 4\n" + kXyzFloat);

std::string binary_cloud_with_nan() {
  Bytes b;
  b.floats({1, 2, 3, 4, 5, 6, 7, std::numeric_limits<float>::quiet_NaN(), 9, 10, 11, 12});
  return kBinXyzHeader + b.s;
}

std::vector<BadFile> bad_files() {
  std::vector<BadFile> t;
  const std::uint64_t bin_data = kBinXyzHeader.size();
  // Generic
  t.push_back({"empty file", "empty.ply", "", Expect::Input, "file is empty"});
  t.push_back({"unknown extension", "points.abc", "1 2 3\n", Expect::Input, "unknown file format \".abc\""});
  t.push_back({"directory", "folder.ply", "", Expect::Io, "is a directory", {}, {}, false, Kind::Directory});
  t.push_back({"missing file", "missing.ply", "", Expect::Io, "cannot open", {}, {}, false, Kind::Missing});
  t.push_back({"zero vertices", "zero.ply", ply_header("ascii", "element vertex 0\n" + kXyzFloat), Expect::Input,
               "no points"});
  t.push_back({"xyz of comments only", "c.xyz", "# nothing\n\n", Expect::Input, "no points"});
  // PLY header
  t.push_back({"not ply", "text.ply", "hello\n1 2 3\n", Expect::Input, "not a PLY file", 1});
  t.push_back({"no end_header", "noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",
               Expect::Input, "no \"end_header\"", 5});
  t.push_back({"header cut mid-line", "cut.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty flo", Expect::Input,
               "no \"end_header\"", 4});
  t.push_back({"unknown format", "fmt.ply", ply_header("binary_middle_endian", "element vertex 1\n" + kXyzFloat),
               Expect::Input, "unknown PLY format \"binary_middle_endian\"", 2});
  t.push_back({"format without version", "fmt2.ply", "ply\nformat ascii\nend_header\n", Expect::Input,
               "expected \"format", 2});
  t.push_back({"unsupported version", "ver.ply", "ply\nformat ascii 2.0\nend_header\n", Expect::Input,
               "unsupported PLY version \"2.0\"", 2});
  t.push_back({"no format line", "nofmt.ply", "ply\nelement vertex 1\n" + kXyzFloat + "end_header\n1 2 3\n",
               Expect::Input, "no \"format\" line", 2});
  t.push_back({"unknown scalar type", "type.ply",
               ply_header("ascii", "element vertex 1\nproperty float x\nproperty float128 y\nproperty float z\n") + "1 2 3\n",
               Expect::Input, "unknown scalar type \"float128\"", 5});
  t.push_back({"float list count", "list.ply",
               ply_header("ascii", "element vertex 1\n" + kXyzFloat + "element face 1\nproperty list float int v\n"),
               Expect::Input, "list count type must be an integer", 8});
  t.push_back({"property before element", "prop.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n",
               Expect::Input, "property before any element", 3});
  t.push_back({"negative count", "neg.ply", "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", Expect::Input,
               "non-negative count", 3});
  t.push_back({"junk header line", "junk.ply", "ply\nformat ascii 1.0\nelement vertex 1\nhello there\nend_header\n",
               Expect::Input, "unexpected PLY header line \"hello there\"", 4});
  t.push_back({"vertex without z", "noz.ply",
               ply_header("ascii", "element vertex 1\nproperty float x\nproperty float y\n") + "1 2\n", Expect::Input,
               "lacks one of the properties x, y, z", 3});
  t.push_back({"no vertex element", "novert.ply", ply_header("ascii", "element point 1\n" + kXyzFloat) + "1 2 3\n",
               Expect::Input, "no \"vertex\" element", 1});
  // Binary data
  t.push_back({"truncated binary vertices", "trunc.ply", kBinXyzHeader + std::string(12 * 3 + 6, '\0'),
               Expect::Input, "file ends inside vertex 3 of 4", std::nullopt, bin_data + 36});
  {
    Bytes b;
    b.floats({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    b.put<std::uint8_t>(1).put<std::int32_t>(0).put<std::uint8_t>(0).put<std::uint8_t>(1).put<std::int32_t>(1);
    t.push_back({"truncated binary list element", "grid.ply",
                 ply_header("binary_little_endian",
                            "element vertex 4\n" + kXyzFloat + "element range_grid 5\nproperty list uchar int v\n") +
                     b.s,
                 Expect::Input, "file ends inside range_grid 3 of 5", std::nullopt,
                 ply_header("binary_little_endian",
                            "element vertex 4\n" + kXyzFloat + "element range_grid 5\nproperty list uchar int v\n")
                         .size() +
                     48 + 11});
    Bytes c;
    c.floats({1, 2, 3}).put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1);  // list cut short
    const std::string h = ply_header("binary_little_endian", "element vertex 1\nproperty float x\nproperty float y\n"
                                                             "property float z\nelement face 1\n"
                                                             "property list uchar int vertex_indices\n");
    t.push_back({"truncated binary list", "list.ply", h + c.s, Expect::Input, "file ends inside face 0 of 1",
                 std::nullopt, h.size() + 13});
  }
  t.push_back({"bytes after the last element", "extra.ply", kBinXyzHeader + std::string(12 * 4, '\0') + "JUNK",
               Expect::Input, "4 unexpected bytes after the last element", std::nullopt, bin_data + 48});
  t.push_back({"binary NaN", "nan.ply", binary_cloud_with_nan(), Expect::Input, "point 2 (0-based) has a non-finite",
               std::nullopt, bin_data + 24});
  {
    const std::string h = ply_header("binary_little_endian", "element vertex 50000000000\n" + kXyzFloat);
    t.push_back({"absurd vertex count, binary", "huge.ply", h + std::string(36, '\0'), Expect::Input,
                 "file ends inside vertex 3 of 50000000000 (the header (line 3) claims 50000000000 vertex records",
                 std::nullopt, h.size() + 36});
    t.push_back({"absurd vertex count, ascii", "hugea.ply",
                 ply_header("ascii", "element vertex 50000000000\n" + kXyzFloat) + "1 2 3\n", Expect::Input,
                 "claims 50000000000 vertex records", 9});
    t.push_back({"absurd count after lists", "hugel.ply",
                 ply_header("binary_little_endian", "element vertex 1\n" + kXyzFloat +
                                                        "element range_grid 1\nproperty list uchar int v\n"
                                                        "element junk 3000000000\nproperty double d\n") +
                     std::string(12 + 1, '\0'),
                 Expect::Input, "claims 3000000000 junk records", std::nullopt,
                 ply_header("binary_little_endian", "element vertex 1\n" + kXyzFloat +
                                                        "element range_grid 1\nproperty list uchar int v\n"
                                                        "element junk 3000000000\nproperty double d\n")
                         .size() +
                     13});
  }
  {
    Bytes b;
    b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}).put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1);
    b.put<std::int32_t>(2).put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(-1).put<std::int32_t>(2);
    const std::string h = ply_header("binary_little_endian", "element vertex 3\n" + kXyzFloat +
                                                                 "element face 2\nproperty list uchar int vertex_indices\n");
    t.push_back({"binary face index out of range", "face.ply", h + b.s, Expect::Input,
                 "face refers to vertex -1 but there are 3 vertices", std::nullopt, h.size() + 36 + 13, true});
  }
  // Ascii data (the header of kAsciiXyzHeader is 7 lines: data starts on line 8)
  t.push_back({"truncated ascii, short records", "ta.ply",
               ply_header("ascii", "element vertex 3\n" + kXyzFloat) + "1 2 3\n4 5 6\n", Expect::Input,
               "file ends too early", 10});
  t.push_back({"truncated ascii inside a record", "tb.ply", kAsciiXyzHeader + "1.5 2.5 3.5\n4.5 5.5\n", Expect::Input,
               "file ends inside vertex 1 of 2 (property z)", 10});
  t.push_back({"too many ascii records", "tm.ply", kAsciiXyzHeader + "1 2 3\n4 5 6\n\n\n7 8 9\n", Expect::Input,
               "unexpected data \"7\" after the last element", 12});
  t.push_back({"extra ascii value on the last line", "tv.ply", kAsciiXyzHeader + "1 2 3\n4 5 6 7\n", Expect::Input,
               "unexpected data \"7\" after the last element", 9});
  t.push_back({"non-numeric token", "nn.ply", kAsciiXyzHeader + "1 2 3\n4 5 six\n", Expect::Input,
               "expected a number for property \"z\" of vertex 1 of 2, found \"six\"", 9});
  t.push_back({"sign after plus", "pm.ply", kAsciiXyzHeader + "1 2 3\n4 +-5 6\n", Expect::Input,
               "found \"+-5\"", 9});
  t.push_back({"non-integer in an integer property", "ni.ply",
               ply_header("ascii", "element vertex 1\n" + kXyzFloat + "property uchar red\n") + "1 2 3 4.5\n",
               Expect::Input, "expected an integer for property \"red\"", 9});
  t.push_back({"ascii NaN", "nan.ply", kAsciiXyzHeader + "1 2 3\nnan 0 0\n", Expect::Input,
               "point 1 (0-based) has a non-finite coordinate", 9});
  t.push_back({"ascii Inf normal", "infn.ply",
               ply_header("ascii", "element vertex 2\n" + kXyzFloat +
                                       "property float nx\nproperty float ny\nproperty float nz\n") +
                   "1 2 3 0 0 1\n4 5 6 0 -inf 0\n",
               Expect::Input, "point 1 (0-based) has a non-finite coordinate or normal", 12});
  t.push_back({"ascii face index out of range", "face.ply",
               ply_header("ascii", "element vertex 3\n" + kXyzFloat + "element face 2\nproperty list uchar int vertex_indices\n") +
                   "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 3\n",
               Expect::Input, "face refers to vertex 3 but there are 3 vertices", 14, std::nullopt, true});
  for (const char* index : {"1e300", "-1e19"}) {
    t.push_back({std::string("ascii face index ") + index, "hugeface.ply",
                 ply_header("ascii", "element vertex 3\n" + kXyzFloat + "element face 1\nproperty list uchar int vertex_indices\n") +
                     "0 0 0\n1 0 0\n0 1 0\n3 0 1 " + index + "\n",
                 Expect::Input, std::string("face refers to vertex ") + index + " but there are 3 vertices", 13,
                 std::nullopt, true});
  }
  t.push_back({"ascii face index inf", "infface.ply",
               ply_header("ascii", "element vertex 3\n" + kXyzFloat + "element face 1\nproperty list uchar int vertex_indices\n") +
                   "0 0 0\n1 0 0\n0 1 0\n3 0 1 inf\n",
               Expect::Input, "expected an integer for property \"vertex_indices\" of face 0 of 1, found \"inf\"", 13,
               std::nullopt, true});
  t.push_back({"non-finite mesh vertex", "nanmesh.ply",
               ply_header("ascii", "element vertex 3\n" + kXyzFloat + "element face 1\nproperty list uchar int vertex_indices\n") +
                   "0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n",
               Expect::Input, "non-finite", 11, std::nullopt, true});
  // XYZ / PTS
  t.push_back({"xyz inconsistent columns", "ic.xyz", "# header\n1 2 3\n4 5 6\n7 8 9 0 0 1\n", Expect::Input,
               "expected 3 values as on line 2, found 6", 4});
  t.push_back({"xyz five columns", "five.xyz", "\n1 2 3 4 5\n", Expect::Input, "found 5", 2});
  t.push_back({"xyz non-numeric", "nn.xyz", "1 2 3\n4 5 6e\n", Expect::Input, "expected a number in column 3", 2});
  t.push_back({"xyz Inf", "inf.xyz", "1 2 3\n4 inf 6\n7 8 9\n", Expect::Input,
               "point 1 (0-based) has a non-finite", 2});
  t.push_back({"xyz NaN normal", "nan.xyz", "1 2 3 0 0 1\n4 5 6 nan 0 0\n", Expect::Input, "non-finite", 2});
  t.push_back({"pts count mismatch", "c.pts", "3\n1 2 3 0 1 2 3\n4 5 6 0 1 2 3\n", Expect::Input,
               "the count line says 3 points but the file has 2", 1});
  t.push_back({"pts bad count line", "b.pts", "many\n1 2 3\n", Expect::Input, "expected \"x y z\" or a point count", 1});
  t.push_back({"xyz as mesh", "m.xyz", "1 2 3\n", Expect::Input, "holds points, not a mesh", std::nullopt,
               std::nullopt, true});
  // OBJ
  t.push_back({"obj undefined vertex", "u.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", Expect::Input,
               "face refers to vertex 3 but only 2 are defined before it", 3, std::nullopt, true});
  t.push_back({"obj negative index too far back", "n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", Expect::Input,
               "face refers to vertex -4", 4, std::nullopt, true});
  t.push_back({"obj index zero", "z.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", Expect::Input,
               "expected a vertex index, found \"0\"", 4, std::nullopt, true});
  t.push_back({"obj short face", "s.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", Expect::Input, "at least 3 vertices", 3,
               std::nullopt, true});
  t.push_back({"obj bad vertex", "v.obj", "v 0 0 0\nv 1 0\n", Expect::Input, "found 2 values", 2});
  t.push_back({"obj NaN vertex", "nan.obj", "v 0 0 0\n# c\nv 1 nan 0\n", Expect::Input, "non-finite", 3});
  t.push_back({"obj Inf normal", "infn.obj", "v 0 0 0\nv 1 1 0\nvn 0 0 1\nvn inf 0 0\n", Expect::Input,
               "point 1 (0-based) has a non-finite", 4});
  return t;
}

class MalformedFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(MalformedFile, FailsWithTypeMessageAndLocation) {
  const BadFile& f = GetParam();
  TempDir dir;
  const auto file = dir / f.name;
  if (f.kind == Kind::File) write_file(file, f.bytes);
  if (f.kind == Kind::Directory) std::filesystem::create_directory(file);
  auto read = [&] {
    if (f.mesh) (void)read_triangle_mesh(file);
    else (void)read_point_cloud(file);
  };
  try {
    read();
    FAIL() << "no exception for " << f.label;
  } catch (const InputError& e) {
    ASSERT_EQ(f.type, Expect::Input) << "got InputError: " << e.what();
    EXPECT_NE(std::string(e.what()).find(f.message), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << "message must name the file: " << e.what();
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(e.where().line, f.line) << e.what();
    EXPECT_EQ(e.where().byte_offset, f.byte) << e.what();
    if (f.line) {
      EXPECT_NE(std::string(e.what()).find(file.string() + ":" + std::to_string(*f.line) + ": "), std::string::npos);
    }
    if (f.byte) {
      EXPECT_NE(std::string(e.what()).find(": byte " + std::to_string(*f.byte) + ": "), std::string::npos);
    }
  } catch (const IoError& e) {
    ASSERT_EQ(f.type, Expect::Io) << "got IoError: " << e.what();
    EXPECT_NE(std::string(e.what()).find(f.message), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Table, MalformedFile, ::testing::ValuesIn(bad_files()),
                         [](const ::testing::TestParamInfo<BadFile>& info) {
                           std::string name = std::to_string(info.index) + "_" + info.param.label;
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

TEST(MalformedFileExtra, AbsurdCountFailsFastWithoutAllocating) {
  TempDir dir;
  const std::string h = ply_header("binary_little_endian", "element vertex 50000000000\n" + kXyzFloat);
  write_file(dir / "huge.ply", h + std::string(36, '\0'));
  const auto start = std::chrono::steady_clock::now();
  try {
    (void)read_point_cloud(dir / "huge.ply");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("50000000000"), std::string::npos) << e.what();
  }
  // 50e9 points would take 1.2 TB: reaching the check at all proves nothing was allocated
  // (std::bad_alloc otherwise); it must also be immediate.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST(MalformedFileExtra, EmptyOutputNameAndUnwritableTarget) {
  const PointCloud c = awkward_cloud(3, false, false);
  EXPECT_THROW(write_ply("", c), IoError);
}

/// A file that is one endless line (the "5 GB line") is refused once the line passes 1 MiB,
/// with the line's number, whatever the format; the bytes after the limit are never looked at
/// (here: 64 MiB of them, read in far less time than a scan would take under the sanitizers).
TEST(MalformedFileExtra, EndlessLineIsRefusedAtTheLimit) {
  constexpr std::size_t kLimit = std::size_t{1} << 20;
  const std::string endless(64 * kLimit, '7');
  const std::string spaces(2 * kLimit, ' ');
  struct Case {
    std::string name, bytes;
    std::uint64_t line;
  };
  const std::vector<Case> cases = {
      {"digits.xyz", "1 2 3\n" + endless, 2},
      {"comment.xyz", "1 2 3\n#" + endless + "\n4 5 6\n", 2},
      {"spaces.xyz", "1 2 3\n" + spaces + "4 5 6\n", 2},
      {"vertex.obj", "v 0 0 0\nv 1 " + endless, 2},
      {"header.ply", "ply\nformat ascii 1.0\ncomment " + endless + "\nend_header\n", 3},
      {"token.ply", kAsciiXyzHeader + "1 2 3\n4 5 " + endless, 9},
      {"blank.ply", kAsciiXyzHeader + "1 2 3\n4 5" + spaces + "6\n", 9},
  };
  TempDir dir;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    write_file(dir / c.name, c.bytes);
    const auto start = std::chrono::steady_clock::now();
    try {
      (void)read_point_cloud(dir / c.name);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(e.message().find("line is longer than 1048576 bytes"), std::string::npos) << e.what();
      EXPECT_EQ(e.where().line, c.line) << e.what();
    }
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  }
  // A line just under the limit is fine.
  write_file(dir / "long.xyz", "1 2 3 # " + std::string(kLimit - 9, 'x') + "\n4 5 6\n");
  EXPECT_EQ(read_point_cloud(dir / "long.xyz").size(), 2);
}

/// The files with non-finite values of the table, read with drop_non_finite: they load without
/// the bad points and the warning reports the count.
TEST(NonFinite, DroppedOnRequestWithAWarning) {
  struct Case {
    std::string name, bytes;
    Eigen::Index kept;
    std::string count;  // "dropped K of N"
  };
  const std::vector<Case> cases = {
      {"nan.ply", kAsciiXyzHeader + "1 2 3\nnan 0 0\n", 1, "dropped 1 of 2"},
      {"inf.ply", ply_header("ascii", "element vertex 3\n" + kXyzFloat) + "inf 2 3\n4 5 6\n7 -inf nan\n", 1,
       "dropped 2 of 3"},
      {"nanb.ply", binary_cloud_with_nan(), 3, "dropped 1 of 4"},
      {"inf.xyz", "1 2 3\n4 inf 6\n7 8 9\n", 2, "dropped 1 of 3"},
      {"nan.xyz", "1 2 3 0 0 1\n4 5 6 nan 0 0\n", 1, "dropped 1 of 2"},
      {"nan.obj", "v 0 0 0\n# c\nv 1 nan 0\n", 1, "dropped 1 of 2"},
  };
  TempDir dir;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    write_file(dir / c.name, c.bytes);
    EXPECT_THROW((void)read_point_cloud(dir / c.name), InputError);
    std::vector<std::string> warnings;
    ReadOptions o;
    o.drop_non_finite = true;
    o.warn = [&](const std::string& w) { warnings.push_back(w); };
    const PointCloud r = read_point_cloud(dir / c.name, o);
    EXPECT_EQ(r.size(), c.kept);
    EXPECT_TRUE(r.positions.allFinite());
    if (r.has_normals()) {
      EXPECT_EQ(r.normals.rows(), c.kept);
      EXPECT_TRUE(r.normals.allFinite());
    }
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(c.count), std::string::npos) << warnings[0];
    // Without a callback the warning is silently ignored.
    ReadOptions quiet;
    quiet.drop_non_finite = true;
    EXPECT_EQ(read_point_cloud(dir / c.name, quiet).size(), c.kept);
  }
  // Kept points keep their attributes in order.
  write_file(dir / "attr.ply", ply_header("ascii", "element vertex 3\n" + kXyzFloat + "property uchar red\nproperty "
                                                                                      "uchar green\nproperty uchar blue\n") +
                                   "1 1 1 10 11 12\nnan 2 2 20 21 22\n3 3 3 30 31 32\n");
  ReadOptions o;
  o.drop_non_finite = true;
  const PointCloud r = read_point_cloud(dir / "attr.ply", o);
  EXPECT_TRUE(mat_eq(r.positions, rows({{1, 1, 1}, {3, 3, 3}})));
  ASSERT_TRUE(r.has_colors());
  EXPECT_EQ(r.colors(1, 0), 30);
  EXPECT_EQ(r.colors(1, 2), 32);
  // Every point dropped: no points left.
  write_file(dir / "all.xyz", "nan 0 0\n");
  EXPECT_THROW((void)read_point_cloud(dir / "all.xyz", o), InputError);
}

/// Random corruptions of valid files (byte changes, truncations, insertions): every read either
/// succeeds or throws InputError; never a crash, a hang or another exception type.
TEST(MalformedFileExtra, RandomCorruptionsOnlyEverThrowInputError) {
  TempDir dir;
  Bytes bin;
  bin.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  bin.put<std::uint8_t>(4).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2).put<std::int32_t>(3);
  bin.put<std::uint8_t>(3).put<std::int32_t>(3).put<std::int32_t>(2).put<std::int32_t>(1);
  const std::vector<std::pair<std::string, std::string>> seeds = {
      {"a.ply", ply_header("ascii", "element vertex 4\n" + kXyzFloat +
                                        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                        "element face 2\nproperty list uchar int vertex_indices\n") +
                    "0 0 0 1 2 3\n1 0 0 4 5 6\n1 1 0 7 8 9\n0 1 0 10 11 12\n4 0 1 2 3\n3 3 2 1\n"},
      {"b.ply", ply_header("binary_little_endian",
                           "element vertex 4\n" + kXyzFloat + "element face 2\nproperty list uchar int vertex_indices\n") +
                    bin.s},
      {"c.xyz", "3\n1 2 3 0 0 1\n4 5 6 0 1 0\n7 8 9 1 0 0\n"},
      {"d.obj", "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1//1 2//2 3//3\nf -1 -2 -3\n"},
  };
  const std::string alphabet = "0123456789 -+.\n\r\t#,/eEnaifvxyz\xff\x80";
  std::mt19937_64 rng(2024);
  int ok = 0, rejected = 0;
  for (const auto& [name, original] : seeds) {
    for (int trial = 0; trial < 1000; ++trial) {
      std::string bytes = original;
      const int edits = 1 + static_cast<int>(rng() % 3);
      for (int e = 0; e < edits && !bytes.empty(); ++e) {
        const std::size_t at = rng() % bytes.size();
        switch (rng() % 5) {
          case 0: bytes[at] = static_cast<char>(rng() % 256); break;
          case 1: bytes[at] = alphabet[rng() % alphabet.size()]; break;
          case 2: bytes.resize(at); break;
          case 3: bytes.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
          default: bytes.erase(at, 1 + rng() % 4); break;
        }
      }
      // A new file each time: rewriting one in place (O_TRUNC) makes ext4 flush it on close.
      std::filesystem::remove(dir / name);
      write_file(dir / name, bytes);
      for (bool mesh : {false, true}) {
        if (mesh && name == "c.xyz") continue;
        try {
          if (mesh) {
            const TriangleMesh m = read_triangle_mesh(dir / name);
            if (m.triangles.size() != 0) {
              EXPECT_GE(m.triangles.minCoeff(), 0);
              EXPECT_LT(m.triangles.maxCoeff(), m.vertices.rows());
            }
          } else {
            (void)read_point_cloud(dir / name);
          }
          ++ok;
        } catch (const InputError&) {
          ++rejected;
        } catch (const std::exception& e) {
          ADD_FAILURE() << name << " trial " << trial << ": unexpected exception " << e.what();
        }
      }
    }
  }
  EXPECT_GT(ok, 100);
  EXPECT_GT(rejected, 100);
}

// ---------------------------------------------------------------------------------------------
// Real data (shared scans; skipped when absent)

void expect_bbox(const Points& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const BoundingBox b = bounding_box(p);
  // The README gives 4 decimals.
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(b.min[k], lo[k], 6e-5) << "min " << k;
    EXPECT_NEAR(b.max[k], hi[k], 6e-5) << "max " << k;
  }
}

TEST(RealData, StanfordRangeScanSkipsRangeGrid) {
  const auto file = test::shared_data("bunny/scans/bun000.ply");
  if (!file) GTEST_SKIP() << "shared data bunny/scans/bun000.ply is absent";
  const PointCloud c = read_point_cloud(*file);
  EXPECT_EQ(c.size(), 40256);
  EXPECT_FALSE(c.has_normals());
  expect_bbox(c.positions, {-0.0948, 0.0357, -0.0587}, {0.0610, 0.1879, 0.0587});
}

TEST(RealData, AlignedScansWithNormals) {
  const auto file = test::shared_data("bunny/bunny_scans_aligned.ply");
  if (!file) GTEST_SKIP() << "shared data bunny/bunny_scans_aligned.ply is absent";
  const PointCloud c = read_point_cloud(*file);
  EXPECT_EQ(c.size(), 361035);
  ASSERT_TRUE(c.has_normals());
  EXPECT_FALSE(c.has_colors());
  expect_bbox(c.positions, {-0.0951, 0.0330, -0.0628}, {0.0614, 0.1879, 0.0591});
  const Eigen::ArrayXd len = c.normals.rowwise().norm().array();
  EXPECT_LT((len - 1.0).abs().maxCoeff(), 1e-4);
}

TEST(RealData, TristripsMeshReadsAsPointCloud) {
  const auto file = test::shared_data("meshes/igea_original_tristrips.ply");
  if (!file) GTEST_SKIP() << "shared data meshes/igea_original_tristrips.ply is absent";
  const PointCloud c = read_point_cloud(*file);
  EXPECT_EQ(c.size(), 134345);
  expect_bbox(c.positions, {-0.0346, -0.0497, -0.0495}, {0.0346, 0.0497, 0.0495});
}

TEST(RealData, ZipperedReconstructionAsMesh) {
  const auto file = test::shared_data("bunny/reconstruction/bun_zipper.ply");
  if (!file) GTEST_SKIP() << "shared data bunny/reconstruction/bun_zipper.ply is absent";
  const TriangleMesh m = read_triangle_mesh(*file);
  EXPECT_EQ(m.vertices.rows(), 35947);
  EXPECT_EQ(m.triangles.rows(), 69451);
  EXPECT_GE(m.triangles.minCoeff(), 0);
  EXPECT_LT(m.triangles.maxCoeff(), 35947);
  expect_bbox(m.vertices, {-0.0947, 0.0330, -0.0619}, {0.0610, 0.1873, 0.0588});
  // 1,113 vertices are referenced by no face.
  std::vector<char> used(35947, 0);
  for (Eigen::Index i = 0; i < m.triangles.size(); ++i) used[static_cast<std::size_t>(m.triangles.data()[i])] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 1113);
}

TEST(RealData, ConvertedMeshesMatchTheReadme) {
  struct M {
    const char* file;
    Eigen::Index v, f;
  };
  for (const M& m : {M{"meshes/igea.ply", 134345, 268686}, M{"meshes/fandisk.ply", 6475, 12946},
                     M{"bunny/bunny_npm.ply", 1839, 3674}}) {
    SCOPED_TRACE(m.file);
    const auto file = test::shared_data(m.file);
    if (!file) GTEST_SKIP() << "shared data " << m.file << " is absent";
    const TriangleMesh r = read_triangle_mesh(*file);
    EXPECT_EQ(r.vertices.rows(), m.v);
    EXPECT_EQ(r.triangles.rows(), m.f);
  }
}

TEST(RealData, DefaultBunny) {
  const auto file = test::default_bunny();
  if (!file) GTEST_SKIP() << "data/bunny.ply is absent (run scripts/setup)";
  const PointCloud c = read_point_cloud(*file);
  EXPECT_EQ(c.size(), 1839);
  EXPECT_TRUE(c.positions.allFinite());
}

TEST(RealData, ReadWriteReadIsStableOnAScan) {
  const auto file = test::shared_data("bunny/scans/bun000.ply");
  if (!file) GTEST_SKIP() << "shared data bunny/scans/bun000.ply is absent";
  const PointCloud c = read_point_cloud(*file);
  TempDir dir;
  PlyWriteOptions o;
  o.double_precision = true;  // the ascii scan's decimals are not floats
  write_ply(dir / "b.ply", c, o);
  EXPECT_TRUE(same_bits(read_point_cloud(dir / "b.ply").positions, c.positions));
  write_xyz(dir / "b.xyz", c);
  EXPECT_TRUE(same_bits(read_point_cloud(dir / "b.xyz").positions, c.positions));
}

}  // namespace
}  // namespace clustersurf

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
  using namespace clustersurf;
  const PointCloud c = parse_point_cloud(tetrahedron_ply(), FileFormat::Ply);
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
  ReadOptions off;
  off.normals_from_faces = false;
  EXPECT_EQ(parse_point_cloud(tetrahedron_ply(), FileFormat::Ply, "<memory>", off).normals.rows(), 0);
  EXPECT_EQ(parse_point_cloud(tetrahedron_ply(1), FileFormat::Ply).normals.rows(), 0);
  const PointCloud broken = parse_point_cloud(tetrahedron_ply(0, "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 9\n"), FileFormat::Ply);
  EXPECT_EQ(broken.size(), 4);
  EXPECT_EQ(broken.normals.rows(), 0);
}
