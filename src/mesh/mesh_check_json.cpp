// The mesh check's and the mesh topology's reports as JSON, for both front ends.

#include <clustersurf/mesh/mesh_check.hpp>

#include <nlohmann/json.hpp>

#include <cmath>

namespace clustersurf {

namespace {

nlohmann::json number_or_null(double x) { return std::isnan(x) ? nlohmann::json(nullptr) : nlohmann::json(x); }

nlohmann::json topology_object(const MeshTopology& t) {
  return {{"vertices", t.vertices},
          {"triangles", t.triangles},
          {"edges", t.edges},
          {"boundary_edges", t.boundary_edges},
          {"non_manifold_edges", t.non_manifold_edges},
          {"inconsistent_edges", t.inconsistent_edges},
          {"components", t.components},
          {"small_components", t.small_components},
          {"euler_characteristic", t.euler_characteristic},
          {"area", t.area},
          {"boundary_length", t.boundary_length},
          {"boundary_per_sqrt_area", boundary_per_sqrt_area(t)},
          {"signed_volume", t.signed_volume},
          {"watertight", is_watertight(t)}};
}

}  // namespace

std::string mesh_topology_json(const MeshTopology& topology) { return topology_object(topology).dump(); }

std::string mesh_check_json(const MeshCheck& c) {
  nlohmann::json j = topology_object(c.topology);
  nlohmann::json pairs = nlohmann::json::array();
  for (const auto& p : c.intersecting_pairs) pairs.push_back({p[0], p[1]});
  j["genus"] = c.genus >= 0 ? nlohmann::json(c.genus) : nlohmann::json(nullptr);
  j["volume"] = number_or_null(c.volume);
  j["self_intersections"] = c.self_intersections;
  j["intersecting_pairs"] = pairs;
  j["consistently_oriented"] = c.consistently_oriented;
  j["printable"] = c.printable;
  j["problems"] = printing_problems(c);
  return j.dump();
}

}  // namespace clustersurf
