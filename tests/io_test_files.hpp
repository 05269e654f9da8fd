#pragma once
// Helpers of the reader and writer tests: exact comparisons, awkward values, hand-made PLY
// headers and binary records, hand-made LAS files, and reading bytes through a temporary file.

#include "test_support.hpp"

#include <clustersurf/io/point_cloud_io.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <initializer_list>
#include <string>

namespace clustersurf::test {

/// Bit-exact comparison (distinguishes -0.0 from 0.0 and compares NaN payloads).
::testing::AssertionResult same_bits(const Points& a, const Points& b);

/// Exact equality of two matrices, sizes first (Eigen's == requires equal sizes).
template <class A, class B>
::testing::AssertionResult mat_eq(const A& a, const B& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    return ::testing::AssertionFailure() << "size " << a.rows() << "x" << a.cols() << " vs " << b.rows() << "x"
                                         << b.cols();
  if (a != b)
    return ::testing::AssertionFailure() << "\n" << a.template cast<double>() << "\nvs\n" << b.template cast<double>();
  return ::testing::AssertionSuccess();
}

/// A cloud whose values need every bit of a double: random, tiny, huge, negative zero.
PointCloud awkward_cloud(int n, bool normals, bool colors, unsigned seed = 3);

/// Little- or big-endian byte builder for binary PLY data.
struct Bytes {
  bool big = false;
  std::string s;

  template <class T>
  Bytes& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
    return *this;
  }
  /// Appends `v` converted to the PLY scalar type `type`.
  Bytes& put_as(std::string type, double v);
  Bytes& floats(std::initializer_list<float> v) {
    for (float f : v) put(f);
    return *this;
  }
};

/// A LAS file built byte by byte: the 1.4 header (375 bytes), no VLRs, then `records`.
struct LasFile {
  std::string bytes;

  LasFile(unsigned format, std::uint16_t record_length, std::uint64_t count, Eigen::Vector3d scale = {0.01, 0.01, 0.01},
          Eigen::Vector3d offset = {1000, 2000, 0}) {
    bytes.assign(375, '\0');
    std::memcpy(bytes.data(), "LASF", 4);
    bytes[24] = 1, bytes[25] = 4;
    poke<std::uint16_t>(94, 375);
    poke<std::uint32_t>(96, 375);
    bytes[104] = static_cast<char>(format);
    poke<std::uint16_t>(105, record_length);
    poke<std::uint32_t>(107, static_cast<std::uint32_t>(count));
    for (int k = 0; k < 3; ++k) poke<double>(131 + 8 * static_cast<std::size_t>(k), scale(k));
    for (int k = 0; k < 3; ++k) poke<double>(155 + 8 * static_cast<std::size_t>(k), offset(k));
    poke<std::uint64_t>(247, count);
  }
  template <class T>
  void poke(std::size_t at, T v) {
    std::memcpy(bytes.data() + at, &v, sizeof v);
  }
  /// Appends one record of `length` bytes: integer coordinates, intensity, and the bytes `set`
  /// (offset, value) on top.
  void record(std::uint16_t length, std::int32_t x, std::int32_t y, std::int32_t z, std::uint16_t intensity,
              std::initializer_list<std::pair<std::size_t, std::uint16_t>> set16 = {},
              std::initializer_list<std::pair<std::size_t, std::uint8_t>> set8 = {}) {
    std::string r(length, '\0');
    std::memcpy(r.data(), &x, 4), std::memcpy(r.data() + 4, &y, 4), std::memcpy(r.data() + 8, &z, 4);
    std::memcpy(r.data() + 12, &intensity, 2);
    for (auto [at, v] : set16) std::memcpy(r.data() + at, &v, 2);
    for (auto [at, v] : set8) r[at] = static_cast<char>(v);
    bytes += r;
  }
};

/// "ply", the format line, `body`, "end_header".
std::string ply_header(const std::string& format, const std::string& body);
/// The x, y, z float properties.
inline const std::string kXyzFloat = "property float x\nproperty float y\nproperty float z\n";

/// `bytes` written to dir/name and read back as a cloud (or a mesh).
PointCloud read_text(const TempDir& dir, const std::string& name, const std::string& bytes, const ReadOptions& o = {});
TriangleMesh read_mesh_text(const TempDir& dir, const std::string& name, const std::string& bytes);

/// Points from rows written inline.
Points rows(std::initializer_list<std::array<double, 3>> r);

}  // namespace clustersurf::test
