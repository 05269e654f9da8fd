// The OBJ reader on a hand-written file: vertex colors, normals and negative face indices.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <gtest/gtest.h>

namespace clustersurf {
namespace {

using namespace clustersurf::test;

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

}  // namespace
}  // namespace clustersurf
