#pragma once
// Per-vertex colors: the input's own (from a scan's RGB), or ones that show how a mesh relates to
// the tree and to the input.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/surface/implicit_surface.hpp>
#include <clustersurf/surface/palette.hpp>

namespace clustersurf {

/// Input points whose colors blend into each vertex's (colors_from_points()).
inline constexpr std::size_t kColorNeighbors = 8;

/// The colors of `points` carried onto the mesh: each vertex gets, channel by channel, the
/// median of the colors of its `neighbors` nearest points weighted by exp(-(d / d_k)^2) (d the
/// point's distance, d_k the farthest neighbour's), so a stray point among them changes nothing
/// and a border between two colors stays as sharp as the points draw it. `colors` has one row
/// per point of `points` (the k-d tree's), else OptionError. Deterministic for any thread count.
Colors colors_from_points(const TriangleMesh& mesh, const KdTree& points, const Colors& colors,
                          std::size_t neighbors = kColorNeighbors);

/// Scanner intensities as grey: black at their 1st percentile, white at their 99th, linear in
/// between and clamped (so a few saturated returns do not darken the rest); mid grey when they
/// are all equal. Non-finite values are black.
Colors intensity_grey(const Eigen::VectorXf& intensity);

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
