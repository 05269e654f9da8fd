#include <clustersurf/mesh/mesh_check.hpp>

#include <limits>

namespace clustersurf {

MeshCheck check_mesh(const TriangleMesh& mesh, const MeshCheckOptions& options) {
  return check_mesh(mesh, find_self_intersections(mesh, options));
}

MeshCheck check_mesh(const TriangleMesh& mesh, SelfIntersections intersections) {
  MeshCheck c;
  c.topology = mesh_topology(mesh);
  const MeshTopology& t = c.topology;
  c.watertight = is_watertight(t);
  c.consistently_oriented = t.inconsistent_edges == 0;
  if (c.watertight && c.consistently_oriented) {
    // Closed orientable components: χᵢ = 2 − 2gᵢ, so Σgᵢ = (2·components − χ)/2.
    const long twice = 2 * static_cast<long>(t.components) - t.euler_characteristic;
    if (twice >= 0 && twice % 2 == 0) c.genus = twice / 2;
  }
  c.volume = c.watertight ? t.signed_volume : std::numeric_limits<double>::quiet_NaN();
  c.self_intersections = intersections.count;
  c.intersecting_pairs = std::move(intersections.pairs);
  c.printable = c.watertight && c.consistently_oriented && c.self_intersections == 0 && c.volume > 0;
  return c;
}

namespace {

/// "1 boundary edge", "12 boundary edges".
std::string count_of(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

std::vector<std::string> printing_problems(const MeshCheck& c) {
  const MeshTopology& t = c.topology;
  std::vector<std::string> out;
  if (t.triangles == 0) out.emplace_back("no triangles");
  if (t.boundary_edges > 0) out.push_back(count_of(t.boundary_edges, "boundary edge", "boundary edges"));
  if (t.non_manifold_edges > 0)
    out.push_back(count_of(t.non_manifold_edges, "non-manifold edge", "non-manifold edges"));
  if (t.inconsistent_edges > 0)
    out.push_back(count_of(t.inconsistent_edges, "inconsistently oriented edge", "inconsistently oriented edges"));
  if (c.self_intersections > 0)
    out.push_back(
        count_of(c.self_intersections, "self-intersecting triangle pair", "self-intersecting triangle pairs"));
  if (c.watertight && !(c.volume > 0))
    out.emplace_back(c.volume < 0 ? "negative volume (the triangles face inward)" : "no volume enclosed");
  return out;
}

}  // namespace clustersurf
