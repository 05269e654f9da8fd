#pragma once
// What the tree builder's passes share: the working copy of the points in cluster order, the
// nodes under construction, and the error a test over n points allows.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/cluster/noise.hpp>
#include <clustersurf/cluster/noise_field.hpp>

#include <cmath>
#include <cstdint>
#include <memory>
#include <numeric>
#include <span>
#include <vector>

namespace clustersurf::detail {

/// The noise, as a share of the point spacing, from which it counts as the points' own: below
/// it the noise estimate of a clean sample reads the facets and detail its fits miss, which do
/// not vary independently from point to point (support_alpha() starts widening the supports
/// there; build_nodes() tests the leaves' bias against it from there).
inline constexpr double kNoiseCountsShare = 0.15;

/// The error a test over n points allows: the tolerance plus the noise with its margin
/// (noise_variance_margin()), so a cluster or a support is not split or shrunk for noise alone.
inline double allowed_error(double tolerance, double noise, double n) {
  return std::sqrt(tolerance * tolerance + noise * noise * noise_variance_margin(n));
}

/// A node under construction: its cluster's rows start at `begin` in the working set.
struct BuildNode {
  ClusterNode node;
  std::uint32_t begin = 0;
  std::unique_ptr<BuildNode> left, right;
};

/// The points in cluster order: every cluster's points are contiguous rows, so the passes over
/// a cluster read memory sequentially instead of gathering from the whole input.
struct WorkingSet {
  Points positions;                  // positions[j] = input.positions[ids[j]]
  std::vector<std::uint32_t> ids;    // input index of each row
  std::vector<std::uint32_t> local;  // the splitters' index ranges; local[j] == j between splits

  /// Moves rows [begin, begin + order.size()) into the order a splitter left in `order`
  /// (a permutation of those rows), and makes `order` the identity again.
  void apply(std::uint32_t begin, std::span<std::uint32_t> order);
};

/// What a build measures over the whole cloud: the clustered points' box (the relative
/// tolerance is a fraction of its diagonal), the median point spacing and the noise estimate
/// (used by the Auto threshold). A region of a larger cloud is built with its cloud's.
struct BuildScale {
  BoundingBox bbox;
  double point_spacing = 0;
  double noise_sigma = 0;
  /// The noise over the surface (empty: noise_sigma everywhere); a cluster keeps its local
  /// noise, from noise_sigma up to kMaxLocalNoise times it.
  const NoiseField* noise_field = nullptr;
};

/// The tree of the rows `ids` of `cloud` (their positions: `clustered`, in that order): the
/// recursion, the flattening and the point-leaf table of build_cluster_tree(), at the given
/// scale, with the support checks over `support_points` (indexed by `support_index`: the
/// clustered points, or those and their region's halo; `support_normals`: their input normals,
/// or null). The tree's bbox is that of `clustered`.
ClusterTree build_tree(const PointCloud& cloud, std::vector<std::uint32_t> ids, const Points& clustered,
                       const Points& support_points, const Points* support_normals, const KdTree& support_index,
                       const BuildScale& scale, const BuildOptions& options, const ProgressCallback& progress);

/// Smallest sphere containing spheres a and b (padded so rounding never leaves one outside).
Sphere enclose(const Sphere& a, const Sphere& b);

/// Appends the subtree of `root` to tree.nodes in depth-first pre-order (children after their
/// parent, child indices set). With `leaf_begin`, also appends each node's first working row.
void flatten(BuildNode& root, ClusterTree& tree, std::vector<std::uint32_t>* leaf_begin);

}  // namespace clustersurf::detail
