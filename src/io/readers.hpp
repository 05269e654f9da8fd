#pragma once
// Format-specific readers behind read_point_cloud() and read_triangle_mesh().

#include <clustersurf/core/errors.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include "io/text_parse.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

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

/// What the columns of an XYZ / PTS / TXT / CSV file hold beyond x y z: the first column of its
/// normals and of its colors, and its intensity's, each -1 when it has none.
struct XyzLayout {
  int normals = -1, colors = -1, intensity = -1;
};

/// A color channel's byte from its value in a text file (0 where it is not a number).
std::uint8_t text_color_byte(double value);

/// An XYZ / PTS / TXT / CSV file parsed a point at a time (read_xyz() is this run to the end):
/// the same rules and the same errors, each naming its line.
class XyzLines {
 public:
  /// The most values a line holds.
  static constexpr std::size_t kMaxColumns = 9;
  /// `bytes` must outlive the parser.
  XyzLines(const std::filesystem::path& file, std::string_view bytes);
  XyzLines(const XyzLines&) = delete;
  XyzLines& operator=(const XyzLines&) = delete;
  /// The next point's values into v (3, 4, 6, 7 or 9 of them, the file's columns) and their
  /// count; 0 at the end of the file, where a PTS count line is checked. Throws InputError.
  std::size_t next(std::array<double, kMaxColumns>& v);
  /// The line of the last point read.
  std::uint64_t line() const noexcept { return cursor_.line(); }
  /// Bytes consumed so far.
  std::size_t offset() const noexcept { return cursor_.offset(); }
  /// What the columns hold, from every line read so far (the whole file's once next() has
  /// returned 0): x y z [intensity]; with 6 columns normals, or colors where those three are
  /// whole numbers from 0 to 255 on every line and above 1 on some (x y z r g b, as CloudCompare
  /// writes a colored cloud); with 7, PTS's intensity and colors; with 9, colors and normals, the
  /// colors the last three only where those alone look like colors.
  XyzLayout layout() const noexcept;

 private:
  std::filesystem::path file_;
  TextCursor cursor_;
  std::vector<std::string_view> fields_;
  std::size_t columns_ = 0;
  std::uint64_t columns_line_ = 0;
  std::int64_t declared_ = -1;
  std::uint64_t declared_line_ = 0;
  std::uint64_t points_ = 0;
  /// For the triples that start at columns 3 and 6: every line's are whole numbers from 0 to
  /// 255, and some line's is above 1.
  std::array<bool, 2> byte_triple_{true, true}, above_one_{false, false};
};
ParsedFile read_obj(const std::filesystem::path& file, std::string_view bytes, bool want_faces);
/// LAS 1.0-1.4, point formats 0-10 (las_reader.cpp).
ParsedFile read_las(const std::filesystem::path& file, std::string_view bytes);

/// Where a LAS file's point records lie and how their coordinates decode, from a header checked
/// against the file's size (every count, offset, VLR and EVLR): las_points() throws InputError
/// with the byte offset otherwise, so each of the `count` records lies inside the file.
struct LasPoints {
  std::uint64_t count = 0;
  std::uint64_t first = 0;   ///< byte offset of the first record
  std::uint16_t record = 0;  ///< bytes per record
  unsigned format = 0;       ///< point data record format, 0-10
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::optional<std::uint16_t> rgb;  ///< offset of red, green, blue in a record, if the format has them

  /// The position of record `i` (< count) in the file's coordinates: integers times the
  /// scale plus the offset, in double precision.
  Eigen::Vector3d position(std::string_view bytes, std::uint64_t i) const;
  /// Whether the point format has red, green and blue.
  bool has_colors() const noexcept { return rgb.has_value(); }
  /// The 16-bit red, green and blue of record `i` (< count; has_colors() required).
  std::array<std::uint16_t, 3> color(std::string_view bytes, std::uint64_t i) const;
  /// The largest red, green or blue over every record (has_colors() required; reads every
  /// record's color). 0: the format has the fields but the file left them empty, and the cloud
  /// has no colors; at most 255: 8-bit values stored in the 16-bit fields, read as they are
  /// (wide_color_byte()).
  std::uint16_t color_maximum(std::string_view bytes) const;
};

/// The byte of a 16-bit color channel (LAS, PDAL's PCD): as it is when the file's colors are
/// all at most 255 (8-bit values in 16-bit fields), else rounded from 0..65535.
inline std::uint8_t wide_color_byte(std::uint16_t value, bool eight_bit) {
  return eight_bit ? static_cast<std::uint8_t>(value) : static_cast<std::uint8_t>(std::lround(value / 257.0));
}
LasPoints las_points(const std::filesystem::path& file, std::string_view bytes);
/// E57: every scan, posed, with colors and intensity when present (e57_reader.cpp).
ParsedFile read_e57(const std::filesystem::path& file, std::string_view bytes);

/// An E57 file's points decoded a block of records at a time (e57_stream.cpp), as read_e57()
/// gives them: every scan in turn, posed, the records the scanner marked invalid left out.
/// Positions and colors only: the other fields are not decoded, so a damaged intensity stream,
/// which read_e57() refuses, goes unnoticed. Its memory is a block and what the packets hold
/// of one coordinate field ahead of another (nothing much for files whose writers interleave
/// the fields packet by packet, as libE57Format does), whatever the file's size.
class E57Points {
 public:
  /// Checks the header, the XML and every scan's binary section (InputError with the byte
  /// offset); `bytes` must outlive the reader.
  E57Points(const std::filesystem::path& file, std::string_view bytes);
  ~E57Points();
  E57Points(const E57Points&) = delete;
  E57Points& operator=(const E57Points&) = delete;

  /// Records in all scans (the invalid ones included).
  std::uint64_t records() const noexcept;
  /// Whether every scan has colors (as read_e57() gives them only then).
  bool has_colors() const noexcept;
  /// Decodes the next `n` records (at most those left) and puts the positions of the valid ones
  /// into `out` (its rows replaced), non-finite ones included, and their colors into `colors`
  /// when given and has_colors(); `located[i]` is the physical byte offset of row i's
  /// non-finite coordinate when it was decoded as one (not when a pose made it overflow).
  /// Throws InputError for a damaged packet.
  void read(std::uint64_t n, Points& out, std::vector<std::optional<std::uint64_t>>& located, Colors* colors = nullptr);
  /// The file's byte ranges [begin, end) that no read before rewind() touches again, those not
  /// handed out by an earlier call.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> finished_bytes();
  /// Back to the first record.
  void rewind();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
/// PTX: every gridded scan with its transform; (0,0,0) is no return (ptx_reader.cpp).
ParsedFile read_ptx(const std::filesystem::path& file, std::string_view bytes);

/// A point of a PTX file: posed by its scan's transform, its intensity (0 when the file has
/// none), its color when the file has them, and its scan.
struct PtxPoint {
  Eigen::Vector3d position;
  float intensity = 0;
  std::array<std::uint8_t, 3> rgb{};
  std::uint32_t scan = 0;
};

/// A PTX file parsed a point at a time (read_ptx() is this run to the end): the same rules and
/// the same errors, each naming its line.
class PtxLines {
 public:
  /// `bytes` must outlive the parser.
  PtxLines(const std::filesystem::path& file, std::string_view bytes);
  PtxLines(const PtxLines&) = delete;
  PtxLines& operator=(const PtxLines&) = delete;
  /// The next point with a return into `out`; false at the end of the file (InputError when it
  /// holds no scan). Throws InputError for a malformed header or grid line.
  bool next(PtxPoint& out);
  /// The line of the last point read.
  std::uint64_t line() const noexcept { return cursor_.line(); }
  /// Bytes consumed so far.
  std::size_t offset() const noexcept { return cursor_.offset(); }
  /// Whether the points have colors (unset before the first grid line).
  std::optional<bool> colored() const noexcept { return colored_; }
  /// The scanner position of every scan begun so far (x, y, z each).
  const std::vector<double>& scanners() const noexcept { return scanners_; }

 private:
  /// Reads the next scan's header; false at the end of the file.
  bool open_scan();

  std::filesystem::path file_;
  TextCursor cursor_;
  std::size_t bytes_ = 0;
  std::vector<std::string_view> fields_;
  std::vector<double> scanners_;
  std::optional<bool> colored_;
  Eigen::Matrix3d linear_ = Eigen::Matrix3d::Identity();
  Eigen::RowVector3d translation_ = Eigen::RowVector3d::Zero();
  std::int64_t columns_ = 0, rows_ = 0;
  std::uint64_t cells_ = 0, cell_ = 0;
};
/// PCD 0.5-0.7: ascii, binary and binary_compressed (pcd_reader.cpp).
ParsedFile read_pcd(const std::filesystem::path& file, std::string_view bytes);

}  // namespace clustersurf::io
