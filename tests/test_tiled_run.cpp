// A tiled run on disk: the partition, each stage a task that reads and writes files, the same
// result as the tiled pipeline in memory; interrupted runs resume, damaged files are refused.

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

#include <gtest/gtest.h>

#include <fstream>

#include "io_test_files.hpp"
#include "tiling/tiles.hpp"

using namespace clustersurf;

namespace {

/// A torus written as a binary PLY of doubles (read back bit for bit) and read again.
struct TorusFile {
  test::TempDir dir;
  std::filesystem::path file = dir / "torus.ply";
  PointCloud cloud;
  explicit TorusFile(int n) {
    PlyWriteOptions ply;
    ply.double_precision = true;
    write_ply(file, test::sample_torus(n), ply);
    cloud = read_point_cloud(file);
  }
};

PartitionOptions small_regions(std::uint64_t points) {
  PartitionOptions o;
  o.regions.max_points = points;
  o.block_points = 1000;  // many blocks
  return o;
}

/// Every stage of `run`, region after region.
SurfaceMesh run_all(const TiledRun& run, const ReconstructOptions& options) {
  for (std::int32_t r = 0; r < static_cast<std::int32_t>(run.regions()); ++r) run.survey(r, options.build);
  for (std::int32_t r = 0; r < static_cast<std::int32_t>(run.regions()); ++r) run.build(r, options.build);
  run.merge();
  for (std::int32_t r = 0; r < static_cast<std::int32_t>(run.regions()); ++r) run.mesh(r, options);
  return run.join(options.meshing);
}

bool same_mesh(const TriangleMesh& a, const TriangleMesh& b) {
  return a.vertices == b.vertices && a.triangles == b.triangles && a.normals == b.normals;
}

}  // namespace

TEST(TiledRun, FilesGiveTheTiledPipelinesResult) {
  const TorusFile torus(15000);
  const TiledRun run = TiledRun::partition(torus.file, torus.dir / "work", small_regions(5000));
  ASSERT_GE(run.regions(), 6u);
  EXPECT_EQ(run.input_points(), 15000u);
  EXPECT_TRUE(run.has_normals());
  const ReconstructOptions options;
  const SurfaceMesh mesh = run_all(run, options);

  RegionOptions regions;
  regions.max_points = 5000;
  ReconstructOptions in_memory = options;
  in_memory.build.keep_point_leaves = false;
  const Reconstruction tiled = reconstruct_tiled(torus.cloud, regions, in_memory);
  EXPECT_EQ(serialize_tree(run.merge()), serialize_tree(tiled.tree));
  EXPECT_TRUE(same_mesh(mesh.mesh, tiled.mesh->mesh));
  EXPECT_TRUE(run.orientation().used_normals);
  // The mesh tasks read only the region trees their tiles meet, and still give the merged
  // tree's tiles (the pipeline in memory meshes the merged tree): some regions are left out.
  MeshOptions grid;
  grid.voxel_size = tiled_cell_size(tiled.tree, options.meshing);
  const RegionMerge record = run.merge_record();
  std::size_t partial = 0;
  for (std::int32_t r = 0; r < static_cast<std::int32_t>(run.regions()); ++r)
    partial += tile_regions(run.plan(), record, r, grid).size() < run.regions();
  EXPECT_GT(partial, 0u);
  EXPECT_EQ(record.leaves, tiled.tree.leaves().size());
}

TEST(TiledRun, ResumedRunRedoesOnlyWhatIsMissing) {
  const TorusFile torus(12000);
  const std::filesystem::path work = torus.dir / "work";
  const ReconstructOptions options;
  SurfaceMesh expected;
  {
    const TiledRun run = TiledRun::partition(torus.file, torus.dir / "whole", small_regions(4000));
    expected = run_all(run, options);
  }
  std::filesystem::file_time_type first_tree;
  {
    // Interrupted after the first region's build.
    const TiledRun run = TiledRun::partition(torus.file, work, small_regions(4000));
    for (std::int32_t r = 0; r < static_cast<std::int32_t>(run.regions()); ++r) run.survey(r, options.build);
    run.build(0, options.build);
    first_tree = std::filesystem::last_write_time(work / "tree-000000.cstree");
    EXPECT_TRUE(run.done("build", 0));
    EXPECT_FALSE(run.done("build", 1));
    EXPECT_THROW(run.merge(), InputError);  // a stage needs the one before
  }
  const TiledRun resumed = TiledRun::partition(torus.file, work, small_regions(4000));
  EXPECT_TRUE(resumed.done("survey", 1));  // the partition and the surveys were kept
  const SurfaceMesh mesh = run_all(resumed, options);
  EXPECT_EQ(std::filesystem::last_write_time(work / "tree-000000.cstree"), first_tree);
  EXPECT_TRUE(same_mesh(mesh.mesh, expected.mesh));
}

TEST(TiledRun, OutOfCoreRunCleansUpAndEqualsTheTiledPipeline) {
  const TorusFile torus(12000);
  OutOfCoreOptions out_of_core;
  out_of_core.memory_limit = std::uint64_t{128} << 20;
  out_of_core.work_directory = torus.dir / "work";
  out_of_core.mesh_output = torus.dir / "mesh.ply";
  const OutOfCoreReconstruction r = reconstruct_out_of_core(torus.file, {}, out_of_core);
  ASSERT_TRUE(r.mesh);
  EXPECT_TRUE(r.mesh->streamed);
  EXPECT_FALSE(std::filesystem::exists(out_of_core.work_directory));
  RegionOptions regions;
  regions.max_points = region_points_for_memory(out_of_core.memory_limit);
  ReconstructOptions in_memory;
  in_memory.build.keep_point_leaves = false;
  const Reconstruction tiled = reconstruct_tiled(torus.cloud, regions, in_memory);
  EXPECT_EQ(serialize_tree(r.tree), serialize_tree(tiled.tree));
  write_ply(torus.dir / "tiled.ply", tiled.mesh->mesh);
  EXPECT_EQ(test::read_file(out_of_core.mesh_output), test::read_file(torus.dir / "tiled.ply"));
  EXPECT_EQ(r.mesh->vertices, static_cast<std::size_t>(tiled.mesh->mesh.vertices.rows()));
  EXPECT_TRUE(r.orientation.used_normals);
}

// The driver with its tasks run elsewhere (as Dask runs them): each task reopens the run from
// its directory, the regions in reverse order; the tree and the mesh are the same bytes as the
// run whose tasks ran here, and a runner that leaves a task undone is an error.
TEST(TiledRun, TasksRunByARunnerInAnyOrderGiveTheSameResult) {
  const TorusFile torus(12000);
  OutOfCoreOptions here;
  here.max_region_points = 5000;
  here.work_directory = torus.dir / "here";
  here.mesh_output = torus.dir / "here.ply";
  const OutOfCoreReconstruction a = reconstruct_out_of_core(torus.file, {}, here);
  OutOfCoreOptions elsewhere = here;
  elsewhere.work_directory = torus.dir / "elsewhere";
  elsewhere.mesh_output = torus.dir / "elsewhere.ply";
  std::vector<std::string> stages;
  elsewhere.run_tasks = [&](std::string_view stage, std::span<const std::int32_t> regions, const ProgressCallback&) {
    stages.emplace_back(stage);
    const TiledRun run(elsewhere.work_directory);
    const ReconstructOptions options;
    for (auto k = regions.rbegin(); k != regions.rend(); ++k) {
      if (stage == "survey") run.survey(*k, options.build);
      if (stage == "build") run.build(*k, options.build);
      if (stage == "mesh") run.mesh(*k, options);
    }
  };
  const OutOfCoreReconstruction b = reconstruct_out_of_core(torus.file, {}, elsewhere);
  EXPECT_GT(b.regions, 1u);
  EXPECT_EQ(stages, (std::vector<std::string>{"survey", "build", "mesh"}));
  EXPECT_EQ(serialize_tree(a.tree), serialize_tree(b.tree));
  EXPECT_EQ(test::read_file(here.mesh_output), test::read_file(elsewhere.mesh_output));
  OutOfCoreOptions lazy = here;
  lazy.work_directory = torus.dir / "lazy";
  lazy.mesh_output = torus.dir / "lazy.ply";
  lazy.run_tasks = [](std::string_view, std::span<const std::int32_t>, const ProgressCallback&) {};
  EXPECT_THROW(reconstruct_out_of_core(torus.file, {}, lazy), Error);
}

// A survey's LAS file is read in place (PointStream) and gives the tiled pipeline's result on
// the same points read whole.
TEST(TiledRun, LasInputIsReadInPlaceAndTiled) {
  const test::TempDir dir;
  const PointCloud torus = test::sample_torus(12000);
  const Eigen::Index n = torus.size();
  test::LasFile las(6, 30, static_cast<std::uint64_t>(n), {1e-6, 1e-6, 1e-6}, {0, 0, 0});
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d x = torus.positions.row(i).transpose() * 1e6;
    las.record(30, static_cast<std::int32_t>(std::lround(x.x())), static_cast<std::int32_t>(std::lround(x.y())),
               static_cast<std::int32_t>(std::lround(x.z())), 0);
  }
  const std::filesystem::path file = dir / "torus.las";
  test::write_file(file, las.bytes);
  const TiledRun run = TiledRun::partition(file, dir / "work", small_regions(4000));
  ASSERT_GE(run.regions(), 3u);
  EXPECT_EQ(run.input_points(), static_cast<std::uint64_t>(n));
  EXPECT_FALSE(run.has_normals());
  const ReconstructOptions options;
  const SurfaceMesh mesh = run_all(run, options);
  RegionOptions regions;
  regions.max_points = 4000;
  ReconstructOptions in_memory = options;
  in_memory.build.keep_point_leaves = false;
  const Reconstruction tiled = reconstruct_tiled(read_point_cloud(file), regions, in_memory);
  EXPECT_EQ(serialize_tree(run.merge()), serialize_tree(tiled.tree));
  EXPECT_TRUE(same_mesh(mesh.mesh, tiled.mesh->mesh));
  EXPECT_GT(mesh.mesh.triangles.rows(), 1000);
}

TEST(TiledRun, MeshJoinedIntoTheFileTileByTileIsTheJoinedMeshWritten) {
  const TorusFile torus(15000);
  const TiledRun run = TiledRun::partition(torus.file, torus.dir / "work", small_regions(4000));
  ReconstructOptions options;
  options.meshing.coloring = MeshColoring::ByNode;
  options.meshing.trim.min_component_points = 2000;  // drops fragments, so that the vote decides something
  const SurfaceMesh joined = run_all(run, options);
  write_ply(torus.dir / "joined.ply", joined.mesh);
  const WrittenMesh streamed = run.write_mesh(torus.dir / "streamed.ply", options.meshing);
  EXPECT_TRUE(streamed.streamed);
  EXPECT_EQ(streamed.triangles, static_cast<std::size_t>(joined.mesh.triangles.rows()));
  EXPECT_EQ(test::read_file(torus.dir / "streamed.ply"), test::read_file(torus.dir / "joined.ply"));
  // Other formats, ascii and decimated meshes are joined in memory and written.
  const WrittenMesh obj = run.write_mesh(torus.dir / "mesh.obj", options.meshing);
  EXPECT_FALSE(obj.streamed);
  EXPECT_EQ(obj.triangles, streamed.triangles);
}

// A scan's colors and up axis go through the region files and the tiles: the run's mesh is the
// tiled pipeline's in memory, colors and all, the streamed PLY is the joined mesh's bytes, and
// the colors agree with the mesh of the whole cloud in core.
TEST(TiledRun, ColorsAndTheUpAxisGoThroughTheRun) {
  const test::TempDir dir;
  PointCloud torus = test::sample_torus(15000);
  torus.colors.resize(torus.size(), 3);
  for (Eigen::Index i = 0; i < torus.size(); ++i)
    torus.colors.row(i) = torus.positions(i, 0) > 0.2 ? Eigen::Matrix<std::uint8_t, 1, 3>(200, 40, 10)
                                                      : Eigen::Matrix<std::uint8_t, 1, 3>(30, 90, 160);
  torus.up = UpAxis::Z;
  PlyWriteOptions ply;
  ply.double_precision = true;
  write_ply(dir / "torus.ply", torus, ply);
  const PointCloud cloud = read_point_cloud(dir / "torus.ply");
  const TiledRun run = TiledRun::partition(dir / "torus.ply", dir / "work", small_regions(4000));
  ASSERT_GE(run.regions(), 3u);
  const ReconstructOptions options;
  const SurfaceMesh mesh = run_all(run, options);
  ASSERT_EQ(mesh.mesh.colors.rows(), mesh.mesh.vertices.rows());
  EXPECT_EQ(mesh.mesh.up, UpAxis::Z);
  EXPECT_EQ(run.merge().up, UpAxis::Z);

  RegionOptions regions;
  regions.max_points = 4000;
  ReconstructOptions in_memory = options;
  in_memory.build.keep_point_leaves = false;
  const Reconstruction tiled = reconstruct_tiled(cloud, regions, in_memory);
  EXPECT_TRUE(same_mesh(mesh.mesh, tiled.mesh->mesh));
  EXPECT_EQ(mesh.mesh.colors, tiled.mesh->mesh.colors);

  write_ply(dir / "joined.ply", mesh.mesh);
  EXPECT_TRUE(run.write_mesh(dir / "streamed.ply", options.meshing).streamed);
  EXPECT_EQ(test::read_file(dir / "streamed.ply"), test::read_file(dir / "joined.ply"));
  // A join asked for no colors drops the tiles' own, in memory and streamed alike.
  SurfaceMeshOptions plain = options.meshing;
  plain.coloring = MeshColoring::None;
  EXPECT_EQ(run.join(plain).mesh.colors.rows(), 0);
  run.write_mesh(dir / "plain.ply", plain);
  EXPECT_FALSE(read_triangle_mesh(dir / "plain.ply").colors.rows() > 0);

  // In core: the same colors wherever the meshes share a vertex's neighbourhood.
  const Reconstruction whole = reconstruct(cloud);
  const KdTree core(whole.mesh->mesh.vertices);
  std::size_t differ = 0;
  std::vector<Neighbor> nb;
  for (Eigen::Index v = 0; v < mesh.mesh.vertices.rows(); ++v) {
    core.knn(mesh.mesh.vertices.row(v).transpose(), 1, nb);
    differ += mesh.mesh.colors.row(v) != whole.mesh->mesh.colors.row(nb[0].index);
  }
  EXPECT_LT(static_cast<double>(differ), 0.02 * static_cast<double>(mesh.mesh.vertices.rows()));
}

TEST(TiledRun, RefusesOtherOptionsInTheSameDirectory) {
  const TorusFile torus(5000);
  const TiledRun run = TiledRun::partition(torus.file, torus.dir / "work", small_regions(2000));
  ReconstructOptions options;
  run.claim(options);
  run.claim(options);  // the same options: fine
  options.build.tolerance *= 2;
  EXPECT_THROW(run.claim(options), OptionError);
}

TEST(TiledRun, DamagedFilesAreClearErrors) {
  const TorusFile torus(5000);
  const std::filesystem::path work = torus.dir / "work";
  const TiledRun run = TiledRun::partition(torus.file, work, small_regions(2000));
  const ReconstructOptions options;
  run_all(run, options);
  // A truncated region file: its size against the plan's count.
  std::filesystem::resize_file(work / "region-000001.own", 100);
  try {
    run.load(1);
    FAIL() << "a truncated region file was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("region-000001.own"), std::string::npos) << e.what();
  }
  // A truncated tile.
  std::filesystem::resize_file(work / "tile-000000.bin", 200);
  EXPECT_THROW(run.join(options.meshing), InputError);
  // A merge record whose region line is broken: the line is named, no tile is made.
  std::filesystem::remove(work / "tile-000001.bin");
  test::write_file(work / "merge.txt", "merge 10 0.01 0 0 0 1 1 1 0.02\nregions 2\nregion 0 0.5\nregion 2 0.5\n");
  try {
    run.mesh(1, options);
    FAIL() << "a broken merge record was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, std::optional<std::uint64_t>(4)) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(work / "tile-000001.bin"));
  // A plan that is not one: the line is named.
  test::write_file(work / "plan.txt", "clustersurf-tiles 2\ninput 1 2 3\n");
  try {
    TiledRun reopened(work);
    FAIL() << "a broken plan was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, std::optional<std::uint64_t>(2)) << e.what();
  }
}

TEST(TiledRun, MemorySizes) {
  EXPECT_EQ(format_memory_size(std::uint64_t{4} << 30), "4G");
  EXPECT_EQ(format_memory_size(std::uint64_t{3} << 29), "1536M");
  EXPECT_EQ(format_memory_size(1000), "1000");
  for (const std::uint64_t bytes :
       {std::uint64_t{1}, std::uint64_t{1} << 20, (std::uint64_t{5} << 40) + 1024, std::uint64_t{123456789}})
    EXPECT_EQ(parse_memory_size(format_memory_size(bytes)), bytes) << bytes;
  EXPECT_EQ(default_work_directory("out/mesh.ply"), std::filesystem::path("out/mesh.ply.work"));
  EXPECT_EQ(parse_memory_size("4G"), std::uint64_t{4} << 30);
  EXPECT_EQ(parse_memory_size("512M"), std::uint64_t{512} << 20);
  EXPECT_EQ(parse_memory_size("1.5GiB"), std::uint64_t{3} << 29);
  EXPECT_EQ(parse_memory_size("1000"), 1000u);
  for (const char* bad : {"", "G", "4X", "-1G", "0", "nan"}) EXPECT_THROW(parse_memory_size(bad), OptionError) << bad;
  EXPECT_THROW(region_points_for_memory(1 << 20), OptionError);
}

TEST(TiledRun, PointsRepeatingTheirPositionsGiveTheDistinctPointsSurface) {
  const PointCloud torus = test::sample_torus(12000);
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < torus.size(); ++i)
    for (int copy = 0; copy < 3; ++copy) rows.push_back(i);
  PointCloud repeated;
  repeated.positions = torus.positions(rows, Eigen::all);
  repeated.normals = torus.normals(rows, Eigen::all);
  RegionOptions regions;
  regions.max_points = 4000;
  ReconstructOptions options;
  options.build.keep_point_leaves = false;
  const Reconstruction distinct = reconstruct_tiled(torus, regions, options);
  regions.max_points = 3 * 4000;  // the same cells around three times the points
  const Reconstruction r = reconstruct_tiled(repeated, regions, options);
  ASSERT_TRUE(r.mesh.has_value());
  EXPECT_EQ(r.tree.point_spacing, distinct.tree.point_spacing);
  // Each region judges its outliers among points whose spreads count their repeats, so a few
  // leaves differ; the surfaces lie within a small share of a cell of each other.
  const double cell = r.mesh->grid.voxel_size;
  EXPECT_EQ(cell, distinct.mesh->grid.voxel_size);
  const SurfaceComparison c = compare_surfaces(r.mesh->mesh, distinct.mesh->mesh);
  EXPECT_LT(c.hausdorff, 0.5 * cell);
  EXPECT_LT(c.chamfer, 0.02 * cell);
}
