#pragma once
// Format-specific readers behind read_point_cloud() and read_triangle_mesh().

#include <clustersurf/point_cloud.hpp>
#include <clustersurf/point_cloud_io.hpp>

#include <filesystem>
#include <string_view>

namespace clustersurf::io {

/// Vertices (as a cloud) and, when asked for, triangles of a parsed file.
struct ParsedFile {
  PointCloud cloud;
  Triangles triangles;
};

ParsedFile read_ply(const std::filesystem::path& file, std::string_view bytes, bool want_faces);
ParsedFile read_xyz(const std::filesystem::path& file, std::string_view bytes);
ParsedFile read_obj(const std::filesystem::path& file, std::string_view bytes, bool want_faces);

}  // namespace clustersurf::io
