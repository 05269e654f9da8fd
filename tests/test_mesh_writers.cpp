// The mesh writers beyond PLY and OBJ: binary STL read back equal, GLB parsed back (JSON chunk,
// accessors, buffer, the origin as the node's translation), OFF; and every writer puts points
// back at their origin.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

namespace clustersurf::test {
namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <class T>
T at(const std::string& b, std::size_t offset) {
  T v;
  std::memcpy(&v, b.data() + offset, sizeof v);
  return v;
}

/// A tetrahedron with normals and colors, away from zero.
TriangleMesh tetrahedron(Eigen::Vector3d origin = Eigen::Vector3d::Zero()) {
  TriangleMesh m;
  m.vertices = rows({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  m.triangles.resize(4, 3);
  m.triangles << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  m.normals = vertex_normals(m);
  m.colors.resize(4, 3);
  m.colors << 255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30;
  m.origin = origin;
  return m;
}

TEST(MeshWriters, BinaryStlReadsBackEqual) {
  TempDir dir;
  const TriangleMesh m = tetrahedron();
  write_triangle_mesh(dir / "t.stl", m);
  const std::string b = slurp(dir / "t.stl");
  ASSERT_EQ(b.size(), 84u + 4u * 50u);
  ASSERT_EQ(at<std::uint32_t>(b, 80), 4u);
  for (Eigen::Index f = 0; f < 4; ++f) {
    const std::size_t r = 84 + 50 * static_cast<std::size_t>(f);
    const Eigen::Vector3d a = m.vertices.row(m.triangles(f, 0)), b1 = m.vertices.row(m.triangles(f, 1)),
                          c = m.vertices.row(m.triangles(f, 2));
    const Eigen::Vector3f n = (b1 - a).cross(c - a).normalized().cast<float>();
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(at<float>(b, r + 4 * static_cast<std::size_t>(k)), n(k));
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(at<float>(b, r + 12 + 12 * static_cast<std::size_t>(v) + 4 * static_cast<std::size_t>(k)),
                  static_cast<float>(m.vertices(m.triangles(f, v), k)));
  }
}

TEST(MeshWriters, GlbHoldsPositionsNormalsColorsIndicesAndTheOrigin) {
  TempDir dir;
  const TriangleMesh m = tetrahedron({636590.5, 849216.25, 0});
  write_triangle_mesh(dir / "t.glb", m);
  const std::string b = slurp(dir / "t.glb");
  ASSERT_GE(b.size(), 28u);
  EXPECT_EQ(b.substr(0, 4), "glTF");
  EXPECT_EQ(at<std::uint32_t>(b, 4), 2u);
  EXPECT_EQ(at<std::uint32_t>(b, 8), b.size());
  const auto json_length = at<std::uint32_t>(b, 12);
  EXPECT_EQ(b.substr(16, 4), "JSON");
  EXPECT_EQ(json_length % 4, 0u);
  const nlohmann::json j = nlohmann::json::parse(b.substr(20, json_length));
  const std::size_t bin = 20 + json_length;
  EXPECT_EQ(b.substr(bin + 4, 4), std::string("BIN\0", 4));
  const std::size_t data = bin + 8;
  EXPECT_EQ(j["asset"]["version"], "2.0");
  EXPECT_EQ(j["nodes"][0]["translation"], (std::vector<double>{636590.5, 849216.25, 0}));
  const auto& primitive = j["meshes"][0]["primitives"][0];
  const auto accessor = [&](const char* name) { return j["accessors"][primitive["attributes"][name].get<int>()]; };
  const auto view_offset = [&](const nlohmann::json& a) {
    return data + j["bufferViews"][a["bufferView"].get<int>()]["byteOffset"].get<std::size_t>();
  };
  const auto positions = accessor("POSITION");
  EXPECT_EQ(positions["count"], 4);
  EXPECT_EQ(positions["max"], (std::vector<float>{1, 1, 1}));
  for (Eigen::Index v = 0; v < 4; ++v)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(
          at<float>(b, view_offset(positions) + 12 * static_cast<std::size_t>(v) + 4 * static_cast<std::size_t>(k)),
          static_cast<float>(m.vertices(v, k)));
  const auto colors = accessor("COLOR_0");
  EXPECT_EQ(colors["type"], "VEC4");
  EXPECT_EQ(static_cast<unsigned char>(b[view_offset(colors) + 12 + 1]), 20);
  const auto normals = accessor("NORMAL");
  EXPECT_FLOAT_EQ(at<float>(b, view_offset(normals) + 8), static_cast<float>(m.normals(0, 2)));
  const auto indices = j["accessors"][primitive["indices"].get<int>()];
  EXPECT_EQ(indices["count"], 12);
  for (Eigen::Index f = 0; f < 4; ++f)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(at<std::uint32_t>(
                    b, view_offset(indices) + 12 * static_cast<std::size_t>(f) + 4 * static_cast<std::size_t>(k)),
                static_cast<std::uint32_t>(m.triangles(f, k)));
}

TEST(MeshWriters, OffAndEveryTextWriterPutPointsBackAtTheirOrigin) {
  TempDir dir;
  const Eigen::Vector3d origin(636590.49, 849216.55, 0);
  const TriangleMesh m = tetrahedron(origin);
  write_triangle_mesh(dir / "t.off", m);
  std::istringstream off(slurp(dir / "t.off"));
  std::string magic;
  int nv = 0, nf = 0, ne = 0;
  off >> magic >> nv >> nf >> ne;
  EXPECT_EQ(magic, "COFF");
  ASSERT_EQ(nv, 4);
  ASSERT_EQ(nf, 4);
  for (Eigen::Index v = 0; v < 4; ++v) {
    double x, y, z;
    int r, g, bl, a;
    off >> x >> y >> z >> r >> g >> bl >> a;
    EXPECT_EQ(Eigen::Vector3d(x, y, z), Eigen::Vector3d(m.vertices.row(v).transpose() + origin));
    EXPECT_EQ(r, m.colors(v, 0));
  }
  // PLY (in double whatever the options say: float would lose the georeference), OBJ: read
  // back next to zero, at the same place bit for bit.
  for (const char* name : {"t.ply", "t.obj"}) {
    write_triangle_mesh(dir / name, m);
    const TriangleMesh back = read_triangle_mesh(dir / name);
    EXPECT_GT(back.origin.norm(), 1e5) << name;
    EXPECT_LT(back.vertices.cwiseAbs().maxCoeff(), 10) << name;
    EXPECT_TRUE(same_bits(Points(back.vertices.rowwise() + back.origin.transpose()),
                          Points(m.vertices.rowwise() + origin.transpose())))
        << name;
  }
  // A cloud read back is shifted the same way, bit for bit.
  PointCloud c;
  c.positions = m.vertices;
  c.origin = origin;
  write_point_cloud(dir / "c.ply", c);
  const PointCloud back = read_point_cloud(dir / "c.ply");
  EXPECT_TRUE(same_bits(Points(back.positions.rowwise() + back.origin.transpose()),
                        Points(c.positions.rowwise() + origin.transpose())));
  EXPECT_THROW(write_point_cloud(dir / "c.stl", c), OptionError);
  write_triangle_mesh(dir / "t.stl", m);
  EXPECT_THROW(read_point_cloud(dir / "t.stl"), InputError);
}

}  // namespace
}  // namespace clustersurf::test
