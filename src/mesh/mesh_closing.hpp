#pragma once
// What a closed mesh invented: the vertices the data does not support are marked, and filled
// patches wider than a limit are opened again (--fill-holes).

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/mesh/mesh_trim.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/surface/closed_surface.hpp>

#include <cstddef>

namespace clustersurf::detail {

/// Per vertex of a mesh of `closed`: 1 where the surface is filled in, not fitted (the blend
/// is undefined there, or, with `data`, the vertex lies beyond the trim's reach of the input
/// points), else 0.
Eigen::VectorXf filled_vertices(const TriangleMesh& mesh, const ClosedSurface& closed, const KdTree* data,
                                const TrimOptions& reach);

/// Removes every filled patch (triangles with a filled vertex, connected through shared
/// vertices) whose bounding-box diagonal exceeds `max_size`, with the vertices no triangle
/// uses any more; returns how many patches went. `filled` is the mesh's per-vertex mark.
std::size_t open_large_fills(TriangleMesh& mesh, const Eigen::VectorXf& filled, double max_size);

}  // namespace clustersurf::detail
