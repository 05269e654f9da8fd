// Sub-meshes that keep every per-vertex quantity of the vertices they keep.

#include "mesh/mesh_subset.hpp"

namespace clustersurf::detail {

namespace {

/// The vertices of `mesh` that `triangles` (indices into them) use, with those triangles.
TriangleMesh compact(const TriangleMesh& mesh, const Triangles& triangles) {
  const Eigen::Index nv = mesh.vertices.rows();
  std::vector<std::int32_t> remap(static_cast<std::size_t>(nv), -1);
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) remap[static_cast<std::size_t>(triangles(t, k))] = 0;
  std::vector<Eigen::Index> rows;
  for (Eigen::Index v = 0; v < nv; ++v)
    if (remap[static_cast<std::size_t>(v)] == 0)
      remap[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(rows.size()), rows.push_back(v);
  TriangleMesh out;
  out.origin = mesh.origin;
  out.up = mesh.up;
  out.vertices = mesh.vertices(rows, Eigen::all);
  if (mesh.normals.rows() == nv) out.normals = mesh.normals(rows, Eigen::all);
  if (mesh.colors.rows() == nv) out.colors = mesh.colors(rows, Eigen::all);
  for (const PointAttribute& a : mesh.attributes)
    if (a.values.size() == nv) out.attributes.push_back({a.name, a.values(rows)});
  out.triangles.resize(triangles.rows(), 3);
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) out.triangles(t, k) = remap[static_cast<std::size_t>(triangles(t, k))];
  return out;
}

}  // namespace

TriangleMesh without_unused_vertices(const TriangleMesh& mesh) { return compact(mesh, mesh.triangles); }

TriangleMesh with_triangles(const TriangleMesh& mesh, const std::vector<std::uint8_t>& keep) {
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    if (keep[static_cast<std::size_t>(t)]) kept.push_back(t);
  return compact(mesh, mesh.triangles(kept, Eigen::all));
}

}  // namespace clustersurf::detail
