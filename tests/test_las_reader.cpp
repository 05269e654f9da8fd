// The LAS reader: PDAL's real samples (every legacy point format, 1.4 format 6, extra bytes,
// broken headers), LAS 1.4 formats 7-10 written here, and hostile headers.

#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>

namespace clustersurf::test {
namespace {

PointCloud parse_las(const std::string& bytes) { return parse_point_cloud(bytes, FileFormat::Las, "t.las"); }

const PointAttribute& attribute(const PointCloud& c, const std::string& name) {
  for (const PointAttribute& a : c.attributes)
    if (a.name == name) return a;
  throw std::runtime_error("no attribute " + name);
}

/// Expects an InputError whose message contains `text` and names a byte offset.
void expect_error(const std::string& bytes, const std::string& text) {
  try {
    parse_las(bytes);
    ADD_FAILURE() << "accepted; expected: " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    EXPECT_TRUE(e.where().byte_offset.has_value()) << e.what();
  }
}

std::string file_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The header's bounding box (max x at 179, min x at 187, ...), read independently.
BoundingBox header_bounds(const std::string& b) {
  BoundingBox box;
  for (int k = 0; k < 3; ++k) {
    std::memcpy(&box.max(k), b.data() + 179 + 16 * k, 8);
    std::memcpy(&box.min(k), b.data() + 187 + 16 * k, 8);
  }
  return box;
}

TEST(LasReader, Formats7To10WithScaleOffsetColorsAndAttributes) {
  for (unsigned format : {7u, 8u, 10u}) {
    const std::uint16_t length = format == 7 ? 36 : format == 8 ? 38 : 67;
    LasFile f(format, length + 3, 2);  // three extra bytes per record, skipped
    f.record(length + 3, 100, -200, 5, 7, {{30, 65535}, {32, 0}, {34, 32896}}, {{16, 200}});
    f.record(length + 3, -1, 2, 3, 9, {{30, 257}, {32, 514}, {34, 771}}, {{16, 2}});
    const PointCloud c = parse_las(f.bytes);
    ASSERT_EQ(c.size(), 2) << format;
    // Far from zero for its size: moved next to it, exactly.
    const Points file = c.positions.rowwise() + c.origin.transpose();
    EXPECT_EQ(file(0, 0), 100 * 0.01 + 1000);
    EXPECT_EQ(file(0, 1), -200 * 0.01 + 2000);
    EXPECT_EQ(file(1, 2), 3 * 0.01);
    ASSERT_TRUE(c.has_colors());
    EXPECT_EQ(c.colors.row(0), (Eigen::Matrix<std::uint8_t, 1, 3>(255, 0, 128)));  // 16-bit scaled
    EXPECT_EQ(c.colors.row(1), (Eigen::Matrix<std::uint8_t, 1, 3>(1, 2, 3)));
    EXPECT_EQ(attribute(c, "intensity").values(1), 9);
    EXPECT_EQ(attribute(c, "classification").values(0), 200);  // the whole byte in formats 6-10
  }
  LasFile six(6, 30, 1);
  six.record(30, 1, 2, 3, 4);
  EXPECT_FALSE(parse_las(six.bytes).has_colors());
}

// A format with color fields that the file left 0 in every record (no camera on the survey)
// has no colors; one lit channel anywhere gives them all.
TEST(LasReader, ColorFieldsLeftEmptyAreNoColors) {
  for (const bool lit : {false, true}) {
    LasFile f(7, 36, 3);
    for (std::int32_t i = 0; i < 3; ++i)
      f.record(36, i, 2 * i, 3 * i, 5, {{32, lit && i == 2 ? std::uint16_t{200} : std::uint16_t{0}}});
    const PointCloud c = parse_las(f.bytes);
    ASSERT_EQ(c.has_colors(), lit);
    if (lit) {
      EXPECT_EQ(c.colors(2, 1), 200);  // 8-bit values in the 16-bit fields
    }
  }
}

TEST(LasReader, HostileHeadersAreRefusedBeforeAllocating) {
  LasFile good(6, 30, 1);
  good.record(30, 1, 2, 3, 4);
  ASSERT_EQ(parse_las(good.bytes).size(), 1);
  expect_error(good.bytes.substr(0, 200), "header is truncated");
  {
    LasFile f = good;
    f.bytes[104] = static_cast<char>(0x80 | 6);
    expect_error(f.bytes, "LAZ is not supported");
  }
  {
    LasFile f = good;
    f.bytes[104] = 11;
    expect_error(f.bytes, "unknown LAS point data record format 11");
  }
  {
    LasFile f = good;
    f.poke<std::uint64_t>(247, 4'000'000'000'000ULL);
    f.poke<std::uint32_t>(107, 0);
    expect_error(f.bytes, "declares 4000000000000 points");
  }
  {
    LasFile f = good;
    f.poke<std::uint64_t>(247, 2);
    expect_error(f.bytes, "contradicts the legacy count");
  }
  {
    LasFile f = good;
    f.poke<std::uint16_t>(105, 20);
    expect_error(f.bytes, "shorter than point format 6 needs (30)");
  }
  {
    LasFile f = good;
    f.poke<std::uint32_t>(100, 1);  // one VLR that cannot fit before the points
    expect_error(f.bytes, "VLR count is wrong");
  }
  {
    LasFile f = good;
    f.poke<std::uint64_t>(235, 1'000'000);  // an EVLR past the end of the file
    f.poke<std::uint32_t>(243, 1);
    expect_error(f.bytes, "starts past the end of the file");
  }
  {
    LasFile f = good;
    f.poke<double>(131, 0.0);
    expect_error(f.bytes, "scale factors must be finite and non-zero");
  }
  {
    LasFile f = good;
    f.bytes[25] = 9;
    expect_error(f.bytes, "unsupported LAS version 1.9");
  }
}

TEST(LasReader, PdalSamples) {
  const auto dir = shared_data("formats/las");
  if (!dir) GTEST_SKIP() << "the shared LAS samples (formats/las) are not here";
  const PointCloud simple = read_point_cloud(*dir / "simple.las");
  EXPECT_EQ(simple.size(), 1065);
  EXPECT_TRUE(simple.has_colors());
  // Projected coordinates: moved next to zero, and back at the header's bounds with the origin.
  EXPECT_GT(simple.origin.norm(), 1e5);
  const BoundingBox header = header_bounds(file_bytes(*dir / "simple.las"));
  const BoundingBox read = bounding_box(Points(simple.positions.rowwise() + simple.origin.transpose()));
  EXPECT_LT((read.min - header.min).cwiseAbs().maxCoeff(), 0.005);
  EXPECT_LT((read.max - header.max).cwiseAbs().maxCoeff(), 0.005);
  // The same points with extra bytes per record (LAS 1.4), as a 1.2 file.
  const PointCloud extra = read_point_cloud(*dir / "extrabytes.las");
  EXPECT_TRUE(same_bits(extra.positions, simple.positions));
  EXPECT_EQ(extra.origin, simple.origin);
  const PointCloud color = read_point_cloud(*dir / "1.2-with-color.las");
  EXPECT_TRUE(mat_eq(color.colors, simple.colors));
  EXPECT_GT(attribute(simple, "intensity").values.maxCoeff(), 0);
  EXPECT_EQ(read_point_cloud(*dir / "4_6_crop.las").size(), 23875);
  const PointCloud autzen = read_point_cloud(*dir / "autzen_trim.las");
  EXPECT_EQ(autzen.size(), 110000);
  EXPECT_NEAR(autzen.origin.x(), 636590, 600);
  EXPECT_LT(autzen.positions.cwiseAbs().maxCoeff(), 700);
  EXPECT_EQ(read_point_cloud(*dir / "test1_4.las").size(), 1000);
  for (const char* name :
       {"permutation_1.0_0.las", "permutation_1.0_1.las", "permutation_1.1_0.las", "permutation_1.1_1.las",
        "permutation_1.2_0.las", "permutation_1.2_1.las", "permutation_1.2_2.las", "permutation_1.2_3.las"}) {
    const PointCloud one = read_point_cloud(*dir / name);
    EXPECT_EQ(one.size(), 1) << name;
    const char format = name[std::strlen(name) - 5];
    EXPECT_EQ(one.has_colors(), format == '2' || format == '3') << name;
  }
}

TEST(LasReader, PdalBrokenSamplesGiveClearErrors) {
  const auto dir = shared_data("formats/las");
  if (!dir) GTEST_SKIP() << "the shared LAS samples (formats/las) are not here";
  const std::pair<const char*, const char*> cases[] = {
      {"bad_vlr_count.las", "VLR count is wrong"},
      {"garbage_nVariableLength.las", "VLR count is wrong"},
      {"permutation_1.2-no-points.las", "declares 1065 points of 34 bytes from byte 229"},
      {"no-points.las", "holds no points"},
  };
  for (const auto& [name, text] : cases) {
    try {
      read_point_cloud(*dir / name);
      ADD_FAILURE() << name << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace clustersurf::test
