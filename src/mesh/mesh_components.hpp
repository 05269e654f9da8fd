#pragma once
// Connected components of a triangle mesh's vertices.

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf::detail {

/// For every vertex of `mesh`, the component it belongs to (triangles sharing a vertex are
/// connected), named by one of its vertices, the same for every vertex of the component; -1 for
/// a vertex no counted triangle uses. Only the triangles t with keep[t] count (all of them
/// when `keep` is null).
std::vector<std::int32_t> vertex_components(const TriangleMesh& mesh, const std::vector<std::uint8_t>* keep = nullptr);

/// How many components vertex_components() finds among all of the mesh's triangles.
std::size_t component_count(const TriangleMesh& mesh);

}  // namespace clustersurf::detail
