#pragma once
// Removing a mesh's self-intersections by local smoothing.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/mesh/mesh_check.hpp>

#include <cstddef>

namespace clustersurf::detail {

/// What untangle() did.
struct UntangleReport {
  std::size_t intersections_before = 0;  ///< intersecting triangle pairs found first
  SelfIntersections remaining;           ///< the last search: what is left (all pairs listed)
  std::size_t moved_vertices = 0;        ///< vertex moves over all rounds
};

/// Moves the vertices of self-intersecting triangles (find_self_intersections()) to the mean of
/// their neighbours, a round at a time, until none intersect or `max_rounds` have run. The folds
/// the mesher leaves (Newton steps that pull two close vertices across each other, the seam of
/// a closed mesh's fill) are a cell wide, so a round or two of such local smoothing unfolds
/// them, moving each vertex by a fraction of a cell. Connectivity is unchanged. Deterministic.
UntangleReport untangle(TriangleMesh& mesh, std::size_t max_rounds = 8);

}  // namespace clustersurf::detail
