// The readers on the real scans of the shared data folder (skipped, saying why, when absent):
// the Stanford range scans and their range grids, the aligned scans with normals, the meshes.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <clustersurf/spatial/cloud_stats.hpp>

#include <gtest/gtest.h>

namespace clustersurf {
namespace {

using namespace clustersurf::test;

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
  // A mesh of 1,839 vertices: read as 100,000 samples of its faces, or as its vertices.
  const PointCloud c = read_point_cloud(*file);
  EXPECT_EQ(c.size(), ReadOptions{}.mesh_samples);
  EXPECT_TRUE(c.positions.allFinite());
  ReadOptions vertices;
  vertices.mesh_samples = 0;
  EXPECT_EQ(read_point_cloud(*file, vertices).size(), 1839);
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
