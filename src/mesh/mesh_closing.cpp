// Marking what a closed mesh filled in, and opening the fills wider than a limit.

#include "mesh/mesh_closing.hpp"

#include "mesh/data_reach.hpp"
#include "mesh/mesh_components.hpp"
#include "mesh/mesh_subset.hpp"

#include <tbb/parallel_for.h>

#include <map>
#include <vector>

namespace clustersurf::detail {

Eigen::VectorXf filled_vertices(const TriangleMesh& mesh, const ClosedSurface& closed, const KdTree* data,
                                const TrimOptions& reach) {
  const Eigen::Index nv = mesh.vertices.rows();
  Eigen::VectorXf filled(nv);
  tbb::parallel_for(Eigen::Index{0}, nv,
                    [&](Eigen::Index v) { filled(v) = closed.filled(mesh.vertices.row(v).transpose()) ? 1.0f : 0.0f; });
  if (data != nullptr && data->size() > reach.neighbors && reach.spread_factor > 0) {
    const std::vector<std::uint8_t> near = vertices_near_data(mesh, *data, reach);
    for (Eigen::Index v = 0; v < nv; ++v)
      if (!near[static_cast<std::size_t>(v)]) filled(v) = 1.0f;
  }
  return filled;
}

std::size_t open_large_fills(TriangleMesh& mesh, const Eigen::VectorXf& filled, double max_size) {
  const Eigen::Index nt = mesh.triangles.rows();
  std::vector<std::uint8_t> in_fill(static_cast<std::size_t>(nt), 0);
  for (Eigen::Index t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      if (filled(mesh.triangles(t, k)) > 0) in_fill[static_cast<std::size_t>(t)] = 1;
  const std::vector<std::int32_t> patch = vertex_components(mesh, &in_fill);
  // Each patch's bounding box, over the vertices of its triangles.
  std::map<std::int32_t, BoundingBox> boxes;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    if (patch[static_cast<std::size_t>(v)] >= 0)
      boxes[patch[static_cast<std::size_t>(v)]].extend(mesh.vertices.row(v).transpose());
  std::size_t opened = 0;
  std::vector<std::uint8_t> drop_patch_of(static_cast<std::size_t>(mesh.vertices.rows()), 0);
  for (const auto& [id, box] : boxes)
    if (box.diagonal() > max_size) {
      ++opened;
      drop_patch_of[static_cast<std::size_t>(id)] = 1;
    }
  if (opened == 0) return 0;
  std::vector<std::uint8_t> keep(static_cast<std::size_t>(nt), 1);
  for (Eigen::Index t = 0; t < nt; ++t)
    if (in_fill[static_cast<std::size_t>(t)] &&
        drop_patch_of[static_cast<std::size_t>(patch[static_cast<std::size_t>(mesh.triangles(t, 0))])])
      keep[static_cast<std::size_t>(t)] = 0;
  mesh = with_triangles(mesh, keep);
  return opened;
}

}  // namespace clustersurf::detail
