// The report of a mesh the pipeline made, for both front ends.

#include <clustersurf/mesh/mesh_check.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <nlohmann/json.hpp>

namespace clustersurf {

std::string surface_mesh_json(const SurfaceMesh& m, const MeshTopology& topology) {
  nlohmann::json j = nlohmann::json::parse(mesh_topology_json(topology));
  j.update({{"blended_nodes", m.blended_nodes},
            {"voxel_size", m.grid.voxel_size},
            {"surface_cells", m.grid.surface_cells},
            {"evaluated_corners", m.grid.evaluated_corners},
            {"trimmed_triangles", m.trim.removed_triangles},
            {"removed_components", m.trim.removed_components},
            {"closed_pinholes", m.trim.closed_pinholes},
            {"coarsened_from_triangles", m.coarsening.triangles_before},
            {"coarsening_tolerance", m.coarsening.tolerance},
            {"refitted_vertices", m.refit.refitted},
            {"refit_mean_move", m.refit.mean_move},
            {"refit_mean_chord_offset", m.refit.mean_chord_offset},
            {"filled_vertices", m.closing.filled_vertices},
            {"filled_triangles", m.closing.filled_triangles},
            {"opened_holes", m.closing.opened_holes},
            {"decimated_from_triangles", m.decimation.triangles_before},
            {"decimation_deviation", m.decimation.deviation},
            {"mesh_seconds", m.seconds}});
  if (m.closing.closed) j["check"] = nlohmann::json::parse(mesh_check_json(m.closing.check));
  return j.dump();
}

std::string surface_mesh_json(const SurfaceMesh& mesh) { return surface_mesh_json(mesh, mesh_topology(mesh.mesh)); }

}  // namespace clustersurf
