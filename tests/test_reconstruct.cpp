// The pipeline function: reconstruct() is build → orient → mesh → trim → color, the same bytes
// as the stages called one by one; mesh_tree() of a loaded tree gives the same mesh; the checks
// (surface extent, points that are not the tree's input) happen here, once.

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/mesh/mesh_coarsening.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <gtest/gtest.h>

#include <iostream>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

bool same_mesh(const TriangleMesh& a, const TriangleMesh& b) {
  return a.vertices == b.vertices && a.triangles == b.triangles && a.normals == b.normals && a.colors == b.colors;
}

}  // namespace

TEST(Reconstruct, IsTheStagesInOrder) {
  const PointCloud cloud = test::sample_torus(8000);
  ReconstructOptions options;
  options.meshing.coloring = MeshColoring::ByDistance;
  const Reconstruction r = reconstruct(cloud, options);
  ASSERT_TRUE(r.mesh.has_value());

  ClusterTree tree = build_cluster_tree(cloud, options.build);
  orient_tree(tree, cloud);
  EXPECT_EQ(serialize_tree(r.tree), serialize_tree(tree));
  MeshOptions grid;
  grid.voxel_size = cell_size_for_points(cloud);
  const ImplicitSurface surface(tree);
  const Points clustered = clustered_points(tree, cloud.positions);
  TriangleMesh mesh = trim_to_points(extract_mesh(surface, grid), clustered);
  mesh = coarsen_mesh(mesh, tree.bbox.min, *grid.voxel_size, coarsening_scale(tree));
  refit_vertices(mesh, KdTree(clustered), surface);
  mesh.colors = colors_by_distance(mesh, cloud.positions, 0.005 * tree.bbox.diagonal());
  EXPECT_TRUE(same_mesh(r.mesh->mesh, mesh));
  EXPECT_GT(r.mesh->mesh.triangles.rows(), 1000);
}

TEST(Reconstruct, PointsRepeatingTheirPositionsGiveTheDistinctPointsSurface) {
  // Every point eight times, as a triangle soup's corners or a cloud saved twice over repeat
  // them: each position counts once, in the tree, the mesh grid, the trim and the refit.
  const PointCloud cloud = test::sample_sphere(4000);
  std::vector<Eigen::Index> rows;
  for (int copy = 0; copy < 8; ++copy)
    for (Eigen::Index i = 0; i < cloud.size(); ++i) rows.push_back(i);
  PointCloud repeated;
  repeated.positions = cloud.positions(rows, Eigen::all);
  repeated.normals = cloud.normals(rows, Eigen::all);
  const Reconstruction distinct = reconstruct(cloud), r = reconstruct(repeated);
  ASSERT_TRUE(r.mesh.has_value());
  EXPECT_EQ(r.tree.outliers(), 7u * 4000u);
  EXPECT_EQ(r.tree.point_spacing, distinct.tree.point_spacing);
  EXPECT_EQ(r.tree.nodes.size(), distinct.tree.nodes.size());
  EXPECT_TRUE(same_mesh(r.mesh->mesh, distinct.mesh->mesh));
}

TEST(Reconstruct, MeshOfTheSavedTreeIsTheSameMesh) {
  const PointCloud cloud = test::sample_sphere(4000);
  const Reconstruction r = reconstruct(cloud);
  const ClusterTree loaded = deserialize_tree(serialize_tree(r.tree));
  const CloudIndex index(cloud);
  EXPECT_TRUE(same_mesh(mesh_tree(loaded, {}, &index).mesh, r.mesh->mesh));
  // Without the points: the same grid (the tree stores the spacing), untrimmed.
  const SurfaceMesh untrimmed = mesh_tree(loaded);
  EXPECT_EQ(untrimmed.grid.voxel_size, r.mesh->grid.voxel_size);
  EXPECT_GE(untrimmed.mesh.triangles.rows(), r.mesh->mesh.triangles.rows());
}

TEST(Reconstruct, RefusesWhatIsNotASurface) {
  PointCloud same;
  same.positions = Points::Constant(50, 3, 1.5);
  EXPECT_THROW(reconstruct(same), InputError);
  PointCloud line;
  line.positions.resize(50, 3);
  for (int i = 0; i < 50; ++i) line.positions.row(i) << i, 2 * i, 3 * i;
  try {
    reconstruct(line);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "all 50 points lie on one line: there is no surface to reconstruct");
  }
}

TEST(Reconstruct, PointsOfAnotherCloudAreAnOptionError) {
  const Reconstruction r = reconstruct(test::sample_sphere(2000));
  const PointCloud other = test::sample_sphere(1999);
  const CloudIndex index(other);
  EXPECT_THROW(mesh_tree(r.tree, {}, &index), OptionError);
  SurfaceMeshOptions colored;
  colored.coloring = MeshColoring::ByDistance;
  EXPECT_THROW(mesh_tree(r.tree, colored), OptionError);  // distance colors need the points
}

// The README's main job: the default input (a mesh of 1,839 vertices) read as it is by default
// (samples of its faces) becomes one surface close to the mesh, ears included. Read as its
// vertices, the same options gave two pieces, Chamfer 3.3e-3 of the diagonal and normal
// consistency 0.926: the ears, thinner than the vertices' spacing, fused into a spiral.
TEST(Reconstruct, TheDefaultInputBecomesOneSurfaceCloseToItsMesh) {
  const auto file = test::default_bunny();
  if (!file) GTEST_SKIP() << "data/bunny.ply is absent: run scripts/setup";
  const Reconstruction r = reconstruct(read_point_cloud(*file));
  ASSERT_TRUE(r.mesh.has_value());
  ComparisonOptions options;
  options.samples = 50'000;
  const SurfaceComparison c = compare_surfaces(r.mesh->mesh, read_triangle_mesh(*file), options);
  std::cout << "default bunny: Chamfer " << c.chamfer << " of the diagonal, Hausdorff " << c.hausdorff
            << ", normal consistency " << c.normal_consistency << ", " << c.reconstruction_topology.components
            << " component(s)\n";
  EXPECT_EQ(c.reconstruction_topology.components, 1u);
  EXPECT_LT(c.chamfer, 3e-4);  // fractions of the diagonal
  EXPECT_LT(c.hausdorff, 0.02);
  EXPECT_GT(c.normal_consistency, 0.985);
}
