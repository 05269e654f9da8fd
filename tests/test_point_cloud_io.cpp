// Point-cloud and mesh I/O: round trips through every writer (bit-exact where promised), the
// writers' atomicity, and the choice of reader by magic number or extension.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <filesystem>

#include <gtest/gtest.h>

namespace clustersurf {
namespace {

using namespace clustersurf::test;

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

TEST(Readers, PlyIsRecognisedByMagicWhateverTheExtension) {
  TempDir dir;
  const PointCloud c = read_text(dir, "cloud.xyz", ply_header("ascii", "element vertex 1\n" + kXyzFloat) + "1 2 3\n");
  EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}})));
  EXPECT_EQ(format_from_extension("A.PLY"), FileFormat::Ply);
  EXPECT_EQ(format_from_extension("a.pts"), FileFormat::Xyz);
  EXPECT_EQ(format_from_extension("a.Obj"), FileFormat::Obj);
  EXPECT_THROW(format_from_extension("a"), InputError);
}

}  // namespace
}  // namespace clustersurf
