#pragma once
// Sub-meshes: some of a mesh's triangles, with only the vertices they use.

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf::detail {

/// `mesh` without the vertices no triangle uses: the others keep their order, normals, colors
/// and attributes, and the triangles are renumbered; the origin is kept.
TriangleMesh without_unused_vertices(const TriangleMesh& mesh);

/// The vertices of `mesh` that `triangles` (indices into them) use, in their order with every
/// per-vertex quantity, and those triangles renumbered; the origin is kept.
TriangleMesh with_new_triangles(const TriangleMesh& mesh, const Triangles& triangles);

/// `mesh` with only the triangles t whose keep[t] is set, without the vertices they leave
/// unused (as without_unused_vertices()).
TriangleMesh with_triangles(const TriangleMesh& mesh, const std::vector<std::uint8_t>& keep);

}  // namespace clustersurf::detail
