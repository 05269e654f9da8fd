// The E57 reader: the real samples of the shared data folder (skipped, saying why, when absent),
// files written here by the small E57 writer of e57_writer.hpp (bit-packed ScaledIntegers,
// spherical coordinates, poses, packets and values straddling pages) and a hostile table (each
// refused with an InputError naming the file and the byte offset of the problem).

#include "e57_writer.hpp"
#include "io_test_files.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf {
namespace {

using namespace clustersurf::test;

PointCloud parse(const std::string& bytes, const ReadOptions& o = {}) {
  return parse_point_cloud(bytes, FileFormat::E57, "test.e57", o);
}

/// Positions in the file's coordinates (the dispatcher moves far clouds next to zero).
Points file_positions(const PointCloud& c) { return c.positions.rowwise() + c.origin.transpose(); }

const float* intensity_of(const PointCloud& c) {
  for (const auto& a : c.attributes)
    if (a.name == "intensity") return a.values.data();
  return nullptr;
}

// ---- the real samples ---------------------------------------------------------------------

std::optional<PointCloud> sample(const std::string& name) {
  const auto file = shared_data("formats/e57/" + name);
  if (!file) return std::nullopt;
  return read_point_cloud(*file);
}
#define SAMPLE(var, name)        \
  const auto var = sample(name); \
  if (!var) GTEST_SKIP() << "shared data formats/e57/" name " is absent"

void expect_box(const PointCloud& c, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const BoundingBox b = bounding_box(file_positions(c));
  EXPECT_TRUE(b.min.isApprox(lo, 1e-12)) << b.min.transpose();
  EXPECT_TRUE(b.max.isApprox(hi, 1e-12)) << b.max.transpose();
}

TEST(E57Reader, A4MatchesPdalsExpectations) {
  SAMPLE(c, "A4.e57");
  ASSERT_EQ(c->size(), 4);
  const Points p = file_positions(*c);
  EXPECT_FLOAT_EQ(static_cast<float>(p(0, 0)), -44.300098f);  // PDAL's E57ReaderTest
  EXPECT_FLOAT_EQ(static_cast<float>(p(0, 1)), -1.132100f);
  EXPECT_FLOAT_EQ(static_cast<float>(p(0, 2)), 0.335800f);
  EXPECT_FLOAT_EQ(static_cast<float>(p(1, 0)), -44.506901f);
  EXPECT_FLOAT_EQ(static_cast<float>(p(1, 1)), -0.886000f);
  EXPECT_FLOAT_EQ(static_cast<float>(p(1, 2)), 0.328600f);
  ASSERT_TRUE(c->has_colors());
  EXPECT_EQ(c->colors(0, 0), 0);
  EXPECT_EQ(c->colors(0, 1), 255);
  EXPECT_EQ(c->colors(0, 2), 0);
  ASSERT_NE(intensity_of(*c), nullptr);
  EXPECT_EQ(intensity_of(*c)[0], 0.0f);
  EXPECT_FALSE(c->has_scanners());  // no pose: the file does not say where the scanner was
  // The bounds the file's XML states (cartesianBounds, the floats printed in full).
  expect_box(*c, {-4.49522018432617188e+01, -1.34930002689361572e+00, -6.07699990272521973e-01},
             {-4.43000984191894531e+01, -8.85999977588653564e-01, 3.69399994611740112e-01});
}

TEST(E57Reader, B2) {
  SAMPLE(c, "B2.e57");
  ASSERT_EQ(c->size(), 2);
  EXPECT_TRUE(c->has_colors());
  expect_box(*c, {-4.26422996520996094e+01, 1.87259995937347412e+00, 5.10100007057189941e-01},
             {-4.26394996643066406e+01, 2.05780005455017090e+00, 6.66700005531311035e-01});
}

TEST(E57Reader, TwoScansAreConcatenatedInOrder) {
  SAMPLE(ab, "A_B.e57");
  SAMPLE(a, "A4.e57");
  SAMPLE(b, "B2.e57");
  SAMPLE(merged, "A_merged_B.e57");
  ASSERT_EQ(ab->size(), 6);
  const Points p = file_positions(*ab);
  EXPECT_TRUE(mat_eq(Points(p.topRows(2)), file_positions(*b)));
  EXPECT_TRUE(mat_eq(Points(p.bottomRows(4)), file_positions(*a)));
  EXPECT_TRUE(mat_eq(ab->colors.topRows(2), b->colors));
  EXPECT_TRUE(mat_eq(ab->colors.bottomRows(4), a->colors));
  EXPECT_TRUE(mat_eq(file_positions(*merged), p));  // one scan holding both
  // Intensity mapped to 0..1 by each scan's own intensityLimits (0..0.873 and 0..257.9).
  const float* in = intensity_of(*ab);
  ASSERT_NE(in, nullptr);
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(in[i] >= 0.0f && in[i] <= 1.0f) << in[i];
  EXPECT_FLOAT_EQ(in[1], 1.0f);  // B2's second point is at its maximum (0.873046875)
  EXPECT_FALSE(ab->has_scanners());
}

TEST(E57Reader, MovedFilesAreTheSameScanMovedRigidly) {
  SAMPLE(a, "A4.e57");
  SAMPLE(moved, "A4_moved.e57");
  SAMPLE(amb, "A_moved_B.e57");
  SAMPLE(b, "B2.e57");
  // The "moved" samples carry no pose: their points were moved before writing (as floats).
  const Points pa = file_positions(*a), pm = file_positions(*moved);
  ASSERT_EQ(pm.rows(), 4);
  const Eigen::RowVector3d shift = pm.row(0) - pa.row(0);
  EXPECT_GT(shift.norm(), 1.0);
  for (Eigen::Index i = 0; i < 4; ++i) EXPECT_LT((pm.row(i) - pa.row(i) - shift).norm(), 1e-5) << i;
  ASSERT_EQ(amb->size(), 6);
  const Points p = file_positions(*amb);
  EXPECT_TRUE(mat_eq(Points(p.topRows(2)), file_positions(*b)));
  EXPECT_LT((Points(p.bottomRows(4)) - pm).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(E57Reader, ScansWithDifferentFieldsKeepOnlyWhatAllHave) {
  SAMPLE(c, "A_B_different_dims.e57");
  ASSERT_EQ(c->size(), 2);
  EXPECT_FALSE(c->has_colors());         // the first scan has none
  EXPECT_EQ(intensity_of(*c), nullptr);  // the second scan has none
  const Points p = file_positions(*c);
  EXPECT_FLOAT_EQ(static_cast<float>(p(0, 0)), 8.4174026e+01f);
  EXPECT_FLOAT_EQ(static_cast<float>(p(1, 1)), 5.3846844e+02f);
}

// ---- files written here -------------------------------------------------------------------

TEST(E57Reader, BitPackedScaledIntegersAcrossPacketsAndPages) {
  const int n = 1000;
  std::vector<std::int64_t> x, y, z, r, g, b, in, row, state;
  for (int i = 0; i < n; ++i) {
    x.push_back(-4000 + (i * 37) % 8001);
    y.push_back(4000 - (i * 91) % 8001);
    z.push_back((i * i) % 8001 - 4000);
    r.push_back(i % 1024), g.push_back((i * 3) % 1024), b.push_back(1023 - i % 1024);
    in.push_back((i * 7) % 4096);
    row.push_back(i);
    state.push_back(i % 10 == 3 ? 2 : i % 10 == 7 ? 1 : 0);
  }
  const std::string scale = "scale=\"0.001\" offset=\"10\"";
  TestScan scan{
      {int_field("cartesianX", -4000, 4000, x, scale), int_field("rowIndex", 0, 999, row),
       int_field("cartesianY", -4000, 4000, y, scale), int_field("cartesianZ", -4000, 4000, z, scale),
       int_field("colorRed", 0, 1023, r), int_field("colorGreen", 0, 1023, g), int_field("colorBlue", 0, 1023, b),
       int_field("intensity", 0, 4095, in), int_field("cartesianInvalidState", 0, 2, state)},
      "<intensityLimits type=\"Structure\"><intensityMinimum type=\"Integer\"/>"
      "<intensityMaximum type=\"Integer\">4095</intensityMaximum></intensityLimits>"};
  ASSERT_EQ(scan.fields[0].bits, 13U);
  // Small pages and 7-byte buffers: values straddle packets, packets straddle pages.
  WriteOptions o;
  o.page = 64;
  o.chunk = 7;
  o.extra_packets = true;
  const TestFile f = write_e57({scan}, o);
  const PointCloud c = parse(f.bytes);
  ASSERT_EQ(c.size(), 800);
  ASSERT_TRUE(c.has_colors());
  const float* intensity = intensity_of(c);
  ASSERT_NE(intensity, nullptr);
  const Points p = file_positions(c);
  Eigen::Index k = 0;
  for (int i = 0; i < n; ++i) {
    if (state[static_cast<std::size_t>(i)] != 0) continue;
    EXPECT_DOUBLE_EQ(p(k, 0), static_cast<double>(x[static_cast<std::size_t>(i)]) * 0.001 + 10);
    EXPECT_DOUBLE_EQ(p(k, 1), static_cast<double>(y[static_cast<std::size_t>(i)]) * 0.001 + 10);
    EXPECT_DOUBLE_EQ(p(k, 2), static_cast<double>(z[static_cast<std::size_t>(i)]) * 0.001 + 10);
    EXPECT_EQ(c.colors(k, 0), std::lround(static_cast<double>(r[static_cast<std::size_t>(i)]) * 255.0 / 1023.0));
    EXPECT_EQ(c.colors(k, 2), std::lround(static_cast<double>(b[static_cast<std::size_t>(i)]) * 255.0 / 1023.0));
    EXPECT_FLOAT_EQ(intensity[k], static_cast<float>(static_cast<double>(in[static_cast<std::size_t>(i)]) / 4095.0));
    ++k;
    if (HasFailure()) break;
  }
}

TEST(E57Reader, ConstantIntegerFieldHasNoBits) {
  TestScan scan{{float_field("cartesianX", {1, 2, 3}), float_field("cartesianY", {4, 5, 6}),
                 int_field("cartesianZ", 7, 7, {7, 7, 7})}};
  ASSERT_EQ(scan.fields[2].bits, 0U);
  const PointCloud c = parse(write_e57({scan}).bytes);
  EXPECT_TRUE(mat_eq(c.positions, rows({{1, 4, 7}, {2, 5, 7}, {3, 6, 7}})));
  EXPECT_FALSE(c.has_colors());
  EXPECT_TRUE(c.attributes.empty());
}

TEST(E57Reader, SphericalCoordinatesWithInvalidStates) {
  const std::vector<double> range = {1, 2, 3, 4}, az = {0, std::numbers::pi / 2, 1.0, 2.0},
                            el = {0, 0, std::numbers::pi / 2, -0.5};
  TestScan scan{{float_field("sphericalRange", range), float_field("sphericalAzimuth", az),
                 float_field("sphericalElevation", el), int_field("sphericalInvalidState", 0, 2, {0, 0, 1, 0})}};
  const PointCloud c = parse(write_e57({scan}).bytes);
  ASSERT_EQ(c.size(), 3);
  const Points expect =
      rows({{1, 0, 0},
            {0, 2, 0},
            {4 * std::cos(-0.5) * std::cos(2.0), 4 * std::cos(-0.5) * std::sin(2.0), 4 * std::sin(-0.5)}});
  EXPECT_LT((file_positions(c) - expect).cwiseAbs().maxCoeff(), 1e-12);
  // Spherical data is centred on its scanner: the origin of the scan's frame (no pose: 0).
  ASSERT_TRUE(c.has_scanners());
  EXPECT_TRUE(mat_eq(c.scanner_positions, rows({{0, 0, 0}})));
}

std::string pose_xml(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
  char s[512];
  std::snprintf(
      s, sizeof s,
      "<pose type=\"Structure\"><rotation type=\"Structure\"><w type=\"Float\">%.17g</w><x type=\"Float\">%.17g</x>"
      "<y type=\"Float\">%.17g</y><z type=\"Float\">%.17g</z></rotation><translation type=\"Structure\">"
      "<x type=\"Float\">%.17g</x><y type=\"Float\">%.17g</y><z type=\"Float\">%.17g</z></translation></pose>",
      q.w(), q.x(), q.y(), q.z(), t.x(), t.y(), t.z());
  return s;
}

TEST(E57Reader, PosesAreAppliedAndGiveScannerPositions) {
  const std::vector<double> xs = {1.5, -2.25, 3}, ys = {0.5, 4, -1}, zs = {2, 0, 0.125};
  const Eigen::Quaterniond q1 = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d t1(10, -20, 5), t2(-3, 4, 1.5);
  const auto fields = [&] {
    return std::vector<TestField>{float_field("cartesianX", xs), float_field("cartesianY", ys),
                                  float_field("cartesianZ", zs)};
  };
  const TestScan unposed{fields()};
  const TestScan a{fields(), pose_xml(q1, t1)};
  const TestScan b{fields(),
                   "<pose type=\"Structure\"><translation type=\"Structure\"><x type=\"Float\">-3</x>"
                   "<y type=\"Float\">4</y><z type=\"Float\">1.5</z></translation></pose>"};
  const PointCloud plain = parse(write_e57({unposed}).bytes);
  const PointCloud c = parse(write_e57({a, b}).bytes);
  ASSERT_EQ(c.size(), 6);
  const Points p = file_positions(c), local = file_positions(plain);
  for (Eigen::Index i = 0; i < 3; ++i) {
    const Eigen::Vector3d l = local.row(i).transpose();
    EXPECT_LT((p.row(i).transpose() - (q1 * l + t1)).norm(), 1e-9) << i;
    EXPECT_LT((p.row(i + 3).transpose() - (l + t2)).norm(), 1e-9) << i;
  }
  ASSERT_TRUE(c.has_scanners());
  ASSERT_EQ(c.scanner_positions.rows(), 2);
  EXPECT_LT((c.scanner_positions.row(0) + c.origin.transpose() - t1.transpose()).norm(), 1e-9);
  EXPECT_LT((c.scanner_positions.row(1) + c.origin.transpose() - t2.transpose()).norm(), 1e-9);
  EXPECT_EQ(c.scanner_of_point, (std::vector<std::uint32_t>{0, 0, 0, 1, 1, 1}));
  // One scan without a pose: no scan gets a scanner position.
  EXPECT_FALSE(parse(write_e57({a, unposed}).bytes).has_scanners());
}

// ---- the hostile table --------------------------------------------------------------------

/// Four points and a long description, so that the XML spans pages 0 to 2.
TestFile small_file() {
  return write_e57({TestScan{{float_field("cartesianX", {1, 2, 3, 4}), float_field("cartesianY", {5, 6, 7, 8}),
                              float_field("cartesianZ", {9, 10, 11, 12}), int_field("colorRed", 0, 255, {1, 2, 3, 4})},
                             "<description type=\"String\"><![CDATA[" + std::string(1500, 'd') + "]]></description>"}});
}

struct Hostile {
  std::string name;
  std::string bytes;
  std::string message;                // part of what()
  std::optional<std::uint64_t> byte;  // the byte offset it must name
};
std::ostream& operator<<(std::ostream& os, const Hostile& h) { return os << h.name; }

std::vector<Hostile> hostile_table() {
  std::vector<Hostile> t;
  const TestFile ok = small_file();
  const auto patched = [&](std::uint64_t at, std::uint64_t v, int bytes) {
    std::string s = ok.bytes;
    put_le(s, at, v, bytes);
    refresh_crcs(s);
    return s;
  };
  t.push_back({"truncated header", ok.bytes.substr(0, 40), "shorter than the 48-byte E57 header", 0});
  t.push_back({"truncated", ok.bytes.substr(0, 1024), "header says the file is", 16});
  t.push_back({"filePhysicalLength wrong", patched(16, 4096, 8), "header says the file is 4096 bytes", 16});
  t.push_back({"page size not a power of two", patched(40, 1000, 8), "page size 1000", 40});
  t.push_back({"major version", patched(8, 2, 4), "major version 2", 8});
  std::string bad_crc = ok.bytes;
  bad_crc[1500] ^= 1;
  t.push_back({"bad page CRC", bad_crc, "page 1 (bytes 1024 to 2047) fails its CRC-32C check", 1024});
  t.push_back({"xml offset past the end", patched(24, 1 << 20, 8), "xmlPhysicalOffset 1048576 is past the end", 24});
  t.push_back({"xml offset on a CRC", patched(24, 1022, 8), "points into a page's CRC", 24});
  t.push_back({"xml length past the end", patched(32, 1ULL << 40, 8), "reaches past the end of the file", 32});
  t.push_back({"section id", patched(ok.sections[0], 7, 1), "section id is 7", ok.sections[0]});
  t.push_back({"section length", patched(ok.sections[0] + 8, 1ULL << 62, 8), "section length", ok.sections[0] + 8});
  t.push_back({"data offset outside", patched(ok.sections[0] + 16, 2, 8), "dataPhysicalOffset is outside",
               ok.sections[0] + 16});
  t.push_back({"packet length past the section", patched(ok.packets[0] + 2, 0xFFFF, 2),
               "packet of 65536 bytes reaches past", ok.packets[0]});
  t.push_back({"bytestream count", patched(ok.packets[0] + 4, 9, 2), "has 9 bytestreams", ok.packets[0] + 4});
  t.push_back({"buffer lengths past the packet", patched(ok.packets[0] + 6, 0xFFFF, 2), "do not fit in the",
               ok.packets[0] + 6});
  t.push_back({"unknown packet type", patched(ok.packets[0], 9, 1), "unknown packet type 9", ok.packets[0]});
  const auto scan = [](const std::string& extra_field, std::optional<std::string> count = std::nullopt) {
    TestScan s{
        {float_field("cartesianX", {1, 2}), float_field("cartesianY", {3, 4}), float_field("cartesianZ", {5, 6})}};
    if (!extra_field.empty()) s.fields.push_back({extra_field, 0, {0, 0}});
    s.record_count = std::move(count);
    return s;
  };
  t.push_back({"absurd recordCount",
               write_e57({scan("", "1000000000000")}).bytes,
               "recordCount 1000000000000 is more than",
               {}});
  t.push_back({"recordCount not a number", write_e57({scan("", "12x")}).bytes, "recordCount=\"12x\"", {}});
  WriteOptions slack;  // the empty and index packets leave room for a third record
  slack.extra_packets = true;
  t.push_back(
      {"more records than data", write_e57({scan("", "3")}, slack).bytes, "section ends before all 3 records", {}});
  t.push_back(
      {"unknown field type", write_e57({scan("<colorRed type=\"Blob\"/>")}).bytes, "unsupported type \"Blob\"", {}});
  t.push_back({"bad precision",
               write_e57({scan("<intensity type=\"Float\" precision=\"half\"/>")}).bytes,
               "precision \"half\"",
               {}});
  t.push_back({"maximum below minimum",
               write_e57({scan("<colorRed type=\"Integer\" minimum=\"5\" maximum=\"1\"/>")}).bytes,
               "maximum below minimum",
               {}});
  TestScan no_xyz{{float_field("cartesianX", {1}), float_field("cartesianY", {2})}};
  t.push_back({"no coordinates", write_e57({no_xyz}).bytes, "neither cartesianX/Y/Z nor spherical", {}});
  TestScan zero_q = scan("");
  zero_q.extra = pose_xml(Eigen::Quaterniond(0, 0, 0, 0), Eigen::Vector3d::Zero());
  t.push_back({"zero quaternion", write_e57({zero_q}).bytes, "not a valid quaternion", {}});
  std::string broken = ok.bytes;
  const std::size_t close = broken.find("</data3D>");
  broken.replace(close, 9, "</data3X>");
  refresh_crcs(broken);
  t.push_back({"malformed XML", broken, "XML section is not well-formed", {}});
  return t;
}

class E57Hostile : public ::testing::TestWithParam<Hostile> {};

TEST_P(E57Hostile, RefusedWithByteOffset) {
  const Hostile& h = GetParam();
  try {
    parse_point_cloud(h.bytes, FileFormat::E57, "hostile.e57");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("hostile.e57"), std::string::npos) << what;
    EXPECT_NE(what.find(h.message), std::string::npos) << what;
    ASSERT_TRUE(e.where().byte_offset.has_value()) << what;  // every E57 error names a byte
    if (h.byte) {
      EXPECT_EQ(*e.where().byte_offset, *h.byte) << what;
    }
  }
}
INSTANTIATE_TEST_SUITE_P(Table, E57Hostile, ::testing::ValuesIn(hostile_table()), [](const auto& info) {
  std::string s = info.param.name;
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
});

TEST(E57Reader, NanCoordinateIsRefusedNamingItsByte) {
  const TestFile f =
      write_e57({TestScan{{float_field("cartesianX", {1, std::nan(""), 3}), float_field("cartesianY", {4, 5, 6}),
                           float_field("cartesianZ", {7, 8, 9})}}});
  try {
    parse(f.bytes);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    // cartesianX's buffer starts after the 6-byte packet header and 3 buffer lengths; the NaN
    // is its second double.
    EXPECT_EQ(e.where().byte_offset, f.packets[0] + 12 + 8) << e.what();
    EXPECT_NE(std::string(e.what()).find("byte"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
  }
  ReadOptions drop;
  drop.drop_non_finite = true;
  EXPECT_TRUE(mat_eq(parse(f.bytes, drop).positions, rows({{1, 4, 7}, {3, 6, 9}})));
}

TEST(E57Reader, DeeplyNestedXmlIsHarmless) {
  WriteOptions o;
  for (int i = 0; i < 100000; ++i) o.xml_tail += "<a>";
  for (int i = 0; i < 100000; ++i) o.xml_tail += "</a>";
  const PointCloud c = parse(write_e57({TestScan{{float_field("cartesianX", {1}), float_field("cartesianY", {2}),
                                                  float_field("cartesianZ", {3})}}},
                                       o)
                                 .bytes);
  EXPECT_EQ(c.size(), 1);
}

TEST(E57Reader, EveryByteFlipIsAnInputErrorOrAValidCloud) {
  // Flipping any byte of a small file (CRCs refreshed, so the flip reaches the content)
  // either still parses or throws InputError; nothing else escapes.
  const TestFile ok = small_file();
  for (std::size_t i = 0; i < ok.bytes.size(); ++i) {
    if (i % 1024 >= 1020) continue;
    std::string s = ok.bytes;
    s[i] = static_cast<char>(s[i] ^ 0x5A);
    refresh_crcs(s);
    try {
      const PointCloud c = parse(s);
      EXPECT_GT(c.size(), 0);
    } catch (const InputError&) {}
  }
}

}  // namespace
}  // namespace clustersurf
