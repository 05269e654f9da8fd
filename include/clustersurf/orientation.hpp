#pragma once
// Consistent orientation of the proxies: every node's Q is positive outside the surface
// (METHOD.md "Support spheres and blending").

#include <clustersurf/cluster_tree.hpp>

namespace clustersurf {

/// What orient_tree() did.
struct OrientationReport {
  bool used_normals = false;     ///< oriented by the input normals (else by propagation)
  std::size_t flipped = 0;       ///< nodes whose proxy was flipped
  std::size_t components = 0;    ///< connected groups of overlapping leaves (propagation only)
};

/// Flips proxies so that all agree on the outside. With `cloud` normals and the tree's
/// point-leaf table: each node follows the mean normal of its points. Otherwise: a minimum
/// spanning tree over leaves with overlapping supports, weighted by 1 − |nᵢ·nⱼ| (plus a
/// penalty for neighbours stacked along their normals, i.e. opposite sides of thin parts),
/// propagates from the leaf holding the extreme point of each component, whose outward side is
/// certain. Internal nodes then follow the point-weighted mean of their leaves' normals.
OrientationReport orient_tree(ClusterTree& tree, const PointCloud& cloud);

}  // namespace clustersurf
