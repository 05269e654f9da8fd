#pragma once
// Format-specific readers behind read_point_cloud() and read_triangle_mesh().

#include <clustersurf/errors.hpp>
#include <clustersurf/point_cloud.hpp>
#include <clustersurf/point_cloud_io.hpp>

#include <filesystem>
#include <optional>
#include <string_view>

namespace clustersurf::io {

/// Vertices (as a cloud) and, when asked for, triangles of a parsed file.
struct ParsedFile {
  PointCloud cloud;
  Triangles triangles;
  /// Where the first point with a non-finite coordinate or normal was read (line or byte
  /// offset), so that the error names it; unset when every point is finite.
  std::optional<FileLocation> first_non_finite;
};

/// Records `where` as the location of the first non-finite point if point `row` of `cloud`
/// (already stored) has a NaN or infinite coordinate or normal.
inline void note_non_finite(ParsedFile& parsed, Eigen::Index row, const FileLocation& where) {
  if (parsed.first_non_finite) return;
  const PointCloud& c = parsed.cloud;
  if (!c.positions.row(row).allFinite() || (c.has_normals() && !c.normals.row(row).allFinite()))
    parsed.first_non_finite = where;
}

ParsedFile read_ply(const std::filesystem::path& file, std::string_view bytes, bool want_faces);
ParsedFile read_xyz(const std::filesystem::path& file, std::string_view bytes);
ParsedFile read_obj(const std::filesystem::path& file, std::string_view bytes, bool want_faces);
/// LAS 1.0-1.4, point formats 0-10 (las_reader.cpp).
ParsedFile read_las(const std::filesystem::path& file, std::string_view bytes);
/// E57: every scan, posed, with colors and intensity when present (e57_reader.cpp).
ParsedFile read_e57(const std::filesystem::path& file, std::string_view bytes);
/// PTX: every gridded scan with its transform; (0,0,0) is no return (ptx_reader.cpp).
ParsedFile read_ptx(const std::filesystem::path& file, std::string_view bytes);
/// PCD 0.5-0.7: ascii, binary and binary_compressed (pcd_reader.cpp).
ParsedFile read_pcd(const std::filesystem::path& file, std::string_view bytes);

}  // namespace clustersurf::io
