#include "commands.hpp"
#include "tree_report.hpp"

#include <clustersurf/cluster/tree_file.hpp>

#include <iostream>

namespace clustersurf::cli {

int run_info(Console& console, const InfoArgs& args) {
  const ClusterTree tree = load_tree(args.tree);
  if (console.options().json) {
    nlohmann::json j = tree_report_json(tree);
    j["file"] = args.tree;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  console.print("file            " + args.tree);
  for (const auto& line : tree_report_lines(tree)) console.print(line);
  console.print("build time      not stored in tree files (they are reproducible); `reconstruct` reports it");
  return 0;
}

}  // namespace clustersurf::cli
