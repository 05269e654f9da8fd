// The tiles of a tiled mesh welded into one, and the trim's fragment test over the whole.

#include "tiling/tiles.hpp"
#include <clustersurf/core/errors.hpp>

#include "mesh/mesh_components.hpp"
#include "mesh/mesh_subset.hpp"
#include "spatial/position_ids.hpp"

#include <algorithm>

namespace clustersurf {

TriangleMesh join_tiles(std::span<const MeshTile> tiles, const TrimOptions& trim) {
  std::vector<const MeshTile*> order;
  Eigen::Index vertices = 0, triangles = 0;
  for (const MeshTile& tile : tiles) {
    const TriangleMesh& m = tile.mesh;
    if (m.attributes.size() != 1 || m.attributes[0].name != "votes" ||
        m.attributes[0].values.size() != m.vertices.rows() || m.normals.rows() != m.vertices.rows())
      throw OptionError("a mesh tile must carry a normal and a \"votes\" value per vertex");
    order.push_back(&tile);
    vertices += m.vertices.rows();
    triangles += m.triangles.rows();
  }
  std::stable_sort(order.begin(), order.end(),
                   [](const MeshTile* a, const MeshTile* b) { return a->region < b->region; });
  TriangleMesh mesh;
  if (!order.empty()) mesh.origin = order.front()->mesh.origin, mesh.up = order.front()->mesh.up;
  mesh.vertices.resize(vertices, 3);
  mesh.normals.resize(vertices, 3);
  const bool colors =
      std::any_of(order.begin(), order.end(), [](const MeshTile* t) { return t->mesh.colors.rows() > 0; });
  if (colors) mesh.colors.setConstant(vertices, 3, 128);  // grey for a tile without colors
  mesh.triangles.resize(triangles, 3);
  Eigen::VectorXf votes(vertices);
  Eigen::Index v0 = 0, t0 = 0;
  for (const MeshTile* tile : order) {
    const TriangleMesh& m = tile->mesh;
    if (m.origin != mesh.origin) throw OptionError("the mesh tiles are not of one tree (their origins differ)");
    mesh.vertices.middleRows(v0, m.vertices.rows()) = m.vertices;
    mesh.normals.middleRows(v0, m.vertices.rows()) = m.normals;
    if (colors && m.colors.rows() == m.vertices.rows()) mesh.colors.middleRows(v0, m.vertices.rows()) = m.colors;
    votes.segment(v0, m.vertices.rows()) = m.attributes[0].values;
    mesh.triangles.middleRows(t0, m.triangles.rows()) = m.triangles.array() + static_cast<std::int32_t>(v0);
    v0 += m.vertices.rows();
    t0 += m.triangles.rows();
  }
  // Weld: a vertex on a tile border is the same double-precision point in both tiles.
  const std::vector<std::int32_t> same = detail::position_ids(mesh.vertices);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) mesh.triangles(t, k) = same[static_cast<std::size_t>(mesh.triangles(t, k))];
  Eigen::VectorXf welded_votes = Eigen::VectorXf::Zero(vertices);
  for (Eigen::Index v = 0; v < vertices; ++v) welded_votes(same[static_cast<std::size_t>(v)]) += votes(v);

  // The fragment test of trim_to_points(): a component holding fewer votes than
  // min_component_points (or than the best-supported one) goes.
  std::vector<std::uint8_t> keep(static_cast<std::size_t>(mesh.triangles.rows()), 1);
  if (trim.min_component_points > 0 && !keep.empty()) {
    const std::vector<std::int32_t> component = detail::vertex_components(mesh, &keep);
    std::vector<double> support(component.size(), 0);
    for (std::size_t v = 0; v < component.size(); ++v)
      if (component[v] >= 0)
        support[static_cast<std::size_t>(component[v])] += welded_votes(static_cast<Eigen::Index>(v));
    const double best = *std::max_element(support.begin(), support.end());
    const double needed = std::min(static_cast<double>(trim.min_component_points), best);
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
      keep[static_cast<std::size_t>(t)] =
          support[static_cast<std::size_t>(component[static_cast<std::size_t>(mesh.triangles(t, 0))])] >= needed;
  }
  return detail::with_triangles(mesh, keep);
}

}  // namespace clustersurf
