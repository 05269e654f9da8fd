#pragma once
// Helpers shared by the unit tests: temporary folders, data locations, synthetic samples.

#include <clustersurf/core/point_cloud.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace clustersurf::test {

/// A fresh folder under the system temp dir, removed (with its content) on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

/// Writes `bytes` to `file` (binary, exactly).
void write_file(const std::filesystem::path& file, const std::string& bytes);
/// Reads `file` whole.
std::string read_file(const std::filesystem::path& file);

/// A file of the shared scans folder, or nullopt when it is absent (the caller skips).
std::optional<std::filesystem::path> shared_data(const std::string& relative);
/// The default input written by scripts/setup (the npm bunny), or nullopt when absent.
std::optional<std::filesystem::path> default_bunny();

/// The benchmark's scan10-3k of `mesh`: 3,000 points of 10 virtual range scans (0.05 % range
/// noise, 0.02 % misregistration), drawn with `seed`.
PointCloud sparse_scan(const TriangleMesh& mesh, std::uint64_t seed);
/// `n` points on a sphere (Fibonacci lattice), with outward normals.
PointCloud sample_sphere(int n, double radius = 1.0, const Eigen::Vector3d& center = Eigen::Vector3d::Zero());
/// About `n` points on a torus (major radius R, minor radius r, axis z), with outward normals.
PointCloud sample_torus(int n, double R = 1.0, double r = 0.35);
/// A grid of nx x ny points on the plane z = 0 over [0,1]^2, normals +z.
PointCloud sample_plane(int nx, int ny);
/// A mesh renumbered: its vertices (with their normals) in a random order, its triangles in
/// another with their corners rotated (the same orientation).
struct Renumbered {
  TriangleMesh mesh;
  std::vector<int> new_index;  ///< new_index[v]: the new row of the old vertex v
};
Renumbered renumbered(const TriangleMesh& mesh, std::uint64_t seed);
/// An icosahedron subdivided `levels` times and pushed onto the sphere of `radius` about
/// `center`, its triangles facing out.
TriangleMesh icosphere(int levels, double radius = 1.0, const Eigen::Vector3d& center = Eigen::Vector3d::Zero());
/// Moves every point along its normal by Gaussian noise of standard deviation `sigma` (seeded).
void add_normal_noise(PointCloud& c, double sigma, std::uint64_t seed);
/// The triangles of a mesh as corner positions, each starting at its smallest corner (its
/// orientation kept): the mesh whatever the numbering of its vertices and triangles.
std::set<std::array<double, 9>> triangle_set(const TriangleMesh& mesh);
/// `n` points of the height field z = height(x, y) over the unit square, Gaussian noise of
/// standard deviation `sigma` on every coordinate (seeded), no normals.
PointCloud noisy_heightfield(int n, double sigma, const std::function<double(double, double)>& height,
                             std::uint64_t seed);
/// The rows 0, 1, …, n − 1: every point of a cloud of n.
std::vector<std::uint32_t> all_rows(Eigen::Index n);

}  // namespace clustersurf::test
