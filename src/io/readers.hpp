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

}  // namespace clustersurf::io
