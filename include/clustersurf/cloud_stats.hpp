#pragma once
// Summary figures of a point cloud (the `stats` command).

#include <clustersurf/point_cloud.hpp>

namespace clustersurf {

/// What `clustersurf stats` reports about a cloud.
struct CloudStats {
  std::size_t points = 0;
  BoundingBox bbox;
  double diagonal = 0;
  /// Mean distance from a point to its nearest other point (0 for fewer than two points).
  double mean_spacing = 0;
  /// Median of the same distances.
  double median_spacing = 0;
  bool has_normals = false;
  bool has_colors = false;
};

/// Computes CloudStats; spacing uses every point up to `max_samples` points, then an evenly
/// strided deterministic subset of that size.
CloudStats compute_stats(const PointCloud& cloud, std::size_t max_samples = 200000);

}  // namespace clustersurf
