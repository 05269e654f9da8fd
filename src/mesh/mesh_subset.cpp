// Sub-meshes that keep every per-vertex quantity of the vertices they keep.

#include "mesh/mesh_subset.hpp"

namespace clustersurf::detail {

TriangleMesh without_unused_vertices(const TriangleMesh& mesh) {
  const Eigen::Index nv = mesh.vertices.rows();
  std::vector<std::int32_t> remap(static_cast<std::size_t>(nv), -1);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) remap[static_cast<std::size_t>(mesh.triangles(t, k))] = 0;
  std::vector<Eigen::Index> rows;
  for (Eigen::Index v = 0; v < nv; ++v)
    if (remap[static_cast<std::size_t>(v)] == 0) remap[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(rows.size()), rows.push_back(v);
  TriangleMesh out;
  out.origin = mesh.origin;
  out.vertices = mesh.vertices(rows, Eigen::all);
  if (mesh.normals.rows() == nv) out.normals = mesh.normals(rows, Eigen::all);
  if (mesh.colors.rows() == nv) out.colors = mesh.colors(rows, Eigen::all);
  for (const PointAttribute& a : mesh.attributes)
    if (a.values.size() == nv) out.attributes.push_back({a.name, a.values(rows)});
  out.triangles.resize(mesh.triangles.rows(), 3);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) out.triangles(t, k) = remap[static_cast<std::size_t>(mesh.triangles(t, k))];
  return out;
}

TriangleMesh with_triangles(const TriangleMesh& mesh, const std::vector<std::uint8_t>& keep) {
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    if (keep[static_cast<std::size_t>(t)]) kept.push_back(t);
  TriangleMesh subset;
  subset.origin = mesh.origin;
  subset.vertices = mesh.vertices;  // shared arrays are cheap next to the walk that made them
  subset.normals = mesh.normals;
  subset.colors = mesh.colors;
  subset.attributes = mesh.attributes;
  subset.triangles = mesh.triangles(kept, Eigen::all);
  return without_unused_vertices(subset);
}

}  // namespace clustersurf::detail
