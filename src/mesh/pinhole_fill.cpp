// Pinhole closing (see pinhole_fill.hpp).

#include "mesh/pinhole_fill.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace clustersurf::detail {

namespace {

std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b)), hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

/// The boundary loops of `mesh`, each as its vertices in the order of its triangles' winding,
/// skipping any loop that meets a vertex with more than one boundary edge leaving it.
std::vector<std::vector<std::int32_t>> simple_boundary_loops(const TriangleMesh& mesh) {
  std::unordered_map<std::uint64_t, int> uses;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) ++uses[edge_key(mesh.triangles(t, k), mesh.triangles(t, (k + 1) % 3))];
  const auto nv = static_cast<std::size_t>(mesh.vertices.rows());
  std::vector<std::int32_t> next(nv, -1);
  std::vector<std::uint8_t> branching(nv, 0);
  std::vector<std::int32_t> starts;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = mesh.triangles(t, k), b = mesh.triangles(t, (k + 1) % 3);
      if (uses[edge_key(a, b)] != 1) continue;
      if (next[static_cast<std::size_t>(a)] >= 0) branching[static_cast<std::size_t>(a)] = 1;
      next[static_cast<std::size_t>(a)] = b;
      starts.push_back(a);
    }
  std::sort(starts.begin(), starts.end());
  std::vector<std::uint8_t> visited(nv, 0);
  std::vector<std::vector<std::int32_t>> loops;
  for (const std::int32_t start : starts) {
    if (visited[static_cast<std::size_t>(start)]) continue;
    std::vector<std::int32_t> loop;
    bool simple = true;
    std::int32_t v = start;
    while (v >= 0 && !visited[static_cast<std::size_t>(v)]) {
      visited[static_cast<std::size_t>(v)] = 1;
      simple = simple && !branching[static_cast<std::size_t>(v)];
      loop.push_back(v);
      v = next[static_cast<std::size_t>(v)];
    }
    if (simple && v == start && loop.size() >= 3) loops.push_back(std::move(loop));
  }
  return loops;
}

}  // namespace

std::size_t close_pinholes(TriangleMesh& mesh, const KdTree& index, double spread_factor, std::size_t neighbors,
                           double max_spreads) {
  if (index.size() <= neighbors || mesh.triangles.rows() == 0) return 0;
  const bool with_normals = mesh.normals.rows() == mesh.vertices.rows();
  const bool with_colors = mesh.colors.rows() == mesh.vertices.rows();
  std::vector<Eigen::Vector3d> centers;
  std::vector<std::vector<std::int32_t>> closed;
  std::vector<Neighbor> nearest, around;
  for (auto& loop : simple_boundary_loops(mesh)) {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    for (auto v : loop) center += mesh.vertices.row(v).transpose();
    center /= static_cast<double>(loop.size());
    index.knn(center, 1, nearest);
    index.neighbors_of(nearest[0].index, neighbors, around);
    double spread = 0;
    for (const auto& q : around) spread += std::sqrt(q.distance_squared);
    spread /= static_cast<double>(around.size());
    if (!(std::sqrt(nearest[0].distance_squared) <= spread_factor * spread)) continue;  // no data inside: a real hole
    double radius = 0;
    for (auto v : loop) radius = std::max(radius, (mesh.vertices.row(v).transpose() - center).norm());
    if (!(radius <= max_spreads * spread)) continue;
    centers.push_back(center);
    closed.push_back(std::move(loop));
  }
  if (closed.empty()) return 0;
  Eigen::Index v_next = mesh.vertices.rows(), t_next = mesh.triangles.rows();
  std::size_t fan_triangles = 0;
  for (const auto& loop : closed) fan_triangles += loop.size();
  mesh.vertices.conservativeResize(v_next + static_cast<Eigen::Index>(closed.size()), 3);
  if (with_normals) mesh.normals.conservativeResize(mesh.vertices.rows(), 3);
  if (with_colors) mesh.colors.conservativeResize(mesh.vertices.rows(), 3);
  for (PointAttribute& a : mesh.attributes) {
    // A fan's centre is new, like its loop's vertices: it takes their mean.
    const Eigen::Index old_rows = a.values.size();
    a.values.conservativeResize(mesh.vertices.rows());
    for (std::size_t h = 0; h < closed.size(); ++h) {
      float sum = 0;
      for (auto v : closed[h]) sum += a.values(v);
      a.values(old_rows + static_cast<Eigen::Index>(h)) = sum / static_cast<float>(closed[h].size());
    }
  }
  mesh.triangles.conservativeResize(t_next + static_cast<Eigen::Index>(fan_triangles), 3);
  for (std::size_t h = 0; h < closed.size(); ++h, ++v_next) {
    const auto& loop = closed[h];
    mesh.vertices.row(v_next) = centers[h].transpose();
    if (with_normals) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      for (auto v : loop) n += mesh.normals.row(v).transpose();
      mesh.normals.row(v_next) =
          n.norm() > 0 ? Eigen::RowVector3d(n.normalized().transpose()) : Eigen::RowVector3d::Zero();
    }
    if (with_colors) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (auto v : loop) c += mesh.colors.row(v).cast<double>().transpose();
      mesh.colors.row(v_next) = (c / static_cast<double>(loop.size())).array().round().cast<std::uint8_t>().transpose();
    }
    // The loop runs along its triangles' winding (a → b); the fan crosses each edge back.
    for (std::size_t k = 0; k < loop.size(); ++k, ++t_next)
      mesh.triangles.row(t_next) << loop[(k + 1) % loop.size()], loop[k], static_cast<std::int32_t>(v_next);
  }
  return closed.size();
}

}  // namespace clustersurf::detail
