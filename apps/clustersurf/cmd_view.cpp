#include "commands.hpp"
#include "input.hpp"

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/view/html_viewer.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <iostream>

namespace clustersurf::cli {

int run_view(Console& console, const ViewArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  const auto extension = std::filesystem::path(args.output).extension();
  if (extension != ".html" && extension != ".htm") throw OptionError("the output must be an .html file");
  const ClusterTree tree = load_tree(args.tree);

  PointCloud cloud;
  if (args.points.empty()) {
    console.warn(
        "no --points: the page shows the tree's proxies and spheres only (tree files do not hold the "
        "positions; pass the cloud the tree was built from to see the points)");
  } else {
    cloud = read_input(console, args.points);
  }
  // A .glb mesh is embedded as it is (the page parses it); .ply/.obj meshes are read here.
  std::string mesh_extension = std::filesystem::path(args.mesh).extension().string();
  std::transform(mesh_extension.begin(), mesh_extension.end(), mesh_extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const bool glb = mesh_extension == ".glb";
  TriangleMesh mesh;
  GlbMesh glb_mesh;
  if (glb) {
    glb_mesh = read_glb_file(args.mesh);
  } else if (!args.mesh.empty()) {
    ReadOptions options;
    options.warn = [&console](const std::string& message) { console.warn(message); };
    mesh = read_triangle_mesh(args.mesh, options);
  }

  ViewerOptions options;
  options.max_points = args.max_points;
  options.title = std::filesystem::path(args.tree).filename().string();
  const PointCloud* points = args.points.empty() ? nullptr : &cloud;
  const ViewerStats stats =
      glb ? write_viewer_html(args.output, tree, points, glb_mesh, options)
          : write_viewer_html(args.output, tree, points, args.mesh.empty() ? nullptr : &mesh, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats.points < static_cast<std::size_t>(cloud.size()))
    console.print(fmt::format("points          {} of {} embedded (--max-points)", stats.points, cloud.size()));
  console.print(fmt::format("wrote           {} ({:.1f} MB: {} nodes, {} points, {} triangles) in {:.2f} s",
                            args.output, static_cast<double>(stats.bytes) / 1e6, stats.nodes, stats.points,
                            stats.triangles, seconds));
  if (console.options().json) {
    const nlohmann::json j = {{"file", args.output},    {"bytes", stats.bytes},         {"nodes", stats.nodes},
                              {"points", stats.points}, {"input_points", cloud.size()}, {"triangles", stats.triangles},
                              {"seconds", seconds}};
    std::cout << j.dump(2) << "\n";
  }
  return 0;
}

}  // namespace clustersurf::cli
