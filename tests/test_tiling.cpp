// Regions and tiles: a cloud split into regions built apart and meshed as tiles of one lattice
// gives the in-core surface, without seams along the tile borders.

#include "tiling/tiles.hpp"
#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/mesh/vertex_refit.hpp>

#include <gtest/gtest.h>

#include <iostream>

#include <array>
#include <random>
#include <set>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

RegionOptions regions_of(std::uint64_t points) {
  RegionOptions o;
  o.max_points = points;
  return o;
}

}  // namespace

TEST(RegionPlan, BalancesRegionsByPointCount) {
  const PointCloud cloud = test::sample_torus(40000);
  const RegionPlan plan = plan_regions(cloud.positions, 40000, bounding_box(cloud.positions), 0.0002, regions_of(5000));
  ASSERT_GE(plan.regions(), 8u);
  std::vector<std::size_t> own(plan.regions(), 0);
  for (Eigen::Index i = 0; i < cloud.size(); ++i)
    ++own[static_cast<std::size_t>(plan.region_of(cloud.positions.row(i).transpose()))];
  for (const std::size_t n : own) {
    EXPECT_LE(n, 5000u);
    EXPECT_GE(n, 2000u);  // median cuts: no region far below half the limit
  }
  // The halo: exactly the other regions whose cell is within the halo width.
  std::vector<std::int32_t> near;
  for (Eigen::Index i = 0; i < cloud.size(); i += 97) {
    const Eigen::Vector3d x = cloud.positions.row(i).transpose();
    plan.halo_regions(x, near);
    for (std::int32_t r = 0; r < static_cast<std::int32_t>(plan.regions()); ++r) {
      const BoundingBox& box = plan.region_box(r);
      const double d = ((box.min - x).cwiseMax(0.0) + (x - box.max).cwiseMax(0.0)).norm();
      const bool listed = std::find(near.begin(), near.end(), r) != near.end();
      EXPECT_EQ(listed, r != plan.region_of(x) && d <= plan.halo) << "point " << i << " region " << r;
    }
  }
}

TEST(RegionPlan, RegionsFitWithTheirHalo) {
  const PointCloud cloud = test::sample_torus(40000);
  const RegionPlan plan = plan_regions(cloud.positions, 40000, bounding_box(cloud.positions), 0.001, regions_of(8000));
  ASSERT_GT(plan.halo, 0.05);
  std::vector<std::size_t> held(plan.regions(), 0);
  std::vector<std::int32_t> near;
  for (Eigen::Index i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d x = cloud.positions.row(i).transpose();
    ++held[static_cast<std::size_t>(plan.region_of(x))];
    plan.halo_regions(x, near);
    for (const std::int32_t r : near) ++held[static_cast<std::size_t>(r)];
  }
  for (const std::size_t n : held) EXPECT_LE(n, 8000u);
}

TEST(Tiling, OneRegionIsTheInCoreTree) {
  const PointCloud cloud = test::sample_torus(12000);
  ReconstructOptions options;
  options.mesh = false;
  const Reconstruction in_core = reconstruct(cloud, options);
  const Reconstruction tiled = reconstruct_tiled(cloud, regions_of(1'000'000), options);
  EXPECT_EQ(serialize_tree(tiled.tree), serialize_tree(in_core.tree));
}

TEST(Tiling, TilesMeetWithoutSeams) {
  const PointCloud cloud = test::sample_torus(25000);
  ReconstructOptions options;
  options.meshing.coarsening.noise_share = 0;  // every vertex of the lattice
  const Reconstruction tiled = reconstruct_tiled(cloud, regions_of(8000), options);
  ASSERT_TRUE(tiled.mesh);
  // The tiles welded are the mesh of the merged tree meshed whole, triangle for triangle, to
  // the bit: nothing differs along a tile border.
  const CloudIndex index(cloud);
  const SurfaceMesh whole = mesh_tree(tiled.tree, options.meshing, &index);
  EXPECT_EQ(test::triangle_set(tiled.mesh->mesh), test::triangle_set(whole.mesh));
  EXPECT_EQ(tiled.mesh->mesh.vertices.rows(), whole.mesh.vertices.rows());
  const MeshTopology topology = mesh_topology(tiled.mesh->mesh);
  EXPECT_EQ(topology.non_manifold_edges, 0u);
  EXPECT_EQ(topology.components, 1u);
  EXPECT_GT(topology.signed_volume, 0);
}

TEST(Tiling, TilesMergeFlatBlocksAsTheWholeMeshDoesAwayFromTheirBorders) {
  // A gently curved sheet under noise, whose flat blocks merge: the tiles merge them as the
  // whole mesh does with the vertices near a region border fixed, to the bit, and meet.
  const PointCloud cloud = test::noisy_heightfield(
      60000, 0.003, [](double x, double y) { return 0.1 * std::sin(3 * x) * std::cos(2 * y); }, 9);
  const Reconstruction tiled = reconstruct_tiled(cloud, regions_of(45000));
  ASSERT_TRUE(tiled.mesh);
  const auto total = static_cast<std::uint64_t>(cloud.size());  // reconstruct_tiled()'s plan
  const RegionPlan plan = plan_regions(cloud.positions, total, bounding_box(cloud.positions),
                                       spacing_from_sample(cloud.positions, total), regions_of(45000));
  ASSERT_GE(plan.regions(), 2u);

  const CloudIndex index(cloud);
  SurfaceMeshOptions fine;
  fine.coarsening.noise_share = 0;
  fine.refit.points = 0;
  TriangleMesh whole = mesh_tree(tiled.tree, fine, &index).mesh;
  const double cell = tiled.mesh->grid.voxel_size;
  const Eigen::VectorXf fixed = near_other_regions(whole, plan, kTileFixedCells * cell);
  EXPECT_GT(fixed.sum(), 0);
  EXPECT_LT(fixed.sum(), 0.5 * static_cast<float>(fixed.size()));
  const std::size_t lattice_triangles = static_cast<std::size_t>(whole.triangles.rows());
  whole = coarsen_mesh(whole, tiled.tree.bbox.min, cell, coarsening_scale(tiled.tree), {}, nullptr,
                       std::span<const float>(fixed.data(), static_cast<std::size_t>(fixed.size())));
  refit_vertices(whole, clustered_subset(index, tiled.tree).index, ImplicitSurface(tiled.tree));
  EXPECT_EQ(test::triangle_set(tiled.mesh->mesh), test::triangle_set(whole));
  EXPECT_EQ(tiled.mesh->mesh.vertices.rows(), whole.vertices.rows());
  // The merges took most of the lattice's triangles, and the report counts them (the tiles'
  // triangles, before the join drops the fragments the data does not support).
  EXPECT_LT(tiled.mesh->mesh.triangles.rows(), lattice_triangles / 2);
  EXPECT_NEAR(static_cast<double>(tiled.mesh->coarsening.triangles_after),
              static_cast<double>(tiled.mesh->mesh.triangles.rows()),
              0.01 * static_cast<double>(whole.triangles.rows()));
  EXPECT_GE(tiled.mesh->coarsening.triangles_before, lattice_triangles);
  EXPECT_GT(tiled.mesh->coarsening.tolerance, 0);
  const MeshTopology topology = mesh_topology(tiled.mesh->mesh);
  EXPECT_EQ(topology.non_manifold_edges, 0u);
  EXPECT_EQ(topology.components, 1u);
  EXPECT_EQ(topology.inconsistent_edges, 0u);
}

TEST(Tiling, TiledSurfaceIsTheInCoreSurface) {
  const PointCloud cloud = test::sample_torus(25000);
  const Reconstruction in_core = reconstruct(cloud);
  const Reconstruction tiled = reconstruct_tiled(cloud, regions_of(8000));
  ASSERT_TRUE(tiled.mesh && in_core.mesh);
  const double cell = in_core.mesh->grid.voxel_size;
  // The cell follows the regions' spacing, a median of their medians.
  EXPECT_NEAR(tiled.mesh->grid.voxel_size, cell, 0.01 * cell);
  const SurfaceComparison c = compare_surfaces(tiled.mesh->mesh, in_core.mesh->mesh);
  EXPECT_LT(c.hausdorff, 0.5 * cell);
  EXPECT_LT(c.chamfer, 0.02 * cell);
}

TEST(Tiling, RegionsOrientedByPropagationAgree) {
  PointCloud cloud = test::sample_torus(25000);
  cloud.normals.resize(0, 3);
  const Reconstruction tiled = reconstruct_tiled(cloud, regions_of(8000));
  ASSERT_TRUE(tiled.mesh);
  // One surface facing out: no region flipped against its neighbours, none inside out.
  const MeshTopology topology = mesh_topology(tiled.mesh->mesh);
  EXPECT_EQ(topology.components, 1u);
  EXPECT_EQ(topology.inconsistent_edges, 0u);
  EXPECT_GT(topology.signed_volume, 0);
}

TEST(Tiling, RefusesWhatTilesCannotDo) {
  const PointCloud cloud = test::sample_sphere(3000);
  ReconstructOptions options;
  options.meshing.closing.enabled = true;
  EXPECT_THROW(reconstruct_tiled(cloud, regions_of(1000), options), OptionError);
  EXPECT_THROW(plan_regions(cloud.positions, 3000, bounding_box(cloud.positions), 0.01, regions_of(0)), OptionError);
}

// Points in tight clumps (3,000 clumps of 10, a thirtieth of their distance apart): the median
// spacing is the clumps' own. The tiles take the in-core automatic cell, coarsened for the clumps
// (auto_cell_size() of the merged tree), not twice that spacing, a grid of some hundred surface
// cells per point.
TEST(Tiling, ClumpedPointsGetTheInCoreAutomaticCell) {
  std::mt19937_64 rng(4);
  std::normal_distribution<double> g(0, 1);
  PointCloud c;
  c.positions.resize(30000, 3);
  for (Eigen::Index row = 0; row < c.positions.rows();) {
    const Eigen::Vector3d centre = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    for (int p = 0; p < 10; ++p)
      c.positions.row(row++) = (centre + 0.002 * Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized().transpose();
  }
  c.normals = c.positions;  // the unit sphere's outward normals
  const Reconstruction tiled = reconstruct_tiled(c, regions_of(12000));
  ASSERT_TRUE(tiled.mesh);
  EXPECT_DOUBLE_EQ(tiled.mesh->grid.voxel_size, auto_cell_size(ImplicitSurface(tiled.tree)));
  EXPECT_GT(tiled.mesh->grid.voxel_size, 4 * tiled.tree.point_spacing);
}
