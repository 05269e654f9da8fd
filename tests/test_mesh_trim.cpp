// Trimming a mesh to its input points: the part beyond the data goes, the rest stays as it was.

#include <clustersurf/errors.hpp>
#include <clustersurf/implicit_surface.hpp>
#include <clustersurf/mesh_extraction.hpp>
#include <clustersurf/mesh_trim.hpp>
#include <clustersurf/orientation.hpp>

#include <gtest/gtest.h>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

TriangleMesh sphere_mesh() {
  const PointCloud c = test::sample_sphere(20000);
  ClusterTree t = build_cluster_tree(c, {});
  orient_tree(t, c);
  MeshOptions o;
  o.resolution = 64;
  return extract_mesh(ImplicitSurface(t), o);
}

/// The rows of the sphere samples with z > 0: data that stops at the equator.
Points upper_half() {
  const PointCloud c = test::sample_sphere(20000);
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < c.size(); ++i)
    if (c.positions(i, 2) > 0) rows.push_back(i);
  return c.positions(rows, Eigen::all);
}

}  // namespace

TEST(MeshTrim, DropsWhatLiesBeyondTheDataAndKeepsTheRest) {
  const TriangleMesh full = sphere_mesh();
  const Points data = upper_half();
  TrimReport report;
  const TriangleMesh trimmed = trim_to_points(full, data, {}, &report);
  EXPECT_GT(report.removed_triangles, static_cast<std::size_t>(full.triangles.rows()) / 3);
  EXPECT_EQ(static_cast<std::size_t>(full.triangles.rows() - trimmed.triangles.rows()), report.removed_triangles);
  EXPECT_EQ(static_cast<std::size_t>(full.vertices.rows() - trimmed.vertices.rows()), report.removed_vertices);
  // The sample spacing is about 0.025: nothing stays more than a few spacings below the data.
  EXPECT_GT(trimmed.vertices.col(2).minCoeff(), -0.1);
  // Every triangle well inside the data is kept.
  std::size_t inside_full = 0, inside_trimmed = 0;
  auto count_inside = [](const TriangleMesh& m) {
    std::size_t n = 0;
    for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
      bool inside = true;
      for (int k = 0; k < 3; ++k) inside = inside && m.vertices(m.triangles(t, k), 2) > 0.1;
      n += inside;
    }
    return n;
  };
  inside_full = count_inside(full);
  inside_trimmed = count_inside(trimmed);
  EXPECT_EQ(inside_trimmed, inside_full);
  EXPECT_EQ(trimmed.normals.rows(), trimmed.vertices.rows());
}

TEST(MeshTrim, DataEverywhereOrFactorZeroKeepsTheMeshAsItIs) {
  const TriangleMesh full = sphere_mesh();
  const PointCloud c = test::sample_sphere(20000);
  TrimReport report;
  const TriangleMesh same = trim_to_points(full, c.positions, {}, &report);
  EXPECT_EQ(report.removed_triangles, 0u);
  EXPECT_EQ(same.vertices, full.vertices);
  EXPECT_EQ(same.triangles, full.triangles);
  TrimOptions off;
  off.spread_factor = 0;
  EXPECT_EQ(trim_to_points(full, upper_half(), off).triangles, full.triangles);
  TrimOptions bad;
  bad.spread_factor = -1;
  EXPECT_THROW(trim_to_points(full, c.positions, bad), OptionError);
}
