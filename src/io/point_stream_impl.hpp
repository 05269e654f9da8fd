#pragma once
// PointStream's state: which reader a file takes and where each one is (point_stream.cpp opens
// them and hands out blocks; point_blocks.cpp reads each format's blocks).

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_stream.hpp>

#include "io/mapped_file.hpp"
#include "io/pcd_format.hpp"
#include "io/ply_format.hpp"
#include "io/readers.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace clustersurf {

namespace detail {

/// The vertex element of a binary PLY file of points, and where its records start; nullopt
/// when the file is not one (ascii, faces, lists in the vertex element or before it).
struct PlyPoints {
  io::ply::Element vertex;
  io::ply::VertexLayout layout;
  std::vector<std::size_t> offsets;  // of each property inside a record
  std::size_t record = 0;
  std::size_t begin = 0;  // byte offset of the first record
  bool swap = false;
  UpAxis up = UpAxis::Y;
};

/// The binary PLY file of points `bytes` holds, or nullopt when it is not one (ascii, faces,
/// lists in the vertex element or before it).
std::optional<PlyPoints> ply_points(const std::filesystem::path& file, std::string_view bytes);

/// The error for point `index` (0-based), found at `where`, that has `what` (a non-finite value).
InputError non_finite_point(const std::filesystem::path& file, const FileLocation& where, std::uint64_t index,
                            const std::string& what);

}  // namespace detail

struct PointStream::Impl {
  std::filesystem::path file;
  ReadOptions options;
  std::optional<io::MappedFile> mapped;
  std::optional<detail::PlyPoints> ply;
  std::optional<io::LasPoints> las;
  std::optional<io::E57Points> e57;
  std::optional<io::XyzLines> xyz;
  std::optional<io::PtxLines> ptx;
  std::optional<io::pcd::Layout> pcd_layout;
  std::optional<io::pcd::Records> pcd;
  std::uint64_t text_points = 0;  // points of an XYZ or PTX file, counted when opened
  io::XyzLayout xyz_layout;       // an XYZ file's columns, found when opened
  bool ptx_colored = false;       // PTX: the points have colors
  bool colors = false;            // blocks carry colors
  bool eight_bit = false;         // LAS, PCD red, green, blue: every color is at most 255 (read as it is)
  std::size_t released = 0;       // bytes of a text or PCD file given back to the system
  bool failed = false;            // a read threw: the text parser is past the point it refused
  std::uint64_t points = 0;       // E57: valid points decoded so far (for messages)
  std::vector<std::optional<std::uint64_t>> located;  // E57: where each point of a block was found non-finite
  PointCloud whole;  // the file read whole, in the file's coordinates, when not streamed
  std::uint64_t next = 0;

  std::uint64_t size() const {
    return ply          ? ply->vertex.count
           : las        ? las->count
           : e57        ? e57->records()
           : pcd        ? pcd_layout->points
           : xyz || ptx ? text_points
                        : static_cast<std::uint64_t>(whole.size());
  }
  bool streamed() const { return ply || las || e57 || pcd || xyz || ptx; }
  /// Parses the text file once (its count, an XYZ file's columns, every error the reader
  /// would give), then starts over for the points.
  void open_text();
  /// Back to the text file's first point.
  void restart_text() {
    if (xyz)
      xyz.emplace(file, mapped->view());
    else
      ptx.emplace(file, mapped->view());
  }
  /// The next `n` XYZ points into `block`.
  void read_xyz(Eigen::Index n, PointCloud& block);
  /// Whether blocks carry colors (as read_point_cloud() gives them); for LAS and PCD's red, green
  /// and blue fields, a look at every point's color says whether they are 8-bit (`eight_bit`).
  bool find_colors();
  /// PCD: the largest red, green or blue value (0..65535) of the points that are points.
  std::uint16_t pcd_color_maximum();
  /// The next `n` PTX points into `block` (positions only).
  void read_ptx(Eigen::Index n, PointCloud& block);
  /// Gives back the file's pages read so far (up to byte `offset`).
  void release_read(std::size_t offset) {
    mapped->release(released, offset);
    released = offset;
  }
  /// The next `n` LAS records into `block` (positions only: LAS has no normals).
  void read_las(Eigen::Index n, PointCloud& block);
  /// The next `n` E57 records into `block` (positions only; the invalid ones left out).
  void read_e57(Eigen::Index n, PointCloud& block);
  /// Opens a PCD file (binary_compressed data is decoded through once here, to check it).
  void open_pcd();
  /// The next `n` binary PLY vertices into `block`.
  void read_ply(Eigen::Index n, PointCloud& block);
  /// The next `n` PCD records into `block` (those whose position is NaN, PCL's "no point", left out).
  void read_pcd(Eigen::Index n, PointCloud& block);
};

}  // namespace clustersurf
