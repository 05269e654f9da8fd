#pragma once
// How far apart the scans of a multi-scan cloud lie where they overlap: its registration error,
// measured from which scan saw each point (E57 and PTX files say it).

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <cstddef>

namespace clustersurf {

/// Options of measure_registration().
struct RegistrationOptions {
  /// Points around each sampled point: its own scan's fit the local plane, another scan's are
  /// measured against it.
  std::size_t neighbors = 32;
  /// The fewest points of each of the two scans a measurement needs.
  std::size_t min_points = 8;
  /// Points sampled (evenly strided over the rows); every point up to this many.
  std::size_t samples = 20000;
};

/// The registration error of a cloud's scans.
struct ScanRegistration {
  std::size_t scans = 0;  ///< distinct scans among the points
  /// Sampled points with at least options.min_points of their own scan and of another scan
  /// among their neighbours (0: the scans do not overlap, or the cloud has one scan).
  std::size_t overlaps = 0;
  /// Over those, the offset along the normal from the plane of the point's own scan to the
  /// mean of the other scan's points around it (the other scan taken with the most points
  /// there): the median of its magnitude and its root mean square, in the cloud's units. The
  /// offset holds the noise of that mean too (about σ / √min_points at least).
  double median_offset = 0;
  double rms_offset = 0;
};

/// measure_registration() of `cloud`, whose rows `index` holds; zero overlaps unless
/// cloud.scanner_of_point names a scan for every point. Deterministic for any thread count.
ScanRegistration measure_registration(const PointCloud& cloud, const KdTree& index,
                                      const RegistrationOptions& options = {});

}  // namespace clustersurf
