#pragma once
// The proxy patches of the interactive viewer (write_viewer_html()).

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/point_cloud.hpp>

#include <cstddef>
#include <vector>

namespace clustersurf::detail {

/// Per node, 16 floats: its patch frame's origin relative to the page's center and its axes
/// e1, e2, e3 (3 each), then the extent [umin, umax] × [vmin, vmax] of its cluster's points in
/// that frame (without points: a square of half its support radius); all 0 for a node without
/// a patch (a point proxy, or no extent). And per node a g × g grid of its proxy's heights
/// above the frame's plane over that extent, NaN where it has none within its support radius.
struct PatchGrid {
  std::vector<float> frames;
  std::vector<float> heights;
};

/// The patches of every node of `tree`; `cloud`, when given, the tree's input (its points give
/// the extents). Thread-parallel; the result does not depend on the thread count.
PatchGrid patch_grid(const ClusterTree& tree, const PointCloud* cloud, const Eigen::Vector3d& center, std::size_t g);

}  // namespace clustersurf::detail
