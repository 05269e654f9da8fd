#pragma once
// A binary PLY mesh written in pieces (a mesh joined tile by tile, never whole in memory), and
// the PLY header every PLY writer shares.

#include "io/atomic_file.hpp"

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf::io {

/// The header write_ply() writes: `vertices` with float (or double) x, y, z, normals, uchar
/// colors and float attributes as asked, and `faces` as vertex-index lists when given; a z-up
/// geometry says so in a "comment up z" line, which the reader takes back as PointCloud::up.
std::string ply_header(std::uint64_t vertices, std::optional<std::uint64_t> faces, bool binary, bool double_precision,
                       bool normals, bool colors, const std::vector<std::string>& attributes, UpAxis up);

/// A binary little-endian PLY mesh whose counts are known first and whose vertices, then
/// triangles, come in pieces: the bytes write_ply() writes for the whole mesh (coordinates put
/// back at `origin`; double precision when it is not zero). Atomic: nothing is at `file` until
/// commit(), which checks that the counts were met.
class PlyMeshStream {
 public:
  PlyMeshStream(const std::filesystem::path& file, std::uint64_t vertices, std::uint64_t triangles, bool normals,
                bool colors, const Eigen::Vector3d& origin, UpAxis up);
  /// Appends the rows of `positions` (relative to the origin), with their normals and colors
  /// when the stream has them.
  void add_vertices(const Points& positions, const Points& normals, const Colors& colors);
  void add_triangles(const Triangles& triangles);
  void commit();

 private:
  void flush_if_full();
  AtomicFile out_;
  std::uint64_t vertices_, triangles_, vertices_written_ = 0, triangles_written_ = 0;
  bool normals_, colors_, double_;
  Eigen::Vector3d origin_;
  std::vector<char> buffer_;
};

}  // namespace clustersurf::io
