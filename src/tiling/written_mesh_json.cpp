// The report of a mesh a tiled run wrote, for both front ends.

#include <clustersurf/tiling/tiled_run.hpp>

#include <nlohmann/json.hpp>

namespace clustersurf {

std::string written_mesh_json(const WrittenMesh& m) {
  const nlohmann::json j = {{"file", m.file.string()},
                            {"vertices", m.vertices},
                            {"triangles", m.triangles},
                            {"streamed", m.streamed},
                            {"blended_nodes", m.blended_nodes},
                            {"voxel_size", m.grid.voxel_size},
                            {"surface_cells", m.grid.surface_cells},
                            {"removed_components", m.removed_components},
                            {"coarsened_from_triangles", m.coarsening.triangles_before},
                            {"coarsening_tolerance", m.coarsening.tolerance},
                            {"mesh_seconds", m.seconds}};
  return j.dump();
}

}  // namespace clustersurf
