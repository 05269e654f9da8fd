#include "commands.hpp"
#include "input.hpp"
#include "mesh_stage.hpp"

#include <clustersurf/cluster/tree_file.hpp>

#include <iostream>

namespace clustersurf::cli {

int run_mesh(Console& console, const MeshCommandArgs& args) {
  const SurfaceMeshOptions options = surface_mesh_options(args.mesh);
  const ClusterTree tree = load_tree(args.tree);
  PointCloud cloud;
  if (!args.mesh.points.empty()) cloud = read_input(console, args.mesh.points);
  const CloudIndex input(cloud);
  const SurfaceMesh mesh = mesh_tree(tree, options, args.mesh.points.empty() ? nullptr : &input, console.progress());
  console.end_progress();
  const nlohmann::json j = write_surface_mesh(console, mesh, args.mesh, args.output);
  if (console.options().json) std::cout << j.dump(2) << "\n";
  return 0;
}

}  // namespace clustersurf::cli
