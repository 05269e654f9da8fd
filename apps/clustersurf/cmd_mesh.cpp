#include "commands.hpp"
#include "input.hpp"
#include "mesh_stage.hpp"

#include <clustersurf/tree_file.hpp>

#include <iostream>

namespace clustersurf::cli {

int run_mesh(Console& console, const MeshCommandArgs& args) {
  const ClusterTree tree = load_tree(args.tree);
  PointCloud cloud;
  if (!args.mesh.points.empty()) cloud = read_input(console, InputArgs{args.mesh.points, false});
  const nlohmann::json j = write_tree_mesh(console, tree, args.mesh, args.output, args.mesh.points.empty() ? nullptr : &cloud);
  if (console.options().json) std::cout << j.dump(2) << "\n";
  return 0;
}

}  // namespace clustersurf::cli
