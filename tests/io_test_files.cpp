// Helpers of the reader and writer tests (io_test_files.hpp).

#include "io_test_files.hpp"

#include <bit>
#include <cmath>
#include <limits>
#include <map>
#include <random>

namespace clustersurf::test {

::testing::AssertionResult same_bits(const Points& a, const Points& b) {
  if (a.rows() != b.rows()) return ::testing::AssertionFailure() << "rows " << a.rows() << " != " << b.rows();
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (int c = 0; c < 3; ++c)
      if (std::bit_cast<std::uint64_t>(a(i, c)) != std::bit_cast<std::uint64_t>(b(i, c)))
        return ::testing::AssertionFailure() << "(" << i << ", " << c << "): " << a(i, c) << " vs " << b(i, c);
  return ::testing::AssertionSuccess();
}

PointCloud awkward_cloud(int n, bool normals, bool colors, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::uniform_int_distribution<int> byte(0, 255);
  PointCloud c;
  c.positions.resize(n, 3);
  for (int i = 0; i < n; ++i) c.positions.row(i) << u(rng), u(rng) * 1e-3, u(rng) * 1e5;
  if (n >= 4) {
    c.positions.row(0) << 0.1, 1.0 / 3.0, -0.0;
    c.positions.row(1) << 1e-300, -1e300, 5e-324;  // includes a denormal
    c.positions.row(2) << 123456789.123456789, -2.5, 0.0;
    c.positions.row(3) << std::nextafter(1.0, 2.0), std::nextafter(1.0, 0.0), -std::numeric_limits<double>::max();
  }
  if (normals) {
    c.normals.resize(n, 3);
    for (int i = 0; i < n; ++i) {
      Eigen::Vector3d v(u(rng), u(rng), u(rng));
      c.normals.row(i) = v.normalized().transpose();
    }
  }
  if (colors) {
    c.colors.resize(n, 3);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) c.colors(i, k) = static_cast<std::uint8_t>(byte(rng));
  }
  return c;
}

Bytes& Bytes::put_as(std::string type, double v) {
  static const std::map<std::string, std::string> alias = {
      {"int8", "char"}, {"uint8", "uchar"}, {"int16", "short"},   {"uint16", "ushort"},
      {"int32", "int"}, {"uint32", "uint"}, {"float32", "float"}, {"float64", "double"}};
  if (const auto it = alias.find(type); it != alias.end()) type = it->second;
  if (type == "char") return put(static_cast<std::int8_t>(v));
  if (type == "uchar") return put(static_cast<std::uint8_t>(v));
  if (type == "short") return put(static_cast<std::int16_t>(v));
  if (type == "ushort") return put(static_cast<std::uint16_t>(v));
  if (type == "int") return put(static_cast<std::int32_t>(v));
  if (type == "uint") return put(static_cast<std::uint32_t>(v));
  if (type == "float") return put(static_cast<float>(v));
  if (type == "double") return put(v);
  ADD_FAILURE() << "unknown type " << type;
  return *this;
}

std::string ply_header(const std::string& format, const std::string& body) {
  return "ply\nformat " + format + " 1.0\n" + body + "end_header\n";
}

PointCloud read_text(const TempDir& dir, const std::string& name, const std::string& bytes, const ReadOptions& o) {
  write_file(dir / name, bytes);
  return read_point_cloud(dir / name, o);
}
TriangleMesh read_mesh_text(const TempDir& dir, const std::string& name, const std::string& bytes) {
  write_file(dir / name, bytes);
  return read_triangle_mesh(dir / name);
}

Points rows(std::initializer_list<std::array<double, 3>> r) {
  Points p(static_cast<Eigen::Index>(r.size()), 3);
  Eigen::Index i = 0;
  for (const auto& row : r) p.row(i++) << row[0], row[1], row[2];
  return p;
}

}  // namespace clustersurf::test
