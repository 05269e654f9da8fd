#pragma once
// The print-readiness report of a mesh (check_mesh()) shared by `check` and the mesh stage:
// text lines and JSON.

#include <clustersurf/mesh/mesh_check.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace clustersurf::cli {

/// The library's report of the check (clustersurf::mesh_check_json()), as JSON to add to.
nlohmann::json check_report_json(const MeshCheck& check);
/// The same as human-readable lines.
std::vector<std::string> mesh_check_lines(const MeshCheck& check);

}  // namespace clustersurf::cli
