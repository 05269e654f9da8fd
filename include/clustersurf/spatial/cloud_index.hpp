#pragma once
// A point cloud indexed once for the whole pipeline: the builder, the orientation, the trim,
// the automatic grid and the distance colors share one k-d tree of the points, one of the rows
// a tree clusters, and one measure of the spacing (from the outlier test's neighbour pass when
// that runs first), each computed on first request.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/spatial/outliers.hpp>

#include <cstdint>
#include <memory>
#include <span>

namespace clustersurf {

/// What the stages ask of a cloud, each computed once, on first request, and thread-safe: the
/// k-d tree of its points, their median spacing, and the rows a tree clusters (all but its
/// outliers) with their own k-d tree. Adapts the caller's cloud (a reference: it must outlive
/// the index and stay unchanged); only the clustered rows are copied, and only when a tree left
/// outliers out.
class CloudIndex {
 public:
  explicit CloudIndex(const PointCloud& cloud);
  ~CloudIndex();
  CloudIndex(const CloudIndex&) = delete;
  CloudIndex& operator=(const CloudIndex&) = delete;

  const PointCloud& cloud() const noexcept;
  /// The k-d tree of every point.
  const KdTree& points() const;
  /// PointSpacing::median of the points (point_spacing()): what ClusterTree::point_spacing stores.
  double median_spacing() const;
  /// find_outliers() over points(). Its neighbour pass measures every point's spacing too, so a
  /// median_spacing() not yet asked for is taken from it (the same value) instead of queried;
  /// its kept points' spreads are kept for rows() of those points.
  OutlierReport outliers(const OutlierOptions& options) const;

  /// A subset of the rows, in increasing order, and its k-d tree.
  struct Subset {
    const Points& positions;
    const KdTree& index;
    /// Each row's spread among the subset (mean distance to its `spread_neighbors` nearest) when
    /// the subset is the kept rows of the last outliers() call, else empty.
    std::span<const double> spread;
    std::size_t spread_neighbors = 0;
  };
  /// The rows `kept` (increasing input indices) and their k-d tree; every row: the cloud itself
  /// and points(). The last subset is kept, so the builder's clustered rows serve the trim; a
  /// Subset stays valid until rows() or outliers() is asked for another one.
  Subset rows(std::span<const std::uint32_t> kept) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clustersurf
