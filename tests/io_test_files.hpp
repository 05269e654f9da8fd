#pragma once
// Helpers of the reader and writer tests: exact comparisons, awkward values, hand-made PLY
// headers and binary records, and reading bytes through a temporary file.

#include "test_support.hpp"

#include <clustersurf/point_cloud_io.hpp>

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
    return ::testing::AssertionFailure() << "size " << a.rows() << "x" << a.cols() << " vs " << b.rows() << "x" << b.cols();
  if (a != b) return ::testing::AssertionFailure() << "\n" << a.template cast<double>() << "\nvs\n" << b.template cast<double>();
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
