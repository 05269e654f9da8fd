// Dropping the triangles that reach beyond the input points.

#include <clustersurf/errors.hpp>
#include <clustersurf/kd_tree.hpp>
#include <clustersurf/mesh_trim.hpp>

#include <tbb/parallel_for.h>

#include <cmath>
#include <vector>

namespace clustersurf {

TriangleMesh trim_to_points(const TriangleMesh& mesh, const Points& points, const TrimOptions& options, TrimReport* report) {
  if (!(options.spread_factor >= 0) || !std::isfinite(options.spread_factor))
    throw OptionError("mesh trim: the spread factor must be finite and >= 0 (0 keeps every triangle)");
  if (options.neighbors < 1) throw OptionError("mesh trim: neighbors must be at least 1");
  if (report != nullptr) *report = {};
  if (options.spread_factor == 0 || points.rows() <= static_cast<Eigen::Index>(options.neighbors) || mesh.triangles.rows() == 0)
    return mesh;

  // The nearest input point of every vertex, then the spread of each such point (once per
  // point: many vertices share one), then which vertices are within reach of the data.
  const KdTree index(points);
  const Eigen::Index nv = mesh.vertices.rows();
  std::vector<Neighbor> nearest(static_cast<std::size_t>(nv));
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, nv, 512), [&](const auto& r) {
    std::vector<Neighbor> nb;
    for (Eigen::Index v = r.begin(); v != r.end(); ++v) {
      index.knn(mesh.vertices.row(v).transpose(), 1, nb);
      nearest[static_cast<std::size_t>(v)] = nb[0];
    }
  });
  std::vector<double> spread(static_cast<std::size_t>(points.rows()), -1);
  std::vector<std::uint32_t> used;
  for (const auto& n : nearest)
    if (spread[n.index] < 0) spread[n.index] = 0, used.push_back(n.index);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, used.size(), 256), [&](const auto& r) {
    std::vector<Neighbor> around;
    for (std::size_t u = r.begin(); u != r.end(); ++u) {
      index.neighbors_of(used[u], options.neighbors, around);
      double sum = 0;
      for (const auto& q : around) sum += std::sqrt(q.distance_squared);
      spread[used[u]] = sum / static_cast<double>(around.size());
    }
  });
  std::vector<std::uint8_t> near(static_cast<std::size_t>(nv));
  for (std::size_t v = 0; v < near.size(); ++v)
    near[v] = std::sqrt(nearest[v].distance_squared) <= options.spread_factor * spread[nearest[v].index];

  // Keep the triangles whose three vertices are near, then the vertices they use.
  std::vector<Eigen::Index> kept_triangles;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const auto tri = mesh.triangles.row(t);
    if (near[static_cast<std::size_t>(tri(0))] && near[static_cast<std::size_t>(tri(1))] && near[static_cast<std::size_t>(tri(2))])
      kept_triangles.push_back(t);
  }
  std::vector<std::int32_t> remap(static_cast<std::size_t>(nv), -1);
  for (auto t : kept_triangles)
    for (int k = 0; k < 3; ++k) remap[static_cast<std::size_t>(mesh.triangles(t, k))] = 0;
  std::vector<Eigen::Index> kept_vertices;
  for (Eigen::Index v = 0; v < nv; ++v)
    if (remap[static_cast<std::size_t>(v)] == 0) {
      remap[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(kept_vertices.size());
      kept_vertices.push_back(v);
    }

  TriangleMesh out;
  out.vertices = mesh.vertices(kept_vertices, Eigen::all);
  if (mesh.normals.rows() == nv) out.normals = mesh.normals(kept_vertices, Eigen::all);
  if (mesh.colors.rows() == nv) out.colors = mesh.colors(kept_vertices, Eigen::all);
  out.triangles.resize(static_cast<Eigen::Index>(kept_triangles.size()), 3);
  for (std::size_t t = 0; t < kept_triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      out.triangles(static_cast<Eigen::Index>(t), k) = remap[static_cast<std::size_t>(mesh.triangles(kept_triangles[t], k))];
  if (report != nullptr) {
    report->removed_triangles = static_cast<std::size_t>(mesh.triangles.rows()) - kept_triangles.size();
    report->removed_vertices = static_cast<std::size_t>(nv) - kept_vertices.size();
  }
  return out;
}

}  // namespace clustersurf
