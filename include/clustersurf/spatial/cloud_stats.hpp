#pragma once
// Summary figures of a point cloud (the `stats` command).

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <span>

namespace clustersurf {

/// What `clustersurf stats` reports about a cloud.
struct CloudStats {
  std::size_t points = 0;
  /// In the file's coordinates (the cloud's origin added back).
  BoundingBox bbox;
  /// The cloud's origin (PointCloud::origin).
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double diagonal = 0;
  /// Mean distance from a point to its nearest other point (0 for fewer than two points).
  double mean_spacing = 0;
  /// Median of the same distances.
  double median_spacing = 0;
  bool has_normals = false;
  bool has_colors = false;
  /// Names of the per-point attributes (intensity, classification, ...).
  std::vector<std::string> attributes;
  /// How many scanner positions the file gave (0: unknown).
  std::size_t scanners = 0;
  /// How many scans its points name (PointCloud::scanner_of_point; 0: the file does not say).
  std::size_t scans = 0;
};

/// Repeats of a point's position that the spacing looks past (also OutlierOptions::neighbors'
/// default, so that the outlier test's nearest distances are the spacing's): a point with more
/// has spacing 0.
inline constexpr std::size_t kRepeatsLookedPast = 8;

/// How densely points sample a surface: the mean and the median distance from a point to its
/// nearest point at another position (points that repeat a position exactly count once; 0
/// where kRepeatsLookedPast or more others repeat it).
struct PointSpacing {
  double mean = 0;
  double median = 0;
};

/// PointSpacing of the points `index` holds: every point up to `max_samples` points, then an
/// evenly strided deterministic subset of that size (0 for fewer than two points).
PointSpacing point_spacing(const KdTree& index, std::size_t max_samples = 200000);
/// The same over the first `rows` points only, their neighbours among all the points `index`
/// holds (a region's own points, its halo after them).
PointSpacing point_spacing(const KdTree& index, std::size_t max_samples, std::size_t rows);

/// The same figures from each point's distance to its nearest point at another position (as
/// OutlierReport::nearest holds them, or their first rows for a region's own points): the same
/// samples, so the same values as point_spacing() of the points' k-d tree, without its queries.
PointSpacing point_spacing(std::span<const double> nearest, std::size_t max_samples = 200000);

/// Computes CloudStats; spacing uses every point up to `max_samples` points, then an evenly
/// strided deterministic subset of that size.
CloudStats compute_stats(const PointCloud& cloud, std::size_t max_samples = 200000);

}  // namespace clustersurf
