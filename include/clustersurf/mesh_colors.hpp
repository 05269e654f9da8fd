#pragma once
// Per-vertex colors that show how a mesh relates to the tree and to the input.

#include <clustersurf/implicit_surface.hpp>
#include <clustersurf/kd_tree.hpp>
#include <clustersurf/palette.hpp>
#include <clustersurf/point_cloud.hpp>

namespace clustersurf {

/// A color per blended node (hashed from its index: neighbours almost always differ),
/// given to each vertex by the node of largest weight there.
Colors colors_by_node(const TriangleMesh& mesh, const ImplicitSurface& surface);

/// Green (0) → yellow → red (≥ max_distance) by the distance from each vertex to the nearest
/// point of `points`. Also returns the distances when `distances` is given.
Colors colors_by_distance(const TriangleMesh& mesh, const Points& points, double max_distance,
                          std::vector<double>* distances = nullptr);
/// The same with the points' k-d tree given (`points`, over the points).
Colors colors_by_distance(const TriangleMesh& mesh, const KdTree& points, double max_distance,
                          std::vector<double>* distances = nullptr);

}  // namespace clustersurf
