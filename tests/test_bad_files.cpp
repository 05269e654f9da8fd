// The hostile-input table: every file of tests/data/bad/ (huge claimed counts, face indices out
// of range, cyclic or out-of-range tree children, truncations, NaN, inputs the fuzzers found) is
// listed in expected.tsv with the reader it goes to and the error it must give. Each must be
// refused with InputError naming the file and carrying that message, quickly (nothing large is
// allocated, no long loop runs). The CLI gives the same messages (tests/cli/test_cli.sh).

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <gtest/gtest.h>

#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace clustersurf {
namespace {

const std::filesystem::path kBad = std::filesystem::path(CLUSTERSURF_TEST_DATA) / "bad";

struct HostileFile {
  std::string file;
  std::string read_as;  // cloud, mesh or tree
  std::string message;
};

std::ostream& operator<<(std::ostream& os, const HostileFile& f) { return os << f.file; }

std::vector<HostileFile> table() {
  std::ifstream in(kBad / "expected.tsv");
  std::vector<HostileFile> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    HostileFile row;
    std::getline(fields, row.file, '\t');
    std::getline(fields, row.read_as, '\t');
    std::getline(fields, row.message);
    rows.push_back(row);
  }
  return rows;
}

TEST(HostileFiles, TableListsEveryFileOfTheFolder) {
  std::set<std::string> listed;
  for (const HostileFile& row : table()) {
    EXPECT_TRUE(listed.insert(row.file).second) << row.file << " is listed twice";
    EXPECT_TRUE(row.read_as == "cloud" || row.read_as == "mesh" || row.read_as == "tree") << row.file;
    EXPECT_FALSE(row.message.empty()) << row.file;
  }
  EXPECT_GE(listed.size(), 20u);
  for (const auto& entry : std::filesystem::directory_iterator(kBad)) {
    const std::string name = entry.path().filename().string();
    if (name == "expected.tsv" || name == "README.md") continue;
    EXPECT_TRUE(listed.count(name)) << name << " is not listed in expected.tsv";
  }
}

class HostileFileTest : public ::testing::TestWithParam<HostileFile> {};

TEST_P(HostileFileTest, IsRefusedQuicklyWithItsMessage) {
  const HostileFile& row = GetParam();
  const std::filesystem::path file = kBad / row.file;
  ASSERT_TRUE(std::filesystem::exists(file));
  const auto start = std::chrono::steady_clock::now();
  try {
    if (row.read_as == "tree")
      (void)load_tree(file);
    else if (row.read_as == "mesh")
      (void)read_triangle_mesh(file);
    else
      (void)read_point_cloud(file);
    FAIL() << row.file << " was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(row.message), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), file);
    EXPECT_TRUE(e.where().line || e.where().byte_offset || row.read_as != "tree") << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

INSTANTIATE_TEST_SUITE_P(Table, HostileFileTest, ::testing::ValuesIn(table()),
                         [](const ::testing::TestParamInfo<HostileFile>& info) {
                           std::string name = info.param.file;
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

}  // namespace
}  // namespace clustersurf
