#pragma once
// E57's XML section (pugixml): the scans of /data3D, each with its prototype, limits, pose and
// binary section, read and checked before any point is decoded.

#include "io/e57_bytestream.hpp"
#include "io/e57_pages.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf::io::e57 {

/// A prototype field: its codec and the range it declares (for color scaling).
struct Field {
  std::string name;
  FieldCodec codec;
  double minimum = 0, maximum = 255;  // 0..255 when a Float field declares no range
};

/// One scan of /data3D: which prototype fields hold what (-1: absent), its limits and pose, and
/// its binary section, opened and checked to hold `records` records.
struct Scan {
  std::vector<Field> fields;
  int coord[3] = {-1, -1, -1}, invalid = -1, color[3] = {-1, -1, -1}, intensity = -1;
  bool spherical = false, has_pose = false;
  double color_lo[3] = {0, 0, 0}, color_hi[3] = {255, 255, 255};
  std::optional<std::array<double, 2>> intensity_limits;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // the pose's unit quaternion, as a matrix
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  bool posed = false;  // the pose moves the points (a rotation or translation other than the identity)
  std::uint64_t records = 0;
  Section section;

  /// Whether the scan has colorRed, colorGreen and colorBlue.
  bool has_colors() const noexcept { return color[0] >= 0 && color[1] >= 0 && color[2] >= 0; }
  /// 0..255 of the value `v` of color channel k, scaled from the scan's colorLimits (values
  /// outside clamped; an empty range: `v` itself).
  std::uint8_t color_byte(int k, double v) const;
  /// The fields as bytestreams to decode, without sinks.
  std::vector<StreamField> streams() const;
  /// The point that the three coordinate fields' values `decoded` stand for: spherical ones
  /// turned cartesian (range, azimuth, elevation), then posed.
  Eigen::Vector3d position(const Eigen::Vector3d& decoded) const;
};

/// The scans of a file and their records in all.
struct Scans {
  std::vector<Scan> scans;
  std::uint64_t records = 0;
};

/// Parses the XML section of `pages` and reads every scan of /data3D; throws InputError with
/// the byte offset when the XML, a scan's description or its binary section is malformed, or
/// the scans' records together do not fit in the file.
Scans read_scans(const PagedFile& pages);

}  // namespace clustersurf::io::e57
