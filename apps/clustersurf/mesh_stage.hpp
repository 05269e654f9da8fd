#pragma once
// The mesh stage shared by `mesh` and `reconstruct --mesh`: the options from the words, and
// writing and reporting the mesh the library made.

#include "commands.hpp"

#include <clustersurf/pipeline/reconstruct.hpp>

#include <nlohmann/json.hpp>

namespace clustersurf::cli {

/// The library's mesh options with those of `args` set (set_options()).
SurfaceMeshOptions surface_mesh_options(const MeshArgs& args);

/// Writes `mesh` to `output` atomically and returns its figures as JSON (also printed as text
/// unless --json/--quiet).
nlohmann::json write_surface_mesh(Console& console, const SurfaceMesh& mesh, const MeshArgs& args,
                                  const std::string& output);

}  // namespace clustersurf::cli
