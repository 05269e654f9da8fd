#pragma once
// The two ways to split a cluster in two (thesis 3.2). Both reorder the cluster's index range
// so that the first k indices form one child and return k, or 0 when no split leaves both
// children with at least options.min_points points.

#include <clustersurf/cluster/cluster_tree.hpp>

#include <span>

namespace clustersurf::detail {

/// Result of 2-means clustering with point proxies.
struct TwoMeans {
  Eigen::Vector3d centers[2];
  std::size_t sizes[2] = {0, 0};
  std::vector<std::uint8_t> labels;  ///< per position in the range
  double energy = 0;                 ///< E² = Σ |p − center(label)|², thesis eq. 3.3
};

/// Lloyd iterations from the given seeds until no point changes side (at most `max_rounds`).
TwoMeans two_means(const Points& points, std::span<const std::uint32_t> range, const Eigen::Vector3d& seed0,
                   const Eigen::Vector3d& seed1, int max_rounds = 50);

/// Split-plane clustering (thesis 3.2.3): 2-means direction, sort along it, sweep the split
/// index scoring max(e+, e−) with O(1) moment fits in the parent's frame. `noise` (the
/// estimated scanner noise, or 0) is discounted from the scores; near-ties go to the most
/// balanced split.
std::size_t split_plane(const Points& points, std::span<std::uint32_t> range, const Frame& parent_frame,
                        const BuildOptions& options, double noise);

/// Lloyd 2-means with point proxies (farthest-point seeding, then k-means++ restarts; lowest
/// E² wins), optionally refined by proxy-Lloyd rounds; children below min_points are topped
/// up with the nearest points of the other side.
std::size_t lloyd_split(const Points& points, std::span<std::uint32_t> range, const BuildOptions& options,
                        std::uint64_t node_seed);

/// Splits a cluster made of two parts far apart: along the frame's first axis (largest
/// spread), at the widest empty slab between consecutive points, when that slab is wider than
/// either side's extent along the axis and both sides keep min_points (a smaller side — stray
/// points — only across a gap 8 times wider than either side). Returns k as the other
/// splitters, or 0 when there is no such gap. A proxy fitted across such a gap can meet an
/// error threshold that scales with the model's size while describing neither part.
std::size_t split_at_gap(const Points& points, std::span<std::uint32_t> range, const Frame& frame,
                         std::uint32_t min_points);

/// Splits a cluster whose points form two groups apart: the longest edge of their minimum
/// spanning tree is cut when it is more than kLinkageGapRatio times longer than every edge
/// left within either group (a gap, not a sparser stretch of one surface) and each group keeps
/// `min_side` points. Points of two parts of the model that a sparse sample leaves a few
/// spacings apart (two legs) fall in one cluster that no smooth proxy fits. Returns k as the
/// other splitters (the first group first), or 0. Quadratic in the cluster's size: for leaves.
std::size_t split_at_linkage_gap(const Points& points, std::span<std::uint32_t> range, std::size_t min_side);

/// Splits a cluster whose points lie on two sheets facing apart (normals.row(ids[row]) falls
/// into two groups by 2-means whose means are more than 90 degrees apart: both sides of a thin
/// part, the faces of a deep fold): the rows of each group become one child, each with at least
/// `min_side` points, when the groups' mean heights along the axis between their normals
/// differ by more than three standard errors (`points`, rows as `range`) or the smaller holds
/// a third of the points, more than a scanner's orientation errors (up to 10 % of the normals
/// flipped) give a cluster of its size once in 10,000. Returns k as the other splitters, or 0
/// when the normals form one group or the few turned ones lie among the others. One
/// proxy fitted across two such sheets describes neither and points the wrong way on one.
std::size_t split_two_sheets(const Points& points, const Points& normals, std::span<const std::uint32_t> ids,
                             std::span<std::uint32_t> range, std::size_t min_side);

}  // namespace clustersurf::detail
