// The PCD reader: ascii (three separators), binary and binary_compressed (LZF) files written
// here with normals, packed colors and attributes; PDAL's samples; hostile headers.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <gtest/gtest.h>
#include <lzf.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace clustersurf::test {
namespace {

PointCloud parse_pcd(const std::string& bytes) { return parse_point_cloud(bytes, FileFormat::Pcd, "t.pcd"); }

const std::string kHeader =
    "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z normal_x normal_y normal_z rgb intensity\n"
    "SIZE 4 4 8 4 4 4 4 2\nTYPE F F F F F F F U\nCOUNT 1 1 1 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\n"
    "VIEWPOINT 1 2 3 1 0 0 0\nPOINTS 3\n";

/// Three points with the header's fields, as packed little-endian records.
std::vector<char> records(bool field_major) {
  const float xy[3][2] = {{1, 2}, {4, 5}, {std::nanf(""), 0}};  // the third is PCL's "no point"
  const double z[3] = {3, 6, 0};
  const float n[3] = {0, 0, 1};
  const std::uint32_t rgb[3] = {0x00FF8001, 0x00000000, 0};
  const std::uint16_t intensity[3] = {7, 9, 0};
  std::vector<char> out;
  auto put = [&](const auto& v) {
    const char* p = reinterpret_cast<const char*>(&v);
    out.insert(out.end(), p, p + sizeof v);
  };
  if (!field_major) {
    for (int i = 0; i < 3; ++i) {
      put(xy[i][0]), put(xy[i][1]), put(z[i]), put(n[0]), put(n[1]), put(n[2]), put(rgb[i]), put(intensity[i]);
    }
  } else {
    for (int i = 0; i < 3; ++i) put(xy[i][0]);
    for (int i = 0; i < 3; ++i) put(xy[i][1]);
    for (int i = 0; i < 3; ++i) put(z[i]);
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) put(n[k]);
    for (int i = 0; i < 3; ++i) put(rgb[i]);
    for (int i = 0; i < 3; ++i) put(intensity[i]);
  }
  return out;
}

void expect_points(const PointCloud& c) {
  ASSERT_EQ(c.size(), 2);
  EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}, {4, 5, 6}})));
  EXPECT_TRUE(mat_eq(c.normals, rows({{0, 0, 1}, {0, 0, 1}})));
  EXPECT_EQ(c.colors.row(0), (Eigen::Matrix<std::uint8_t, 1, 3>(255, 128, 1)));
  ASSERT_EQ(c.attributes.size(), 1u);
  EXPECT_EQ(c.attributes[0].name, "intensity");
  EXPECT_EQ(c.attributes[0].values(1), 9);
  EXPECT_TRUE(mat_eq(c.scanner_positions, rows({{1, 2, 3}})));  // the viewpoint
}

std::string compressed_file() {
  const std::vector<char> raw = records(true);
  std::vector<char> packed(raw.size() * 2 + 16);
  const unsigned size =
      lzf_compress(raw.data(), static_cast<unsigned>(raw.size()), packed.data(), static_cast<unsigned>(packed.size()));
  EXPECT_GT(size, 0u);
  std::string bytes = kHeader + "DATA binary_compressed\n";
  const std::uint32_t sizes[2] = {size, static_cast<std::uint32_t>(raw.size())};
  bytes.append(reinterpret_cast<const char*>(sizes), 8);
  bytes.append(packed.data(), size);
  return bytes;
}

void expect_error(const std::string& bytes, const std::string& text) {
  try {
    parse_pcd(bytes);
    ADD_FAILURE() << "accepted; expected: " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    EXPECT_TRUE(e.where().line || e.where().byte_offset) << e.what();
  }
}

// A few header bytes may not make the reader allocate for a billion values: COUNTs adding up
// to more values than an ascii line can hold are refused, naming the DATA line; a binary file
// with such fields and no points costs nothing.
TEST(PcdReader, HugeCountsAreRefusedOrCostNothing) {
  const std::string header =
      "VERSION 0.7\nFIELDS x y z w\nSIZE 4 4 4 1\nTYPE F F F U\nCOUNT 1 1 1 1048576\nWIDTH 0\nHEIGHT 1\nPOINTS 0\n";
  try {
    parse_pcd(header + "DATA ascii\n");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, std::optional<std::uint64_t>(9)) << e.what();
    EXPECT_NE(std::string(e.what()).find("more than an ascii line can hold"), std::string::npos) << e.what();
  }
  try {
    parse_pcd(header + "DATA binary\n");  // no points: refused as empty, if at all, not for memory
  } catch (const InputError&) {}
}

TEST(PcdReader, BinaryAndCompressedRecords) {
  const std::vector<char> raw = records(false);
  expect_points(parse_pcd(kHeader + "DATA binary\n" + std::string(raw.begin(), raw.end())));
  expect_points(parse_pcd(compressed_file()));
}

/// `n` points with x y z normal_x normal_y normal_z rgb (floats but rgb), as a binary PCD file
/// or, compressed by liblzf, a binary_compressed one: slowly varying values and constant
/// normals, so that LZF's back references run within and across the fields' value runs.
std::string many_points(std::size_t n, bool compressed) {
  std::vector<std::vector<char>> fields(7);
  auto put = [](std::vector<char>& out, const auto& v) {
    const char* p = reinterpret_cast<const char*>(&v);
    out.insert(out.end(), p, p + sizeof v);
  };
  for (std::size_t i = 0; i < n; ++i) {
    put(fields[0], static_cast<float>(i % 1000) * 0.25f);
    put(fields[1], static_cast<float>(i / 1000));
    put(fields[2], std::sin(static_cast<float>(i) * 0.01f));
    put(fields[3], 0.0f), put(fields[4], 0.6f), put(fields[5], 0.8f);
    put(fields[6], static_cast<std::uint32_t>(i % 7 == 0 ? 0x00FF8001u : 0x00102030u));
  }
  std::string bytes =
      "VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z rgb\nSIZE 4 4 4 4 4 4 4\nTYPE F F F F F F U\n"
      "COUNT 1 1 1 1 1 1 1\nWIDTH " +
      std::to_string(n) + "\nHEIGHT 1\nPOINTS " + std::to_string(n) + "\n";
  if (!compressed) {
    bytes += "DATA binary\n";
    for (std::size_t i = 0; i < n; ++i)
      for (const auto& f : fields) bytes.append(f.data() + 4 * i, 4);
    return bytes;
  }
  std::vector<char> raw;
  for (const auto& f : fields) raw.insert(raw.end(), f.begin(), f.end());
  std::vector<char> packed(raw.size() + raw.size() / 16 + 64);
  const unsigned size =
      lzf_compress(raw.data(), static_cast<unsigned>(raw.size()), packed.data(), static_cast<unsigned>(packed.size()));
  EXPECT_GT(size, 0u);
  EXPECT_LT(size, raw.size() / 2);  // the runs compress: the test exercises back references
  bytes += "DATA binary_compressed\n";
  const std::uint32_t sizes[2] = {size, static_cast<std::uint32_t>(raw.size())};
  bytes.append(reinterpret_cast<const char*>(sizes), 8);
  bytes.append(packed.data(), size);
  return bytes;
}

// The LZF decoder, one resumable decoder per field, against liblzf's compressor: a compressed
// file of 30 k points reads exactly as the same points stored uncompressed.
TEST(PcdReader, CompressedFileIsTheSameCloudAsBinary) {
  const PointCloud binary = parse_pcd(many_points(30000, false));
  const PointCloud compressed = parse_pcd(many_points(30000, true));
  ASSERT_EQ(binary.size(), 30000);
  EXPECT_EQ(compressed.positions, binary.positions);
  EXPECT_EQ(compressed.normals, binary.normals);
  EXPECT_EQ(compressed.colors, binary.colors);
}

// LZF written by hand: 256 literal runs of 32 bytes, then a back reference from as far back as
// LZF reaches (8192 bytes: ((31 << 8) + 255) + 1) copying 4 bytes, so the last z is the first x.
TEST(PcdReader, CompressedBackReferenceFromTheFarthestByte) {
  std::vector<float> values(2048);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 1 + 0.25f * static_cast<float>(i);
  std::string packed;
  const char* raw = reinterpret_cast<const char*>(values.data());
  for (int run = 0; run < 256; ++run) packed.push_back(31), packed.append(raw + 32 * run, 32);
  packed.push_back(static_cast<char>((2 << 5) | 31)), packed.push_back(static_cast<char>(0xFF));
  std::string bytes =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 683\nHEIGHT 1\nPOINTS 683\n"
      "DATA binary_compressed\n";
  const std::uint32_t sizes[2] = {static_cast<std::uint32_t>(packed.size()), 683 * 12};
  bytes.append(reinterpret_cast<const char*>(sizes), 8).append(packed);
  const PointCloud c = parse_pcd(bytes);
  ASSERT_EQ(c.size(), 683);
  const Eigen::RowVector3d origin = c.origin.transpose();
  EXPECT_EQ(c.positions(0, 0) + origin(0), 1.0);
  EXPECT_EQ(c.positions(682, 1) + origin(1), values[1365]);
  EXPECT_EQ(c.positions(681, 2) + origin(2), values[2047]);
  EXPECT_EQ(c.positions(682, 2) + origin(2), 1.0);  // copied from 8192 bytes back
  // The same reference after one run less (8160 bytes behind it) reaches before the data's
  // start: refused.
  std::string too_far = packed.substr(33, 33 * 255);  // runs 1..255, each a control byte and 32 bytes
  too_far.push_back(static_cast<char>(0xFF)), too_far.push_back(27),
      too_far.push_back(static_cast<char>(0xFF));  // 36 bytes
  std::string refused =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 683\nHEIGHT 1\nPOINTS 683\n"
      "DATA binary_compressed\n";
  const std::uint32_t refused_sizes[2] = {static_cast<std::uint32_t>(too_far.size()), 683 * 12};
  refused.append(reinterpret_cast<const char*>(refused_sizes), 8).append(too_far);
  expect_error(refused, "before its start");
}

TEST(PcdReader, AsciiWithAnySeparator) {
  const std::string header =
      "VERSION .7\nFIELDS x y z rgb intensity\nSIZE 4 4 4 4 4\nTYPE F F F U F\nCOUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT "
      "1\nPOINTS 2\nDATA ascii\n";
  for (const char* sep : {" ", "\t", ","}) {
    const std::string s(sep);
    const PointCloud c = parse_pcd(header + "1" + s + "2" + s + "3" + s + "16744449" + s + "0.5\n4" + s + "5" + s +
                                   "6" + s + "0" + s + "nan\n");
    ASSERT_EQ(c.size(), 2);
    EXPECT_TRUE(mat_eq(c.positions, rows({{1, 2, 3}, {4, 5, 6}})));
    EXPECT_EQ(c.colors.row(0), (Eigen::Matrix<std::uint8_t, 1, 3>(255, 128, 1)));
    EXPECT_FALSE(c.has_scanners());  // the default viewpoint of an unorganized cloud says nothing
  }
}

TEST(PcdReader, HostileFiles) {
  const std::vector<char> raw = records(false);
  const std::string binary = kHeader + "DATA binary\n" + std::string(raw.begin(), raw.end());
  expect_error(binary.substr(0, binary.size() - 5), "more than the rest of the file can hold");
  std::string compressed = compressed_file();
  const std::size_t sizes_at = compressed.find("binary_compressed\n") + 18;
  {
    std::string b = compressed;
    const std::uint32_t huge = 0x7FFFFFFF;
    std::memcpy(b.data() + sizes_at, &huge, 4);
    expect_error(b, "runs past the end of the file");
  }
  {
    std::string b = compressed;
    const std::uint32_t wrong = 12;
    std::memcpy(b.data() + sizes_at + 4, &wrong, 4);
    expect_error(b, "is not POINTS x record size");
  }
  {
    std::string b = compressed;
    b[sizes_at + 8] = static_cast<char>(0xFF);  // a back reference before the start
    b[sizes_at + 9] = static_cast<char>(0xFF);
    expect_error(b, "LZF data is corrupt");
  }
  {
    // Compressed data cut short, or running on past the declared size, each with its offset.
    std::string b = many_points(2000, true);
    const std::size_t at = b.find("binary_compressed\n") + 18;
    std::uint32_t packed = 0;
    std::memcpy(&packed, b.data() + at, 4);
    const std::uint32_t shorter = packed / 2;
    std::memcpy(b.data() + at, &shorter, 4);
    expect_error(b, "LZF data is corrupt");
    std::string longer = many_points(2000, true);
    longer.append(4, '\0');  // two more 1-byte literal runs than declared
    const std::uint32_t grown = packed + 4;
    std::memcpy(longer.data() + at, &grown, 4);
    expect_error(longer, "goes on past the declared");
  }
  std::string many = kHeader;
  many.replace(many.find("WIDTH 3"), 7, "WIDTH 300000000");
  many.replace(many.find("POINTS 3"), 8, "POINTS 300000000");
  expect_error(many + "DATA binary\n", "more than the rest of the file can hold");
  expect_error("VERSION .7\nFIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 0\nPOINTS 0\nDATA ascii\n",
               "FIELDS name no x, y and z");
  expect_error("VERSION .7\nFIELDS x y z\nSIZE 4 4\n", "SIZE needs 3 value(s)");
  expect_error("VERSION .7\nFIELDS x y z\nSIZE 4 4 3\n", "SIZE must be 1, 2, 4 or 8 bytes");
  expect_error("VERSION .7\nFIELDS x y z\nTYPE F F Q\n", "TYPE must be F, I or U");
  expect_error("VERSION .7\nFIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nWIDTH 1\nDATA binary\n123456",
               "is a float of 2 bytes");
  expect_error("VERSION .7\nFIELDS x y z\nWIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n",
               "POINTS (3) is not WIDTH x HEIGHT");
  expect_error("VERSION .7\nFIELDS x y z\nWIDTH 1\nDATA lzma\n", "DATA must be ascii, binary or binary_compressed");
  expect_error("VERSION .7\nFIELDS x y z\nWIDTH 2\nDATA ascii\n1 2 3\n", "file ends after 1 of 2 points");
  expect_error("VERSION .7\nFIELDS x y z\nWIDTH 1\nDATA ascii\n1 2\n", "expected 3 values, found 2");
  expect_error("VERSION .7\nFIELDS x y z\nWIDTH 1\n", "header ends before its DATA line");
  expect_error("1 2 3\n", "expected the PCD header");
}

TEST(PcdReader, PdalSamples) {
  const auto dir = shared_data("formats/pcd");
  if (!dir) GTEST_SKIP() << "the shared PCD samples (formats/pcd) are not here";
  const PointCloud space = read_point_cloud(*dir / "utm17_space.pcd");
  EXPECT_EQ(space.size(), 10);
  for (const char* name : {"utm17_tab.pcd", "utm17_comma.pcd"}) {
    const PointCloud c = read_point_cloud(*dir / name);
    EXPECT_TRUE(same_bits(c.positions, space.positions)) << name;
    EXPECT_EQ(c.origin, space.origin) << name;
  }
  EXPECT_NEAR(space.positions(0, 0) + space.origin.x(), 289814.15, 0.02);  // float fields
  // PDAL's binary export of the LAS sample: the same points, 16-bit colors, intensity and
  // classification.
  const PointCloud autzen = read_point_cloud(*dir / "autzen-utm.pcd");
  EXPECT_EQ(autzen.size(), 1065);
  EXPECT_TRUE(autzen.has_colors());
  EXPECT_EQ(autzen.attributes.size(), 2u);
  EXPECT_THROW(read_point_cloud(*dir / "missingheader.pcd"), InputError);
}

}  // namespace
}  // namespace clustersurf::test
