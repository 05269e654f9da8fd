// Mesh extraction: accuracy against the true surface, manifoldness, watertightness, Euler
// characteristic, outward orientation, holes where data is missing.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/io/surface_sampling.hpp>
#include <clustersurf/mesh/mesh_check.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/surface/implicit_surface.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <iostream>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

TriangleMesh mesh_of(const PointCloud& c, std::uint32_t resolution, ClusterTree* keep = nullptr) {
  ClusterTree t = build_cluster_tree(c, {});
  orient_tree(t, c);
  const ImplicitSurface f(t);
  MeshOptions o;
  o.resolution = resolution;
  TriangleMesh m = extract_mesh(f, o);
  if (keep != nullptr) *keep = std::move(t);
  return m;
}

double diagonal(const PointCloud& c) { return bounding_box(c.positions).diagonal(); }

}  // namespace

TEST(MeshExtraction, SphereIsAccurateWatertightGenusZeroAndOutward) {
  const PointCloud c = test::sample_sphere(30000, 1.0);
  const TriangleMesh m = mesh_of(c, 128);
  ASSERT_GT(m.triangles.rows(), 1000);
  const double tol = 0.002 * diagonal(c);
  double worst = 0;
  for (Eigen::Index v = 0; v < m.vertices.rows(); ++v)
    worst = std::max(worst, std::abs(m.vertices.row(v).norm() - 1.0));
  EXPECT_LT(worst, tol);
  const MeshTopology t = mesh_topology(m);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
  EXPECT_EQ(t.euler_characteristic, 2);
  EXPECT_NEAR(t.signed_volume, 4.0 / 3.0 * M_PI, 0.01 * 4.0 / 3.0 * M_PI);
  // Normals point away from the center.
  for (Eigen::Index v = 0; v < m.vertices.rows(); v += 17) EXPECT_GT(m.normals.row(v).dot(m.vertices.row(v)), 0.99);
}

TEST(MeshExtraction, NoisySphereMeshAveragesTheNoise) {
  // Noise of 0.25 % of the diagonal along the normals: the mesh lies much closer to the true
  // sphere than the points do (each proxy is fitted to its whole weighted support), and stays
  // one closed surface.
  PointCloud c = test::sample_sphere(40000, 1.0);
  const double sigma = 0.0025 * diagonal(c);
  test::add_normal_noise(c, sigma, 11);
  const TriangleMesh m = mesh_of(c, 128);
  double sum = 0, worst = 0;
  for (Eigen::Index v = 0; v < m.vertices.rows(); ++v) {
    const double d = std::abs(m.vertices.row(v).norm() - 1.0);
    sum += d;
    worst = std::max(worst, d);
  }
  const double mean = sum / static_cast<double>(m.vertices.rows());
  std::cout << "noisy sphere: mean distance " << mean / sigma << " sigma, worst " << worst / sigma << " sigma\n";
  EXPECT_LT(mean, 0.15 * sigma);
  EXPECT_LT(worst, 2.0 * sigma);
  const MeshTopology t = mesh_topology(m);
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.euler_characteristic, 2);
}

TEST(MeshExtraction, TorusIsAccurateWatertightGenusOne) {
  const PointCloud c = test::sample_torus(60000, 1.0, 0.35);
  const TriangleMesh m = mesh_of(c, 128);
  const double tol = 0.002 * diagonal(c);
  double worst = 0;
  for (Eigen::Index v = 0; v < m.vertices.rows(); ++v) {
    const Eigen::Vector3d p = m.vertices.row(v).transpose();
    const double ring = std::hypot(p.x(), p.y()) - 1.0;
    worst = std::max(worst, std::abs(std::hypot(ring, p.z()) - 0.35));
  }
  EXPECT_LT(worst, tol);
  const MeshTopology t = mesh_topology(m);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_EQ(t.components, 1u);
  EXPECT_GT(t.signed_volume, 0);
}

TEST(MeshExtraction, MissingDataGivesAHoleNotAWall) {
  // A hemisphere (z > 0 only): the mesh continues the sphere a little past the data (the
  // supports reach beyond it) and ends in a boundary; no wall closes the opening (a wall
  // would put vertices well inside the sphere).
  PointCloud full = test::sample_sphere(30000, 1.0);
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < full.size(); ++i)
    if (full.positions(i, 2) > 0) keep.push_back(i);
  PointCloud half;
  half.positions = full.positions(keep, Eigen::all);
  half.normals = full.normals(keep, Eigen::all);
  const TriangleMesh m = mesh_of(half, 96);
  const MeshTopology t = mesh_topology(m);
  EXPECT_GT(t.boundary_edges, 20u);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  for (Eigen::Index v = 0; v < m.vertices.rows(); ++v) {
    EXPECT_GT(m.vertices(v, 2), -0.5);
    EXPECT_NEAR(m.vertices.row(v).norm(), 1.0, 0.05);
  }
}

TEST(MeshExtraction, SameMeshForOneAndTwoThreads) {
  const PointCloud c = test::sample_torus(20000);
  ClusterTree t = build_cluster_tree(c, {});
  orient_tree(t, c);
  const ImplicitSurface f(t);
  TriangleMesh a, b;
  {
    tbb::task_arena one(1);
    one.execute([&] { a = extract_mesh(f, {}); });
  }
  {
    tbb::task_arena two(2);
    two.execute([&] { b = extract_mesh(f, {}); });
  }
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(MeshExtraction, FineLeavesMeshWithoutPinholes) {
  // A fine tree of a dense sphere: leaves of 8-16 points, supports a few grid cells wide. A
  // cell the surface crosses can then have a corner (up to √3 cells off the surface) outside
  // every support; without the fill band such cells are left out as pinholes.
  const PointCloud c = test::sample_sphere(50000, 1.0);
  BuildOptions b;
  b.threshold_mode = ThresholdMode::Absolute;
  b.tolerance = 1e-6;
  b.min_points = 8;
  ClusterTree t = build_cluster_tree(c, b);
  orient_tree(t, c);
  const ImplicitSurface f(t);
  MeshOptions o;
  o.resolution = 48;
  o.fill_cells = 0;
  const MeshTopology unfilled = mesh_topology(extract_mesh(f, o));
  std::cout << "no fill: " << unfilled.boundary_edges << " boundary edges\n";
  EXPECT_GT(unfilled.boundary_edges, 0u);  // the case the fill is for
  o.fill_cells = MeshOptions{}.fill_cells;
  const TriangleMesh m = extract_mesh(f, o);
  const MeshTopology t2 = mesh_topology(m);
  EXPECT_TRUE(is_watertight(t2)) << t2.boundary_edges << " boundary edges";
  EXPECT_EQ(t2.euler_characteristic, 2);
  double worst = 0;
  for (Eigen::Index v = 0; v < m.vertices.rows(); ++v)
    worst = std::max(worst, std::abs(m.vertices.row(v).norm() - 1.0));
  EXPECT_LT(worst, 0.002 * diagonal(c));
}

TEST(MeshExtraction, AWalkOverItsMemoryLimitIsRefusedBeforeItStarts) {
  const PointCloud c = test::sample_sphere(5000);
  ClusterTree t = build_cluster_tree(c, {});
  orient_tree(t, c);
  const ImplicitSurface f(t);
  MeshOptions o;
  o.voxel_size = 0.001;  // about 12 million surface cells of the unit sphere: some 7 GiB
  o.memory_limit = std::uint64_t{64} << 20;
  try {
    extract_mesh(f, o);
    FAIL() << "a walk of about 7 GiB ran under a 64 MiB limit";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("voxel_size"), std::string::npos) << e.what();
  }
  o.voxel_size = 0.05;  // about 5,000 cells: 3 MiB
  EXPECT_GT(extract_mesh(f, o).triangles.rows(), 1000);
}

TEST(MeshExtraction, AGridWiderThanTheLatticeIsRefusedSayingWhatToChange) {
  // Two spheres 100,000 radii apart: at the automatic cell the box spans some 800,000 cells.
  PointCloud c = test::sample_sphere(3000);
  const PointCloud far = test::sample_sphere(3000, 1.0, Eigen::Vector3d(100000, 0, 0));
  c.positions.conservativeResize(6000, 3);
  c.positions.bottomRows(3000) = far.positions;
  c.normals.conservativeResize(6000, 3);
  c.normals.bottomRows(3000) = far.normals;
  const Reconstruction r = reconstruct(c, [] {
    ReconstructOptions o;
    o.mesh = false;
    return o;
  }());
  const ImplicitSurface f(r.tree);
  MeshOptions o;
  o.voxel_size = auto_cell_size(f);
  try {
    extract_mesh(f, o);
    FAIL() << "a lattice of " << 100000 / *o.voxel_size << " cells along x was walked";
  } catch (const OptionError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("far"), std::string::npos) << what;
    EXPECT_NE(what.find("voxel_size"), std::string::npos) << what;
  }
}

TEST(MeshExtraction, TheProjectionDoesNotFoldTheMesh) {
  // 2,000 points of the bunny: cells of two spacings, where the blend bends sharply within a
  // cell (ears, the rim of the base); a vertex projected onto f = 0 there can be pushed past its
  // neighbours, folding its triangles over each other (before: 7, 0 and 5 pairs of intersecting
  // triangles for the three seeds with supports of 30 points, 18, 7 and 6 with supports of 12).
  const auto file = test::default_bunny();
  if (!file) GTEST_SKIP() << "data/bunny.ply is absent: run scripts/setup";
  const TriangleMesh bunny = read_triangle_mesh(*file);
  std::size_t pairs = 0, triangles = 0;
  for (const std::uint64_t seed : {1, 2, 3}) {
    SurfaceSamplingOptions sampling;
    sampling.count = 2000;
    sampling.seed = seed;
    const Reconstruction r = reconstruct(sample_surface(bunny, sampling));
    ASSERT_TRUE(r.mesh.has_value());
    const MeshCheck check = check_mesh(r.mesh->mesh);
    std::cout << "bunny, 2,000 points, seed " << seed << ": " << check.self_intersections << " intersecting pairs of "
              << r.mesh->mesh.triangles.rows() << " triangles\n";
    pairs += check.self_intersections;
    triangles += static_cast<std::size_t>(r.mesh->mesh.triangles.rows());
  }
  EXPECT_EQ(pairs, 0u);
  EXPECT_GT(triangles, 5000u);
}

// A grid finer than the automatic one (one point spacing instead of about two) meets the same
// small gaps between the leaves' supports in the data; its fill band, counted in automatic
// cells, still bridges them instead of opening them as holes (a closed statue's mesh had 39
// times the automatic grid's boundary edges when the band shrank with the cell).
TEST(MeshExtraction, AFinerGridOpensNoHolesTheAutomaticGridBridges) {
  const auto file = test::shared_data("meshes/igea.ply");
  if (!file) GTEST_SKIP() << "the shared Igea (meshes/igea.ply) is not here";
  SurfaceSamplingOptions sampling;
  sampling.count = 100'000;
  const PointCloud c = sample_surface(read_triangle_mesh(*file), sampling);
  ClusterTree t = build_cluster_tree(c, {});
  orient_tree(t, c);
  SurfaceMeshOptions o;
  const MeshTopology automatic = mesh_topology(mesh_tree(t, o).mesh);
  o.grid.voxel_size = cell_size_for_spacing(t.point_spacing, 1.0);
  const MeshTopology fine = mesh_topology(mesh_tree(t, o).mesh);
  std::cout << "boundary edges: " << automatic.boundary_edges << " on the automatic grid, " << fine.boundary_edges
            << " at one point spacing\n";
  EXPECT_LE(fine.boundary_edges, 4 * automatic.boundary_edges + 50);
}
