#include "test_support.hpp"

#include <clustersurf/evaluation/range_scan.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <unistd.h>
#include <utility>
#include <vector>

namespace clustersurf::test {

TempDir::TempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "clustersurf-test-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

void write_file(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string read_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::optional<std::filesystem::path> shared_data(const std::string& relative) {
  const char* env = std::getenv("CLUSTERSURF_SHARED_DATA");
  const std::filesystem::path root = env != nullptr ? env : CLUSTERSURF_SHARED_DATA;
  const auto file = root / relative;
  if (std::filesystem::exists(file)) return file;
  return std::nullopt;
}

std::optional<std::filesystem::path> default_bunny() {
  const auto file = std::filesystem::path(CLUSTERSURF_DEFAULT_DATA) / "bunny.ply";
  if (std::filesystem::exists(file)) return file;
  return std::nullopt;
}

PointCloud sample_sphere(int n, double radius, const Eigen::Vector3d& center) {
  PointCloud c;
  c.positions.resize(n, 3);
  c.normals.resize(n, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n;
    const double r = std::sqrt(1.0 - z * z);
    const Eigen::Vector3d u(r * std::cos(golden * i), r * std::sin(golden * i), z);
    c.normals.row(i) = u.transpose();
    c.positions.row(i) = (center + radius * u).transpose();
  }
  return c;
}

PointCloud sparse_scan(const TriangleMesh& mesh, std::uint64_t seed) {
  RangeScanOptions scan;
  scan.scans = 10;
  scan.count = 3000;
  scan.noise = 0.0005;
  scan.registration = 0.0002;
  scan.seed = seed;
  return scan_surface(mesh, scan);
}

PointCloud sample_torus(int n, double R, double r) {
  // Area-uniform sampling by rejection on the tube angle (area element ~ R + r cos v).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<Eigen::Vector3d> p, nn;
  while (static_cast<int>(p.size()) < n) {
    const double a = 2 * M_PI * U(rng), b = 2 * M_PI * U(rng);
    if (U(rng) * (R + r) > R + r * std::cos(b)) continue;
    const Eigen::Vector3d normal(std::cos(b) * std::cos(a), std::cos(b) * std::sin(a), std::sin(b));
    p.emplace_back(Eigen::Vector3d(R * std::cos(a), R * std::sin(a), 0) + r * normal);
    nn.push_back(normal);
  }
  PointCloud c;
  c.positions.resize(n, 3);
  c.normals.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    c.positions.row(i) = p[static_cast<std::size_t>(i)].transpose();
    c.normals.row(i) = nn[static_cast<std::size_t>(i)].transpose();
  }
  return c;
}

Renumbered renumbered(const TriangleMesh& mesh, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Renumbered out;
  out.new_index.resize(static_cast<std::size_t>(mesh.vertices.rows()));
  std::iota(out.new_index.begin(), out.new_index.end(), 0);
  std::shuffle(out.new_index.begin(), out.new_index.end(), rng);
  const bool normals = mesh.normals.rows() == mesh.vertices.rows();
  out.mesh.vertices.resize(mesh.vertices.rows(), 3);
  if (normals) out.mesh.normals.resize(mesh.vertices.rows(), 3);
  for (std::size_t v = 0; v < out.new_index.size(); ++v) {
    out.mesh.vertices.row(out.new_index[v]) = mesh.vertices.row(static_cast<Eigen::Index>(v));
    if (normals) out.mesh.normals.row(out.new_index[v]) = mesh.normals.row(static_cast<Eigen::Index>(v));
  }
  std::vector<Eigen::Index> order(static_cast<std::size_t>(mesh.triangles.rows()));
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  out.mesh.triangles.resize(mesh.triangles.rows(), 3);
  for (std::size_t t = 0; t < order.size(); ++t)
    for (int k = 0; k < 3; ++k)
      out.mesh.triangles(static_cast<Eigen::Index>(t), k) =
          out.new_index[static_cast<std::size_t>(mesh.triangles(order[t], (k + static_cast<int>(t)) % 3))];
  return out;
}

TriangleMesh icosphere(int levels, double radius, const Eigen::Vector3d& center) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> v{{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<std::array<int, 3>> f{{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> middle;
    const auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto [it, added] = middle.try_emplace(key, static_cast<int>(v.size()));
      if (added) v.push_back((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
      return it->second;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& [a, b, c] : f) {
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.insert(next.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    f = std::move(next);
  }
  TriangleMesh m;
  m.vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    m.vertices.row(static_cast<Eigen::Index>(i)) = (center + radius * v[i]).transpose();
  m.triangles.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i)
    for (int k = 0; k < 3; ++k) m.triangles(static_cast<Eigen::Index>(i), k) = f[i][static_cast<std::size_t>(k)];
  return m;
}

PointCloud sample_plane(int nx, int ny) {
  PointCloud c;
  c.positions.resize(nx * ny, 3);
  c.normals.resize(nx * ny, 3);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      c.positions.row(j * nx + i) << i / double(nx - 1), j / double(ny - 1), 0.0;
      c.normals.row(j * nx + i) << 0, 0, 1;
    }
  return c;
}

void add_normal_noise(PointCloud& c, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  for (Eigen::Index i = 0; i < c.size(); ++i) c.positions.row(i) += g(rng) * c.normals.row(i);
}

PointCloud noisy_heightfield(int n, double sigma, const std::function<double(double, double)>& height,
                             std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, sigma);
  PointCloud c;
  c.positions.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    c.positions.row(i) << x + g(rng), y + g(rng), height(x, y) + g(rng);
  }
  return c;
}

std::vector<std::uint32_t> all_rows(Eigen::Index n) {
  std::vector<std::uint32_t> rows(static_cast<std::size_t>(n));
  std::iota(rows.begin(), rows.end(), 0u);
  return rows;
}

std::set<std::array<double, 9>> triangle_set(const TriangleMesh& mesh) {
  std::set<std::array<double, 9>> out;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a)
        c[static_cast<std::size_t>(k)][static_cast<std::size_t>(a)] = mesh.vertices(mesh.triangles(t, k), a);
    const auto first = static_cast<std::size_t>(std::min_element(c.begin(), c.end()) - c.begin());
    std::array<double, 9> key;
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t a = 0; a < 3; ++a) key[3 * k + a] = c[(first + k) % 3][a];
    out.insert(key);
  }
  return out;
}

}  // namespace clustersurf::test
