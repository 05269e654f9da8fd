#pragma once
// The print-readiness report of a mesh (check_mesh()) shared by `check` and the mesh stage:
// text lines and JSON.

#include <clustersurf/mesh/mesh_check.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace clustersurf::cli {

/// JSON object: vertices, triangles, edges, boundary_edges, non_manifold_edges,
/// inconsistent_edges, components, euler_characteristic, genus (null when not defined), volume
/// (null when not closed), self_intersections, intersecting_pairs (the first ones, [i, j]),
/// watertight, consistently_oriented, printable, problems.
nlohmann::json mesh_check_json(const MeshCheck& check);
/// The same as human-readable lines.
std::vector<std::string> mesh_check_lines(const MeshCheck& check);

}  // namespace clustersurf::cli
