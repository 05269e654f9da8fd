#pragma once
// A point cloud file read a block of points at a time, for inputs larger than memory.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>

namespace clustersurf {

/// A point file read in blocks, in file order, in the file's coordinates (no origin shift).
/// Read in place (memory-mapped, each block's pages released once read, so memory stays at one
/// block whatever the file's size):
///   - a binary PLY file of points (a vertex element of scalar properties and no faces);
///   - a LAS file (1.0-1.4, any point format; its header checked as read_point_cloud() checks it);
///   - an E57 file (its header, XML and sections checked when opened; its packets decoded as the
///     blocks need them, every scan posed, the invalid records left out);
///   - a PCD file, ascii, binary or binary_compressed (its header checked when opened, and
///     compressed data decoded through once to check it, then read with one LZF decoder per
///     field; the records whose position is NaN, PCL's "no point", left out);
///   - a text file, XYZ / PTS / TXT / CSV or PTX (parsed once when opened, for its count and every
///     error the reader gives, then again block by block; a PTX file's scans posed, the cells
///     without a return left out).
/// Other files (OBJ, ascii PLY, meshes, which read_point_cloud() samples)
/// are read whole first and served from memory. Positions, normals and colors, as
/// read_point_cloud() gives them (LAS files and PCD files with red, green and blue fields are
/// looked through once when opened, for whether their 16-bit colors hold 8-bit values, and a
/// LAS file's for whether it left them 0 in every record: then it has none).
class PointStream {
 public:
  /// Opens `file`; IoError when it cannot be read, InputError when it is malformed (a binary
  /// PLY's records and a LAS, E57 or PCD file's header are checked against the file's size here,
  /// compressed PCD data is decoded through, and XYZ and PTX text is parsed through, so their
  /// errors come out here, with their byte offset or line).
  explicit PointStream(const std::filesystem::path& file, const ReadOptions& options = {});
  ~PointStream();
  PointStream(const PointStream&) = delete;
  PointStream& operator=(const PointStream&) = delete;

  /// Records in the file: the points before non-finite ones are dropped (when ReadOptions says
  /// so), and before an E57 file's invalid records and a PCD file's NaN ones are left out.
  std::uint64_t size() const noexcept;
  bool has_normals() const noexcept;
  /// Whether each block carries its points' colors (the class comment says which).
  bool has_colors() const noexcept;
  /// The file's up axis (PointCloud::up): z for LAS, E57 and PTX.
  UpAxis up() const noexcept;
  /// Read in place (binary PLY points, LAS, E57, PCD, XYZ and PTX text) rather
  /// than whole.
  bool streamed() const noexcept;
  /// The points of the next `count` records (fewer at the end) into `block` (its rows
  /// replaced); false at the end of the file. InputError (with the byte offset, or the line of
  /// a text file) for a non-finite coordinate or normal unless ReadOptions::drop_non_finite, for
  /// a damaged E57 packet and for a malformed line of an ascii PCD file; after that, InputError
  /// until rewind().
  bool read(std::size_t count, PointCloud& block);
  /// Back to the first point (also after a read that threw).
  void rewind();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clustersurf
