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

}  // namespace clustersurf
