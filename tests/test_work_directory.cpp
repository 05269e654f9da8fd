// A tiled run's work directory: used alongside files that are not the run's, which are never
// touched, whether the run succeeds, fails half way or is cancelled; only the run's own files
// are removed, and the directories it created when that leaves them empty; paths that cannot
// be a work directory are refused before any work.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// The names in a directory, sorted.
std::vector<std::string> listing(const std::filesystem::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

struct Fixture {
  test::TempDir dir;
  std::filesystem::path input = dir / "torus.ply";
  std::filesystem::path work = dir / "precious";
  Fixture() {
    write_ply(input, test::sample_torus(12000));
    std::filesystem::create_directory(work);
    test::write_file(work / "thesis.txt", "my thesis\n");
    // Named like a temporary file, but of no file a run writes.
    test::write_file(work / ".notes.txt.tmp123456", "my notes\n");
  }
  OutOfCoreOptions out_of_core() const {
    OutOfCoreOptions o;
    o.memory_limit = std::uint64_t{128} << 20;
    o.work_directory = work;
    o.mesh_output = dir / "mesh.ply";
    return o;
  }
  bool users_files_intact() const {
    return test::read_file(work / "thesis.txt") == "my thesis\n" &&
           test::read_file(work / ".notes.txt.tmp123456") == "my notes\n";
  }
};

PartitionOptions small_regions() {
  PartitionOptions o;
  o.regions.max_points = 4000;
  return o;
}

}  // namespace

TEST(WorkDirectory, AUsersDirectoryKeepsTheirFilesAndLosesOnlyTheRuns) {
  const Fixture f;
  const OutOfCoreReconstruction r = reconstruct_out_of_core(f.input, {}, f.out_of_core());
  ASSERT_TRUE(r.mesh);
  EXPECT_GT(r.mesh->triangles, 1000u);
  EXPECT_GT(r.work_bytes, 12000u * 24);  // the region files at least, not the user's
  EXPECT_TRUE(f.users_files_intact());
  EXPECT_EQ(listing(f.work), (std::vector<std::string>{".notes.txt.tmp123456", "thesis.txt"}));
}

TEST(WorkDirectory, ARunThatCreatedItsDirectoriesRemovesThemWhenEmpty) {
  const Fixture f;
  OutOfCoreOptions o = f.out_of_core();
  o.work_directory = f.dir / "new" / "deeper" / "work";
  reconstruct_out_of_core(f.input, {}, o);
  EXPECT_FALSE(std::filesystem::exists(f.dir / "new"));
  // A parent the user put a file in while the run went on is kept, with the file.
  const TiledRun run = TiledRun::partition(f.input, f.dir / "new" / "work", small_regions());
  test::write_file(f.dir / "new" / "mine.txt", "mine\n");
  remove_tiled_run(run.directory());
  EXPECT_EQ(listing(f.dir / "new"), std::vector<std::string>{"mine.txt"});
}

TEST(WorkDirectory, ACancelledRunKeepsTheUsersFilesAndResumes) {
  const Fixture f;
  int calls = 0;
  const ProgressCallback cancel_in_the_builds = [&](std::string_view stage, double) {
    return !(stage == "building regions" && ++calls == 1);
  };
  EXPECT_THROW(reconstruct_out_of_core(f.input, {}, f.out_of_core(), cancel_in_the_builds), Cancelled);
  EXPECT_TRUE(f.users_files_intact());
  EXPECT_FALSE(std::filesystem::exists(f.dir / "mesh.ply"));
  EXPECT_TRUE(std::filesystem::exists(f.work / "plan.txt"));  // kept for a resume
  reconstruct_out_of_core(f.input, {}, f.out_of_core());
  EXPECT_TRUE(std::filesystem::exists(f.dir / "mesh.ply"));
  EXPECT_EQ(listing(f.work), (std::vector<std::string>{".notes.txt.tmp123456", "thesis.txt"}));
}

TEST(WorkDirectory, ARunThatFailsHalfWayKeepsTheUsersFiles) {
  const Fixture f;
  OutOfCoreOptions o = f.out_of_core();
  o.mesh_output = f.dir / "no such folder" / "mesh.ply";  // the join cannot write
  EXPECT_THROW(reconstruct_out_of_core(f.input, {}, o), IoError);
  EXPECT_TRUE(f.users_files_intact());
  // A killed task's temporary file is the run's; it goes with the rest.
  test::write_file(f.work / ".tile-000000.bin.tmpAbC123", "partial");
  remove_tiled_run(f.work);
  EXPECT_EQ(listing(f.work), (std::vector<std::string>{".notes.txt.tmp123456", "thesis.txt"}));
}

TEST(WorkDirectory, PathsThatCannotBeAWorkDirectoryAreRefusedBeforeAnyWork) {
  const Fixture f;
  // A file.
  test::write_file(f.dir / "afile", "data\n");
  try {
    TiledRun::partition(f.input, f.dir / "afile", small_regions());
    FAIL() << "a file was taken for a work directory";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("is not a directory"), std::string::npos) << e.what();
  }
  EXPECT_EQ(test::read_file(f.dir / "afile"), "data\n");
  // A directory holding a file named like a run's, of something else.
  test::write_file(f.work / "plan.txt", "my plan\n");
  try {
    TiledRun::partition(f.input, f.work, small_regions());
    FAIL() << "a foreign plan.txt was taken for a run's";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("holds plan.txt"), std::string::npos) << e.what();
  }
  EXPECT_EQ(test::read_file(f.work / "plan.txt"), "my plan\n");
  EXPECT_EQ(listing(f.work), (std::vector<std::string>{".notes.txt.tmp123456", "plan.txt", "thesis.txt"}));
  // Removing a directory that holds no run touches nothing.
  remove_tiled_run(f.work);
  EXPECT_EQ(listing(f.work).size(), 3u);
}

TEST(WorkDirectory, AnotherInputsRunIsRefusedNotReplaced) {
  const Fixture f;
  const TiledRun run = TiledRun::partition(f.input, f.work, small_regions());
  const std::filesystem::path other = f.dir / "other.ply";
  write_ply(other, test::sample_torus(9000, 1.0, 0.3));
  EXPECT_THROW(TiledRun::partition(other, f.work, small_regions()), OptionError);
  PartitionOptions larger = small_regions();
  larger.regions.max_points *= 2;
  EXPECT_THROW(TiledRun::partition(f.input, f.work, larger), OptionError);
  EXPECT_TRUE(std::filesystem::exists(f.work / "region-000000.own"));  // the first run's files are kept
  EXPECT_EQ(TiledRun::partition(f.input, f.work, small_regions()).regions(), run.regions());  // the same run is reused
  remove_tiled_run(f.work);
  EXPECT_TRUE(f.users_files_intact());
}

TEST(WorkDirectory, AMalformedRunRecordIsAClearError) {
  const Fixture f;
  test::write_file(f.work / "clustersurf-run.txt", "clustersurf-run 1\ncreated-levels x\n");
  try {
    remove_tiled_run(f.work);
    FAIL() << "a malformed run record was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, std::optional<std::uint64_t>(2)) << e.what();
  }
  EXPECT_TRUE(f.users_files_intact());
}

TEST(WorkDirectory, APathThroughDotDotNeverCountsAParentItDidNotCreate) {
  const Fixture f;
  std::filesystem::create_directory(f.dir / "empty");  // the user's, empty
  const TiledRun run = TiledRun::partition(f.input, f.dir / "missing" / ".." / "empty" / "work", small_regions());
  EXPECT_FALSE(std::filesystem::exists(f.dir / "missing"));  // only "empty/work" was made
  remove_tiled_run(f.dir / "empty" / "work");
  EXPECT_TRUE(std::filesystem::is_directory(f.dir / "empty"));
  EXPECT_TRUE(std::filesystem::is_empty(f.dir / "empty"));
}

TEST(WorkDirectory, AMeshNamedLikeTheRunsOwnFilesIsRefused) {
  const Fixture f;
  OutOfCoreOptions o = f.out_of_core();
  o.mesh_output = f.work / "tile-all.ply";
  o.remove_work_directory = false;
  EXPECT_THROW(reconstruct_out_of_core(f.input, {}, o), OptionError);
  EXPECT_TRUE(f.users_files_intact());
  EXPECT_FALSE(std::filesystem::exists(f.work / "survey-000000.txt"));  // refused before any region was worked on
}
