// Malformed files in every format: a table of cases, each refused with its error family, the
// exact line or byte it names and what was expected; absurd counts fail before allocating;
// endless lines stop at the limit; non-finite values are dropped only on request; random
// corruptions only ever throw InputError.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace clustersurf {
namespace {

using namespace clustersurf::test;

enum class Expect { Input, Io };
enum class Kind { File, Directory, Missing };

struct BadFile {
  std::string label;
  std::string name;  // file name (its extension picks the format)
  std::string bytes;
  Expect type = Expect::Input;
  std::string message;  // expected substring of what()
  std::optional<std::uint64_t> line = std::nullopt;
  std::optional<std::uint64_t> byte = std::nullopt;
  bool mesh = false;  // read with read_triangle_mesh instead of read_point_cloud
  Kind kind = Kind::File;
};

std::ostream& operator<<(std::ostream& os, const BadFile& f) { return os << f.label; }

const std::string kAsciiXyzHeader = ply_header("ascii", "element vertex 2\n" + kXyzFloat);  // 7 lines
const std::string kBinXyzHeader = ply_header("binary_little_endian", "element vertex 4\n" + kXyzFloat);

std::string binary_cloud_with_nan() {
  Bytes b;
  b.floats({1, 2, 3, 4, 5, 6, 7, std::numeric_limits<float>::quiet_NaN(), 9, 10, 11, 12});
  return kBinXyzHeader + b.s;
}

std::vector<BadFile> bad_files() {
  std::vector<BadFile> t;
  const std::uint64_t bin_data = kBinXyzHeader.size();
  // Generic
  t.push_back({"empty file", "empty.ply", "", Expect::Input, "file is empty"});
  t.push_back({"unknown extension", "points.abc", "1 2 3\n", Expect::Input, "unknown file format \".abc\""});
  t.push_back({"directory", "folder.ply", "", Expect::Io, "is a directory", {}, {}, false, Kind::Directory});
  t.push_back({"missing file", "missing.ply", "", Expect::Io, "cannot open", {}, {}, false, Kind::Missing});
  t.push_back(
      {"zero vertices", "zero.ply", ply_header("ascii", "element vertex 0\n" + kXyzFloat), Expect::Input, "no points"});
  t.push_back({"xyz of comments only", "c.xyz", "# nothing\n\n", Expect::Input, "no points"});
  // PLY header
  t.push_back({"not ply", "text.ply", "hello\n1 2 3\n", Expect::Input, "not a PLY file", 1});
  t.push_back({"no end_header", "noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",
               Expect::Input, "no \"end_header\"", 5});
  t.push_back({"header cut mid-line", "cut.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty flo", Expect::Input,
               "no \"end_header\"", 4});
  t.push_back({"unknown format", "fmt.ply", ply_header("binary_middle_endian", "element vertex 1\n" + kXyzFloat),
               Expect::Input, "unknown PLY format \"binary_middle_endian\"", 2});
  t.push_back(
      {"format without version", "fmt2.ply", "ply\nformat ascii\nend_header\n", Expect::Input, "expected \"format", 2});
  t.push_back({"unsupported version", "ver.ply", "ply\nformat ascii 2.0\nend_header\n", Expect::Input,
               "unsupported PLY version \"2.0\"", 2});
  t.push_back({"no format line", "nofmt.ply", "ply\nelement vertex 1\n" + kXyzFloat + "end_header\n1 2 3\n",
               Expect::Input, "no \"format\" line", 2});
  t.push_back(
      {"unknown scalar type", "type.ply",
       ply_header("ascii", "element vertex 1\nproperty float x\nproperty float128 y\nproperty float z\n") + "1 2 3\n",
       Expect::Input, "unknown scalar type \"float128\"", 5});
  t.push_back({"float list count", "list.ply",
               ply_header("ascii", "element vertex 1\n" + kXyzFloat + "element face 1\nproperty list float int v\n"),
               Expect::Input, "list count type must be an integer", 8});
  t.push_back({"property before element", "prop.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n",
               Expect::Input, "property before any element", 3});
  t.push_back({"negative count", "neg.ply", "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", Expect::Input,
               "non-negative count", 3});
  t.push_back({"junk header line", "junk.ply", "ply\nformat ascii 1.0\nelement vertex 1\nhello there\nend_header\n",
               Expect::Input, "unexpected PLY header line \"hello there\"", 4});
  t.push_back({"vertex without z", "noz.ply",
               ply_header("ascii", "element vertex 1\nproperty float x\nproperty float y\n") + "1 2\n", Expect::Input,
               "lacks one of the properties x, y, z", 3});
  t.push_back({"no vertex element", "novert.ply", ply_header("ascii", "element point 1\n" + kXyzFloat) + "1 2 3\n",
               Expect::Input, "no \"vertex\" element", 1});
  // Binary data
  t.push_back({"truncated binary vertices", "trunc.ply", kBinXyzHeader + std::string(12 * 3 + 6, '\0'), Expect::Input,
               "file ends inside vertex 3 of 4", std::nullopt, bin_data + 36});
  {
    Bytes b;
    b.floats({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    b.put<std::uint8_t>(1).put<std::int32_t>(0).put<std::uint8_t>(0).put<std::uint8_t>(1).put<std::int32_t>(1);
    t.push_back({"truncated binary list element", "grid.ply",
                 ply_header("binary_little_endian",
                            "element vertex 4\n" + kXyzFloat + "element range_grid 5\nproperty list uchar int v\n") +
                     b.s,
                 Expect::Input, "file ends inside range_grid 3 of 5", std::nullopt,
                 ply_header("binary_little_endian",
                            "element vertex 4\n" + kXyzFloat + "element range_grid 5\nproperty list uchar int v\n")
                         .size() +
                     48 + 11});
    Bytes c;
    c.floats({1, 2, 3}).put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1);  // list cut short
    const std::string h = ply_header("binary_little_endian",
                                     "element vertex 1\nproperty float x\nproperty float y\n"
                                     "property float z\nelement face 1\n"
                                     "property list uchar int vertex_indices\n");
    t.push_back({"truncated binary list", "list.ply", h + c.s, Expect::Input, "file ends inside face 0 of 1",
                 std::nullopt, h.size() + 13});
  }
  t.push_back({"bytes after the last element", "extra.ply", kBinXyzHeader + std::string(12 * 4, '\0') + "JUNK",
               Expect::Input, "4 unexpected bytes after the last element", std::nullopt, bin_data + 48});
  t.push_back({"binary NaN", "nan.ply", binary_cloud_with_nan(), Expect::Input, "point 2 (0-based) has a non-finite",
               std::nullopt, bin_data + 24});
  {
    const std::string h = ply_header("binary_little_endian", "element vertex 50000000000\n" + kXyzFloat);
    t.push_back({"absurd vertex count, binary", "huge.ply", h + std::string(36, '\0'), Expect::Input,
                 "file ends inside vertex 3 of 50000000000 (the header (line 3) claims 50000000000 vertex records",
                 std::nullopt, h.size() + 36});
    t.push_back({"absurd vertex count, ascii", "hugea.ply",
                 ply_header("ascii", "element vertex 50000000000\n" + kXyzFloat) + "1 2 3\n", Expect::Input,
                 "claims 50000000000 vertex records", 9});
    t.push_back({"absurd count after lists", "hugel.ply",
                 ply_header("binary_little_endian", "element vertex 1\n" + kXyzFloat +
                                                        "element range_grid 1\nproperty list uchar int v\n"
                                                        "element junk 3000000000\nproperty double d\n") +
                     std::string(12 + 1, '\0'),
                 Expect::Input, "claims 3000000000 junk records", std::nullopt,
                 ply_header("binary_little_endian", "element vertex 1\n" + kXyzFloat +
                                                        "element range_grid 1\nproperty list uchar int v\n"
                                                        "element junk 3000000000\nproperty double d\n")
                         .size() +
                     13});
  }
  {
    Bytes b;
    b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}).put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1);
    b.put<std::int32_t>(2).put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(-1).put<std::int32_t>(2);
    const std::string h =
        ply_header("binary_little_endian",
                   "element vertex 3\n" + kXyzFloat + "element face 2\nproperty list uchar int vertex_indices\n");
    t.push_back({"binary face index out of range", "face.ply", h + b.s, Expect::Input,
                 "face refers to vertex -1 but there are 3 vertices", std::nullopt, h.size() + 36 + 13, true});
  }
  // Ascii data (the header of kAsciiXyzHeader is 7 lines: data starts on line 8)
  t.push_back({"truncated ascii, short records", "ta.ply",
               ply_header("ascii", "element vertex 3\n" + kXyzFloat) + "1 2 3\n4 5 6\n", Expect::Input,
               "file ends too early", 10});
  t.push_back({"truncated ascii inside a record", "tb.ply", kAsciiXyzHeader + "1.5 2.5 3.5\n4.5 5.5\n", Expect::Input,
               "file ends inside vertex 1 of 2 (property z)", 10});
  t.push_back({"too many ascii records", "tm.ply", kAsciiXyzHeader + "1 2 3\n4 5 6\n\n\n7 8 9\n", Expect::Input,
               "unexpected data \"7\" after the last element", 12});
  t.push_back({"extra ascii value on the last line", "tv.ply", kAsciiXyzHeader + "1 2 3\n4 5 6 7\n", Expect::Input,
               "unexpected data \"7\" after the last element", 9});
  t.push_back({"non-numeric token", "nn.ply", kAsciiXyzHeader + "1 2 3\n4 5 six\n", Expect::Input,
               "expected a number for property \"z\" of vertex 1 of 2, found \"six\"", 9});
  t.push_back({"sign after plus", "pm.ply", kAsciiXyzHeader + "1 2 3\n4 +-5 6\n", Expect::Input, "found \"+-5\"", 9});
  t.push_back({"non-integer in an integer property", "ni.ply",
               ply_header("ascii", "element vertex 1\n" + kXyzFloat + "property uchar red\n") + "1 2 3 4.5\n",
               Expect::Input, "expected an integer for property \"red\"", 9});
  t.push_back({"ascii NaN", "nan.ply", kAsciiXyzHeader + "1 2 3\nnan 0 0\n", Expect::Input,
               "point 1 (0-based) has a non-finite coordinate", 9});
  t.push_back({"ascii Inf normal", "infn.ply",
               ply_header("ascii", "element vertex 2\n" + kXyzFloat +
                                       "property float nx\nproperty float ny\nproperty float nz\n") +
                   "1 2 3 0 0 1\n4 5 6 0 -inf 0\n",
               Expect::Input, "point 1 (0-based) has a non-finite coordinate or normal", 12});
  t.push_back({"ascii face index out of range", "face.ply",
               ply_header("ascii", "element vertex 3\n" + kXyzFloat +
                                       "element face 2\nproperty list uchar int vertex_indices\n") +
                   "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 3\n",
               Expect::Input, "face refers to vertex 3 but there are 3 vertices", 14, std::nullopt, true});
  for (const char* index : {"1e300", "-1e19"}) {
    t.push_back({std::string("ascii face index ") + index, "hugeface.ply",
                 ply_header("ascii", "element vertex 3\n" + kXyzFloat +
                                         "element face 1\nproperty list uchar int vertex_indices\n") +
                     "0 0 0\n1 0 0\n0 1 0\n3 0 1 " + index + "\n",
                 Expect::Input, std::string("face refers to vertex ") + index + " but there are 3 vertices", 13,
                 std::nullopt, true});
  }
  t.push_back({"ascii face index inf", "infface.ply",
               ply_header("ascii", "element vertex 3\n" + kXyzFloat +
                                       "element face 1\nproperty list uchar int vertex_indices\n") +
                   "0 0 0\n1 0 0\n0 1 0\n3 0 1 inf\n",
               Expect::Input, "expected an integer for property \"vertex_indices\" of face 0 of 1, found \"inf\"", 13,
               std::nullopt, true});
  t.push_back({"non-finite mesh vertex", "nanmesh.ply",
               ply_header("ascii", "element vertex 3\n" + kXyzFloat +
                                       "element face 1\nproperty list uchar int vertex_indices\n") +
                   "0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n",
               Expect::Input, "non-finite", 11, std::nullopt, true});
  // XYZ / PTS
  t.push_back({"xyz inconsistent columns", "ic.xyz", "# header\n1 2 3\n4 5 6\n7 8 9 0 0 1\n", Expect::Input,
               "expected 3 values as on line 2, found 6", 4});
  t.push_back({"xyz five columns", "five.xyz", "\n1 2 3 4 5\n", Expect::Input, "found 5", 2});
  t.push_back({"xyz non-numeric", "nn.xyz", "1 2 3\n4 5 6e\n", Expect::Input, "expected a number in column 3", 2});
  t.push_back(
      {"xyz Inf", "inf.xyz", "1 2 3\n4 inf 6\n7 8 9\n", Expect::Input, "point 1 (0-based) has a non-finite", 2});
  t.push_back({"xyz NaN normal", "nan.xyz", "1 2 3 0 0 1\n4 5 6 nan 0 0\n", Expect::Input, "non-finite", 2});
  t.push_back({"pts count mismatch", "c.pts", "3\n1 2 3 0 1 2 3\n4 5 6 0 1 2 3\n", Expect::Input,
               "the count line says 3 points but the file has 2", 1});
  t.push_back(
      {"pts bad count line", "b.pts", "many\n1 2 3\n", Expect::Input, "expected \"x y z\" or a point count", 1});
  t.push_back({"xyz as mesh", "m.xyz", "1 2 3\n", Expect::Input, "cannot read a mesh from a XYZ file", std::nullopt,
               std::nullopt, true});
  // OBJ
  t.push_back({"obj undefined vertex", "u.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", Expect::Input,
               "face refers to vertex 3 but only 2 are defined before it", 3, std::nullopt, true});
  t.push_back({"obj negative index too far back", "n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", Expect::Input,
               "face refers to vertex -4", 4, std::nullopt, true});
  t.push_back({"obj index zero", "z.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", Expect::Input,
               "expected a vertex index, found \"0\"", 4, std::nullopt, true});
  t.push_back({"obj short face", "s.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", Expect::Input, "at least 3 vertices", 3,
               std::nullopt, true});
  t.push_back({"obj bad vertex", "v.obj", "v 0 0 0\nv 1 0\n", Expect::Input, "found 2 values", 2});
  t.push_back({"obj NaN vertex", "nan.obj", "v 0 0 0\n# c\nv 1 nan 0\n", Expect::Input, "non-finite", 3});
  t.push_back({"obj Inf normal", "infn.obj", "v 0 0 0\nv 1 1 0\nvn 0 0 1\nvn inf 0 0\n", Expect::Input,
               "point 1 (0-based) has a non-finite", 4});
  return t;
}

class MalformedFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(MalformedFile, FailsWithTypeMessageAndLocation) {
  const BadFile& f = GetParam();
  TempDir dir;
  const auto file = dir / f.name;
  if (f.kind == Kind::File) write_file(file, f.bytes);
  if (f.kind == Kind::Directory) std::filesystem::create_directory(file);
  auto read = [&] {
    if (f.mesh)
      (void)read_triangle_mesh(file);
    else
      (void)read_point_cloud(file);
  };
  try {
    read();
    FAIL() << "no exception for " << f.label;
  } catch (const InputError& e) {
    ASSERT_EQ(f.type, Expect::Input) << "got InputError: " << e.what();
    EXPECT_NE(std::string(e.what()).find(f.message), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos)
        << "message must name the file: " << e.what();
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(e.where().line, f.line) << e.what();
    EXPECT_EQ(e.where().byte_offset, f.byte) << e.what();
    if (f.line) {
      EXPECT_NE(std::string(e.what()).find(file.string() + ":" + std::to_string(*f.line) + ": "), std::string::npos);
    }
    if (f.byte) {
      EXPECT_NE(std::string(e.what()).find(": byte " + std::to_string(*f.byte) + ": "), std::string::npos);
    }
  } catch (const IoError& e) {
    ASSERT_EQ(f.type, Expect::Io) << "got IoError: " << e.what();
    EXPECT_NE(std::string(e.what()).find(f.message), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Table, MalformedFile, ::testing::ValuesIn(bad_files()),
                         [](const ::testing::TestParamInfo<BadFile>& info) {
                           std::string name = std::to_string(info.index) + "_" + info.param.label;
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

TEST(MalformedFileExtra, AbsurdCountFailsFastWithoutAllocating) {
  TempDir dir;
  const std::string h = ply_header("binary_little_endian", "element vertex 50000000000\n" + kXyzFloat);
  write_file(dir / "huge.ply", h + std::string(36, '\0'));
  const auto start = std::chrono::steady_clock::now();
  try {
    (void)read_point_cloud(dir / "huge.ply");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("50000000000"), std::string::npos) << e.what();
  }
  // 50e9 points would take 1.2 TB: reaching the check at all proves nothing was allocated
  // (std::bad_alloc otherwise); it must also be immediate.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST(MalformedFileExtra, EmptyOutputNameAndUnwritableTarget) {
  const PointCloud c = awkward_cloud(3, false, false);
  EXPECT_THROW(write_ply("", c), IoError);
}

/// A file that is one endless line (the "5 GB line") is refused once the line passes 1 MiB,
/// with the line's number, whatever the format; the bytes after the limit are never looked at
/// (here: 64 MiB of them, read in far less time than a scan would take under the sanitizers).
TEST(MalformedFileExtra, EndlessLineIsRefusedAtTheLimit) {
  constexpr std::size_t kLimit = std::size_t{1} << 20;
  const std::string endless(64 * kLimit, '7');
  const std::string spaces(2 * kLimit, ' ');
  struct Case {
    std::string name, bytes;
    std::uint64_t line;
  };
  const std::vector<Case> cases = {
      {"digits.xyz", "1 2 3\n" + endless, 2},
      {"comment.xyz", "1 2 3\n#" + endless + "\n4 5 6\n", 2},
      {"spaces.xyz", "1 2 3\n" + spaces + "4 5 6\n", 2},
      {"vertex.obj", "v 0 0 0\nv 1 " + endless, 2},
      {"header.ply", "ply\nformat ascii 1.0\ncomment " + endless + "\nend_header\n", 3},
      {"token.ply", kAsciiXyzHeader + "1 2 3\n4 5 " + endless, 9},
      {"blank.ply", kAsciiXyzHeader + "1 2 3\n4 5" + spaces + "6\n", 9},
  };
  TempDir dir;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    write_file(dir / c.name, c.bytes);
    const auto start = std::chrono::steady_clock::now();
    try {
      (void)read_point_cloud(dir / c.name);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(e.message().find("line is longer than 1048576 bytes"), std::string::npos) << e.what();
      EXPECT_EQ(e.where().line, c.line) << e.what();
    }
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  }
  // A line just under the limit is fine.
  write_file(dir / "long.xyz", "1 2 3 # " + std::string(kLimit - 9, 'x') + "\n4 5 6\n");
  EXPECT_EQ(read_point_cloud(dir / "long.xyz").size(), 2);
}

/// The files with non-finite values of the table, read with drop_non_finite: they load without
/// the bad points and the warning reports the count.
TEST(NonFinite, DroppedOnRequestWithAWarning) {
  struct Case {
    std::string name, bytes;
    Eigen::Index kept;
    std::string count;  // "dropped K of N"
  };
  const std::vector<Case> cases = {
      {"nan.ply", kAsciiXyzHeader + "1 2 3\nnan 0 0\n", 1, "dropped 1 of 2"},
      {"inf.ply", ply_header("ascii", "element vertex 3\n" + kXyzFloat) + "inf 2 3\n4 5 6\n7 -inf nan\n", 1,
       "dropped 2 of 3"},
      {"nanb.ply", binary_cloud_with_nan(), 3, "dropped 1 of 4"},
      {"inf.xyz", "1 2 3\n4 inf 6\n7 8 9\n", 2, "dropped 1 of 3"},
      {"nan.xyz", "1 2 3 0 0 1\n4 5 6 nan 0 0\n", 1, "dropped 1 of 2"},
      {"nan.obj", "v 0 0 0\n# c\nv 1 nan 0\n", 1, "dropped 1 of 2"},
  };
  TempDir dir;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    write_file(dir / c.name, c.bytes);
    EXPECT_THROW((void)read_point_cloud(dir / c.name), InputError);
    std::vector<std::string> warnings;
    ReadOptions o;
    o.drop_non_finite = true;
    o.warn = [&](const std::string& w) { warnings.push_back(w); };
    const PointCloud r = read_point_cloud(dir / c.name, o);
    EXPECT_EQ(r.size(), c.kept);
    EXPECT_TRUE(r.positions.allFinite());
    if (r.has_normals()) {
      EXPECT_EQ(r.normals.rows(), c.kept);
      EXPECT_TRUE(r.normals.allFinite());
    }
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(c.count), std::string::npos) << warnings[0];
    // Without a callback the warning is silently ignored.
    ReadOptions quiet;
    quiet.drop_non_finite = true;
    EXPECT_EQ(read_point_cloud(dir / c.name, quiet).size(), c.kept);
  }
  // Kept points keep their attributes in order.
  write_file(dir / "attr.ply", ply_header("ascii", "element vertex 3\n" + kXyzFloat +
                                                       "property uchar red\nproperty "
                                                       "uchar green\nproperty uchar blue\n") +
                                   "1 1 1 10 11 12\nnan 2 2 20 21 22\n3 3 3 30 31 32\n");
  ReadOptions o;
  o.drop_non_finite = true;
  const PointCloud r = read_point_cloud(dir / "attr.ply", o);
  EXPECT_TRUE(mat_eq(r.positions, rows({{1, 1, 1}, {3, 3, 3}})));
  ASSERT_TRUE(r.has_colors());
  EXPECT_EQ(r.colors(1, 0), 30);
  EXPECT_EQ(r.colors(1, 2), 32);
  // Every point dropped: no points left.
  write_file(dir / "all.xyz", "nan 0 0\n");
  EXPECT_THROW((void)read_point_cloud(dir / "all.xyz", o), InputError);
}

/// Random corruptions of valid files (byte changes, truncations, insertions): every read either
/// succeeds or throws InputError; never a crash, a hang or another exception type.
TEST(MalformedFileExtra, RandomCorruptionsOnlyEverThrowInputError) {
  TempDir dir;
  Bytes bin;
  bin.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  bin.put<std::uint8_t>(4).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2).put<std::int32_t>(3);
  bin.put<std::uint8_t>(3).put<std::int32_t>(3).put<std::int32_t>(2).put<std::int32_t>(1);
  const std::vector<std::pair<std::string, std::string>> seeds = {
      {"a.ply", ply_header("ascii", "element vertex 4\n" + kXyzFloat +
                                        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                        "element face 2\nproperty list uchar int vertex_indices\n") +
                    "0 0 0 1 2 3\n1 0 0 4 5 6\n1 1 0 7 8 9\n0 1 0 10 11 12\n4 0 1 2 3\n3 3 2 1\n"},
      {"b.ply", ply_header("binary_little_endian", "element vertex 4\n" + kXyzFloat +
                                                       "element face 2\nproperty list uchar int vertex_indices\n") +
                    bin.s},
      {"c.xyz", "3\n1 2 3 0 0 1\n4 5 6 0 1 0\n7 8 9 1 0 0\n"},
      {"d.obj",
       "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1//1 2//2 3//3\nf -1 -2 -3\n"},
  };
  const std::string alphabet = "0123456789 -+.\n\r\t#,/eEnaifvxyz\xff\x80";
  std::mt19937_64 rng(2024);
  int ok = 0, rejected = 0;
  for (const auto& [name, original] : seeds) {
    for (int trial = 0; trial < 1000; ++trial) {
      std::string bytes = original;
      const int edits = 1 + static_cast<int>(rng() % 3);
      for (int e = 0; e < edits && !bytes.empty(); ++e) {
        const std::size_t at = rng() % bytes.size();
        switch (rng() % 5) {
          case 0:
            bytes[at] = static_cast<char>(rng() % 256);
            break;
          case 1:
            bytes[at] = alphabet[rng() % alphabet.size()];
            break;
          case 2:
            bytes.resize(at);
            break;
          case 3:
            bytes.insert(at, 1, alphabet[rng() % alphabet.size()]);
            break;
          default:
            bytes.erase(at, 1 + rng() % 4);
            break;
        }
      }
      // A new file each time: rewriting one in place (O_TRUNC) makes ext4 flush it on close.
      std::filesystem::remove(dir / name);
      write_file(dir / name, bytes);
      for (bool mesh : {false, true}) {
        if (mesh && name == "c.xyz") continue;
        try {
          if (mesh) {
            const TriangleMesh m = read_triangle_mesh(dir / name);
            if (m.triangles.size() != 0) {
              EXPECT_GE(m.triangles.minCoeff(), 0);
              EXPECT_LT(m.triangles.maxCoeff(), m.vertices.rows());
            }
          } else {
            (void)read_point_cloud(dir / name);
          }
          ++ok;
        } catch (const InputError&) {
          ++rejected;
        } catch (const std::exception& e) {
          ADD_FAILURE() << name << " trial " << trial << ": unexpected exception " << e.what();
        }
      }
    }
  }
  EXPECT_GT(ok, 100);
  EXPECT_GT(rejected, 100);
}

}  // namespace
}  // namespace clustersurf
