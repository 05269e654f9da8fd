#pragma once
// Properties every successful parse must have, checked by the fuzz targets (a violation aborts,
// which libFuzzer reports as a crash with the input that caused it).

#include <clustersurf/core/errors.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace clustersurf::fuzz {

/// A directory of this process's own, made with mkdtemp on first use and removed with what
/// it holds when the process exits: the targets that read files write their inputs there.
inline const std::filesystem::path& scratch_directory() {
  struct Scratch {
    std::filesystem::path dir;
    Scratch() {
      std::string pattern = (std::filesystem::temp_directory_path() / "clustersurf-fuzz-XXXXXX").string();
      if (::mkdtemp(pattern.data()) == nullptr) std::abort();
      dir = pattern;
    }
    ~Scratch() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  };
  static const Scratch scratch;
  return scratch.dir;
}

/// Aborts unless `condition` holds.
inline void require(bool condition) {
  if (!condition) std::abort();
}

/// A cloud as the readers promise it: points, finite coordinates, normals and origin,
/// per-point rows matching the positions, every point's scanner one of the scanners.
inline void check_cloud(const PointCloud& c) {
  require(c.size() > 0 && c.positions.cols() == 3 && c.positions.allFinite() && c.origin.allFinite());
  require(!c.has_normals() || (c.normals.rows() == c.size() && c.normals.allFinite()));
  require(!c.has_colors() || c.colors.rows() == c.size());
  for (const PointAttribute& a : c.attributes) require(a.values.size() == c.size());
  require(!c.has_scanners() || static_cast<Eigen::Index>(c.scanner_of_point.size()) == c.size());
  for (const std::uint32_t s : c.scanner_of_point) require(s < c.scanner_positions.rows());
  require(c.scanner_positions.allFinite());
}

/// A mesh as the readers promise it: every triangle index names a vertex.
inline void check_mesh(const TriangleMesh& m) {
  require(m.vertices.rows() > 0 && m.vertices.allFinite());
  require(m.triangles.size() == 0 || (m.triangles.minCoeff() >= 0 && m.triangles.maxCoeff() < m.vertices.rows()));
}

/// One fuzz input through the readers of a text or PLY format: as a point cloud, then, dropping
/// non-finite values, as a triangle mesh (formats with faces) or as a cloud again. Only
/// InputError may leave a reader, and every successful parse must pass the checks above.
inline int parse_everything(const std::uint8_t* data, std::size_t size, FileFormat format, const char* name,
                            bool has_faces) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    check_cloud(parse_point_cloud(bytes, format, name));
  } catch (const InputError&) {}
  ReadOptions drop;
  drop.drop_non_finite = true;
  try {
    if (has_faces)
      check_mesh(parse_triangle_mesh(bytes, format, name, drop));
    else
      check_cloud(parse_point_cloud(bytes, format, name, drop));
  } catch (const InputError&) {}
  return 0;
}

}  // namespace clustersurf::fuzz
