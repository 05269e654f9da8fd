// untangle(): umbrella smoothing restricted to the vertices of intersecting triangles.

#include "mesh/mesh_untangle.hpp"

#include <algorithm>
#include <vector>

namespace clustersurf::detail {

UntangleReport untangle(TriangleMesh& mesh, std::size_t max_rounds) {
  UntangleReport report;
  MeshCheckOptions all;
  all.max_pairs = static_cast<std::size_t>(mesh.triangles.rows()) * 8 + 8;  // list every pair
  const auto nv = static_cast<std::size_t>(mesh.vertices.rows());
  // Each vertex's neighbours (the other corners of its triangles), sorted and unique.
  std::vector<std::vector<std::int32_t>> neighbours(nv);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l)
        if (k != l) neighbours[static_cast<std::size_t>(mesh.triangles(t, k))].push_back(mesh.triangles(t, l));
  for (auto& n : neighbours) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  for (std::size_t round = 0;; ++round) {
    report.remaining = find_self_intersections(mesh, all);
    const SelfIntersections& found = report.remaining;
    if (round == 0) report.intersections_before = found.count;
    if (found.count == 0 || round == max_rounds) break;
    std::vector<std::int32_t> moving;
    for (const auto& [a, b] : found.pairs)
      for (const std::int32_t t : {a, b})
        for (int k = 0; k < 3; ++k) moving.push_back(mesh.triangles(t, k));
    std::sort(moving.begin(), moving.end());
    moving.erase(std::unique(moving.begin(), moving.end()), moving.end());
    std::vector<Eigen::RowVector3d> target(moving.size());
    for (std::size_t i = 0; i < moving.size(); ++i) {
      Eigen::RowVector3d mean = Eigen::RowVector3d::Zero();
      const auto& n = neighbours[static_cast<std::size_t>(moving[i])];
      for (const std::int32_t v : n) mean += mesh.vertices.row(v);
      target[i] = n.empty() ? Eigen::RowVector3d(mesh.vertices.row(moving[i]))
                            : Eigen::RowVector3d(mean / static_cast<double>(n.size()));
    }
    for (std::size_t i = 0; i < moving.size(); ++i) mesh.vertices.row(moving[i]) = target[i];
    report.moved_vertices += moving.size();
  }
  return report;
}

}  // namespace clustersurf::detail
