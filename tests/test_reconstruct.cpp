// The pipeline function: reconstruct() is build → orient → mesh → trim → color, the same bytes
// as the stages called one by one; mesh_tree() of a loaded tree gives the same mesh; the checks
// (surface extent, points that are not the tree's input) happen here, once.

#include <clustersurf/errors.hpp>
#include <clustersurf/mesh_colors.hpp>
#include <clustersurf/reconstruct.hpp>
#include <clustersurf/tree_file.hpp>

#include <gtest/gtest.h>

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
  TriangleMesh mesh = trim_to_points(extract_mesh(surface, grid), clustered_points(tree, cloud.positions));
  mesh.colors = colors_by_distance(mesh, cloud.positions, 0.005 * tree.bbox.diagonal());
  EXPECT_TRUE(same_mesh(r.mesh->mesh, mesh));
  EXPECT_GT(r.mesh->mesh.triangles.rows(), 1000);
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
