#pragma once
// k-nearest-neighbour and fixed-radius queries over a set of 3D points (nanoflann underneath).

#include <clustersurf/core/point_cloud.hpp>

#include <memory>
#include <vector>

namespace clustersurf {

/// A neighbour found by a query: point index and squared Euclidean distance.
struct Neighbor {
  std::uint32_t index;
  double distance_squared;
};

/// Static k-d tree over the rows of a Points matrix. The tree searches its own copy of the
/// points in Morton order (24 bytes a point), so that a query reads nearby memory; points() is
/// the caller's matrix, which must outlive the tree and not change. Queries are const and safe
/// to run concurrently. Results are sorted by distance, ties by index, so they never depend on
/// tree internals.
class KdTree {
 public:
  /// Builds the tree; `leaf_size` is the bucket size of the leaves (nanoflann's default is 10).
  explicit KdTree(const Points& points, int leaf_size = 10);
  ~KdTree();
  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;

  /// The min(k, size()) points nearest to `query`, nearest first.
  std::vector<Neighbor> knn(const Eigen::Vector3d& query, std::size_t k) const;
  /// Same as knn() but reuses `out` to avoid allocation in loops.
  void knn(const Eigen::Vector3d& query, std::size_t k, std::vector<Neighbor>& out) const;
  /// The min(k, size() − 1) points nearest to point `row` of points(), the point itself left
  /// out (its duplicates stay in, at distance 0), nearest first.
  void neighbors_of(Eigen::Index row, std::size_t k, std::vector<Neighbor>& out) const;
  /// All points within distance `radius` of `query` (inclusive), nearest first.
  std::vector<Neighbor> radius(const Eigen::Vector3d& query, double radius) const;
  /// Same set as radius(), into `out`, in the tree's traversal order (deterministic for a given
  /// tree, but not by distance): cheaper when the order does not matter.
  void radius_unsorted(const Eigen::Vector3d& query, double radius, std::vector<Neighbor>& out) const;

  std::size_t size() const noexcept;
  const Points& points() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clustersurf
