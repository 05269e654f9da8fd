// Connected components by union-find over the vertices the triangles join.

#include "mesh/mesh_components.hpp"

#include <numeric>

namespace clustersurf::detail {

std::vector<std::int32_t> vertex_components(const TriangleMesh& mesh, const std::vector<std::uint8_t>* keep) {
  const auto nv = static_cast<std::size_t>(mesh.vertices.rows());
  std::vector<std::int32_t> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&parent](std::int32_t v) {  // path halving
    while (parent[static_cast<std::size_t>(v)] != v) {
      parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
      v = parent[static_cast<std::size_t>(v)];
    }
    return v;
  };
  std::vector<std::uint8_t> used(nv, 0);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    if (keep != nullptr && !(*keep)[static_cast<std::size_t>(t)]) continue;
    const std::int32_t r0 = find(mesh.triangles(t, 0));
    for (int k = 0; k < 3; ++k) {
      used[static_cast<std::size_t>(mesh.triangles(t, k))] = 1;
      const std::int32_t r = find(mesh.triangles(t, k));
      if (r != r0) parent[static_cast<std::size_t>(r)] = r0;
    }
  }
  std::vector<std::int32_t> component(nv, -1);
  for (std::size_t v = 0; v < nv; ++v)
    if (used[v]) component[v] = find(static_cast<std::int32_t>(v));
  return component;
}

std::size_t component_count(const TriangleMesh& mesh) {
  const std::vector<std::int32_t> component = vertex_components(mesh);
  std::size_t count = 0;
  for (std::size_t v = 0; v < component.size(); ++v) count += component[v] == static_cast<std::int32_t>(v);
  return count;
}

}  // namespace clustersurf::detail
