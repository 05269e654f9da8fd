#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>

#include "mesh/mesh_components.hpp"

#include <Eigen/Geometry>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace clustersurf {

MeshTopology mesh_topology(const TriangleMesh& mesh) {
  MeshTopology t;
  t.vertices = static_cast<std::size_t>(mesh.vertices.rows());
  t.triangles = static_cast<std::size_t>(mesh.triangles.rows());
  if ((mesh.triangles.array() < 0).any() || (mesh.triangles.array() >= mesh.vertices.rows()).any())
    throw OptionError("mesh topology: a triangle refers to a vertex that does not exist");
  // Directed half-edges sorted by undirected key (lo, hi), then direction: grouped by lo with a
  // counting sort, each group (a vertex's few edges) then sorted. Equal half-edges are alike,
  // so this is the order of one sort of them all, in linear time.
  struct HalfEdge {
    std::int32_t lo, hi;
    bool forward;
  };
  std::vector<std::size_t> first(t.vertices + 1, 0);  // half-edges of lo = v: [first[v], first[v + 1])
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      ++first[static_cast<std::size_t>(std::min(mesh.triangles(f, k), mesh.triangles(f, (k + 1) % 3))) + 1];
  for (std::size_t v = 0; v < t.vertices; ++v) first[v + 1] += first[v];
  std::vector<HalfEdge> half(3 * t.triangles);
  std::vector<std::size_t> next(first.begin(), first.end() - 1);
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = mesh.triangles(f, k), b = mesh.triangles(f, (k + 1) % 3);
      half[next[static_cast<std::size_t>(std::min(a, b))]++] = {std::min(a, b), std::max(a, b), a < b};
    }
  // Each triangle's area and volume in parallel, summed in triangle order.
  std::vector<double> triangle_area(t.triangles), triangle_volume(t.triangles);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, mesh.triangles.rows(), 4096), [&](const auto& r) {
    for (Eigen::Index f = r.begin(); f != r.end(); ++f) {
      const Eigen::Vector3d p0 = mesh.vertices.row(mesh.triangles(f, 0)).transpose();
      const Eigen::Vector3d p1 = mesh.vertices.row(mesh.triangles(f, 1)).transpose();
      const Eigen::Vector3d p2 = mesh.vertices.row(mesh.triangles(f, 2)).transpose();
      triangle_volume[static_cast<std::size_t>(f)] = p0.dot(p1.cross(p2)) / 6.0;
      triangle_area[static_cast<std::size_t>(f)] = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    }
  });
  for (std::size_t f = 0; f < t.triangles; ++f) t.signed_volume += triangle_volume[f], t.area += triangle_area[f];
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, t.vertices, 4096), [&](const auto& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v)
      std::sort(half.begin() + static_cast<std::ptrdiff_t>(first[v]),
                half.begin() + static_cast<std::ptrdiff_t>(first[v + 1]), [](const HalfEdge& a, const HalfEdge& b) {
                  return a.hi < b.hi || (a.hi == b.hi && a.forward < b.forward);
                });
  });
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i;
    std::size_t forward = 0;
    while (j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi) forward += half[j++].forward;
    const std::size_t count = j - i;
    ++t.edges;
    if (count == 1) {
      ++t.boundary_edges;
      t.boundary_length += (mesh.vertices.row(half[i].hi) - mesh.vertices.row(half[i].lo)).norm();
    } else if (count > 2)
      ++t.non_manifold_edges;
    else if (forward != 1)
      ++t.inconsistent_edges;
    i = j;
  }
  t.euler_characteristic = static_cast<long>(t.vertices) - static_cast<long>(t.edges) + static_cast<long>(t.triangles);

  // Components: each names itself by one of its vertices.
  const std::vector<std::int32_t> component = detail::vertex_components(mesh);
  for (std::size_t v = 0; v < component.size(); ++v) t.components += component[v] == static_cast<std::int32_t>(v);
  std::vector<double> component_area(component.size(), 0.0);
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f)
    component_area[static_cast<std::size_t>(component[static_cast<std::size_t>(mesh.triangles(f, 0))])] +=
        triangle_area[static_cast<std::size_t>(f)];
  for (std::size_t v = 0; v < component.size(); ++v)
    t.small_components +=
        component[v] == static_cast<std::int32_t>(v) && component_area[v] < kSmallComponentShare * t.area;
  return t;
}

}  // namespace clustersurf
