#pragma once
// Closing a mesh's pinholes: boundary loops the input points cover (see close_pinholes()).

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <cstddef>

namespace clustersurf::detail {

/// Closes, with a fan around its centroid, every boundary loop of `mesh` (a simple loop: no
/// vertex on it twice, none with two boundary edges leaving it) whose centroid lies within
/// `spread_factor` × the local spread of the data (`index` over the input points; the spread of
/// a point is its mean distance to its `neighbors` nearest ones) and whose vertices lie within
/// `max_spreads` spreads of the centroid: the data is there, so the hole is the mesher's, not
/// the scan's. The fans face like the triangles around them; the centroid gets the loop's mean
/// normal and color. Returns how many loops were closed.
std::size_t close_pinholes(TriangleMesh& mesh, const KdTree& index, double spread_factor, std::size_t neighbors,
                           double max_spreads);

}  // namespace clustersurf::detail
