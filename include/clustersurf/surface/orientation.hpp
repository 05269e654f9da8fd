#pragma once
// Consistent orientation of the proxies: every node's Q is positive outside the surface
// by propagation between touching clusters, or by the input normals or scanner positions.

#include <clustersurf/cluster/cluster_tree.hpp>

namespace clustersurf {

/// What orient_tree() did.
struct OrientationReport {
  bool used_normals = false;   ///< oriented by the input normals
  bool used_scanners = false;  ///< oriented towards the scanners that saw the points
  std::size_t flipped = 0;     ///< nodes whose proxy was flipped
  std::size_t components = 0;  ///< connected groups of overlapping leaves (propagation only)
};

/// Flips proxies so that all agree on the outside. `cloud` is the tree's input.
/// With normals in `cloud` (and the tree's point-leaf table): each node follows the mean normal
/// of its points. Otherwise the orientation propagates over a minimum spanning tree of the
/// leaves weighted by 1 − |nᵢ·nⱼ| (Hoppe et al. 1992 on clusters): leaves are neighbours when
/// their clusters touch (k-nearest-neighbour point pairs; the proxies' gradients are compared
/// where they meet) or, without a point-leaf table, when their supports overlap. Each connected
/// component starts from the leaf reaching farthest in +x, whose outward side is certain.
/// Internal nodes then follow the point-weighted mean of their leaves' normals.
/// Without normals but with scanner positions (PointCloud::scanner_of_point), each node follows
/// the sum of its points' unit directions towards their scanners instead: a scanner sees the
/// outer side, so no propagation is needed.
/// Pass an empty cloud (or one without normals or scanners) to force propagation. Non-finite input normals
/// are ignored (each leaf follows the finite normals of its points).
OrientationReport orient_tree(ClusterTree& tree, const PointCloud& cloud);
/// The same with the cloud's shared index (its k-d tree is built once for every stage);
/// `use_normals` false orients by propagation even when the cloud has normals.
OrientationReport orient_tree(ClusterTree& tree, const CloudIndex& cloud, bool use_normals = true);

}  // namespace clustersurf
