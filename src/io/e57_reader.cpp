// E57 (ASTM E2807) reader: the XML section (pugixml) and every scan of /data3D, decoded through
// the paged layer (e57_pages) and the CompressedVector decoder (e57_bytestream), posed and
// concatenated. What is kept across scans:
//   - colors only when every scan has colorRed/Green/Blue, scaled to 0..255 by colorLimits
//     (else by the fields' own minimum and maximum); otherwise the cloud has none;
//   - the attribute "intensity" only when every scan has it, mapped to 0..1 by intensityLimits
//     when they span a range, else raw;
//   - scanner positions only when every scan says where its scanner was: a pose (its translation)
//     or spherical coordinates (the origin of the scan's frame, posed). A cartesian scan without
//     pose is often an export or a merge whose origin is no scanner, and a wrong scanner position
//     would flip its normals, so then no scan gets one.
// Points whose cartesianInvalidState (sphericalInvalidState for spherical scans) is not 0 are
// dropped. Row/column/return indices, time stamps and any other fields are skipped; images2D are
// ignored. Non-finite points are left to the dispatcher, with the byte offset of the first.

#include "io/e57_scans.hpp"
#include "io/readers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace clustersurf::io {

namespace {

/// `v` as a float without undefined behaviour (finite values beyond float saturate).
float to_float(double v) {
  constexpr double m = std::numeric_limits<float>::max();
  return static_cast<float>(std::isnan(v) ? v : std::clamp(v, -m, m));
}

/// The records of an E57 file's scans decoded into one cloud, row after row: positions (posed),
/// colors and intensities where every scan has them, each row's scan, the rows the scanner
/// marked invalid and where a non-finite coordinate was read.
struct DecodedScans {
  const e57::PagedFile& pages;
  bool colors, intensity;
  PointCloud cloud;
  Eigen::VectorXf intensities;
  std::vector<std::uint8_t> invalid;
  std::vector<std::uint32_t> scan_of;
  std::map<Eigen::Index, std::uint64_t> non_finite;  // row → where its first non-finite coordinate is

  DecodedScans(const e57::PagedFile& p, std::uint64_t total, bool with_colors, bool with_intensity)
      : pages(p), colors(with_colors), intensity(with_intensity), invalid(total, 0), scan_of(total, 0) {
    const auto n = static_cast<Eigen::Index>(total);
    cloud.positions.resize(n, 3);
    if (colors) cloud.colors = Colors::Zero(n, 3);
    if (intensity) intensities = Eigen::VectorXf::Zero(n);
  }

  /// Decodes scan `si` into the rows from `row0` on.
  void decode(const e57::Scan& s, std::size_t si, Eigen::Index row0) {
    std::vector<e57::StreamField> streams = s.streams();
    for (int k = 0; k < 3; ++k)
      streams[static_cast<std::size_t>(s.coord[k])].sink = [this, k, row0](std::uint64_t r, double v,
                                                                           std::uint64_t logical) {
        cloud.positions(row0 + static_cast<Eigen::Index>(r), k) = v;
        if (!std::isfinite(v)) non_finite.emplace(row0 + static_cast<Eigen::Index>(r), pages.to_physical(logical));
      };
    if (s.invalid >= 0)
      streams[static_cast<std::size_t>(s.invalid)].sink = [this, row0](std::uint64_t r, double v, std::uint64_t) {
        invalid[static_cast<std::size_t>(row0) + r] = v != 0;
      };
    for (int k = 0; colors && k < 3; ++k)
      streams[static_cast<std::size_t>(s.color[k])].sink = [this, &s, k, row0](std::uint64_t r, double v,
                                                                               std::uint64_t) {
        cloud.colors(row0 + static_cast<Eigen::Index>(r), k) = s.color_byte(k, v);
      };
    if (intensity)
      streams[static_cast<std::size_t>(s.intensity)].sink = [this, row0, lim = s.intensity_limits](
                                                                std::uint64_t r, double v, std::uint64_t) {
        intensities(row0 + static_cast<Eigen::Index>(r)) =
            to_float(lim ? (v - (*lim)[0]) / ((*lim)[1] - (*lim)[0]) : v);
      };
    e57::decode_records(pages, s.section, s.records, streams);
    const auto rows = static_cast<Eigen::Index>(s.records);
    for (Eigen::Index i = row0; i < row0 + rows; ++i) {
      if (s.spherical || s.posed) cloud.positions.row(i) = s.position(cloud.positions.row(i).transpose()).transpose();
      scan_of[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(si);
    }
  }

  /// Drops the rows the scanner marked invalid, keeping the order of the rest; the first kept
  /// row with a non-finite coordinate is named by its byte (invalid records may hold anything).
  /// Returns the rows kept.
  Eigen::Index keep_valid(std::optional<FileLocation>& first_non_finite) {
    Eigen::Index kept = 0;
    for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i) {
      if (invalid[static_cast<std::size_t>(i)] != 0) continue;
      if (!first_non_finite)
        if (const auto it = non_finite.find(i); it != non_finite.end())
          first_non_finite = FileLocation{std::nullopt, it->second};
      cloud.positions.row(kept) = cloud.positions.row(i);
      if (colors) cloud.colors.row(kept) = cloud.colors.row(i);
      if (intensity) intensities(kept) = intensities(i);
      scan_of[static_cast<std::size_t>(kept)] = scan_of[static_cast<std::size_t>(i)];
      ++kept;
    }
    cloud.positions.conservativeResize(kept, 3);
    if (colors) cloud.colors.conservativeResize(kept, 3);
    if (intensity) intensities.conservativeResize(kept);
    scan_of.resize(static_cast<std::size_t>(kept));
    return kept;
  }
};

}  // namespace

ParsedFile read_e57(const std::filesystem::path& file, std::string_view bytes) {
  const e57::PagedFile pages(file, bytes);
  const auto [scans, total] = e57::read_scans(pages);
  bool colors = !scans.empty(), intensity = !scans.empty(), scanners = !scans.empty();
  for (const e57::Scan& s : scans) {
    colors = colors && s.has_colors();
    intensity = intensity && s.intensity >= 0;
    scanners = scanners && (s.has_pose || s.spherical);
  }
  DecodedScans decoded(pages, total, colors, intensity);
  Eigen::Index row0 = 0;
  for (std::size_t si = 0; si < scans.size(); ++si) {
    decoded.decode(scans[si], si, row0);
    row0 += static_cast<Eigen::Index>(scans[si].records);
  }
  ParsedFile out;
  decoded.keep_valid(out.first_non_finite);
  PointCloud& cloud = out.cloud;
  cloud = std::move(decoded.cloud);
  if (intensity) cloud.attributes.push_back({"intensity", std::move(decoded.intensities)});
  if (scanners) {
    cloud.scanner_of_point = std::move(decoded.scan_of);
    cloud.scanner_positions.resize(static_cast<Eigen::Index>(scans.size()), 3);
    for (std::size_t si = 0; si < scans.size(); ++si)
      cloud.scanner_positions.row(static_cast<Eigen::Index>(si)) = scans[si].translation.transpose();
  }
  return out;
}

}  // namespace clustersurf::io
