#include "commands.hpp"
#include "mesh_check_report.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/mesh/mesh_check.hpp>

#include <fmt/format.h>

#include <chrono>
#include <iostream>

namespace clustersurf::cli {

int run_check(Console& console, const CheckArgs& args) {
  ReadOptions read;
  read.warn = [&console](const std::string& message) { console.warn(message); };
  const TriangleMesh mesh = read_triangle_mesh(args.mesh, read);
  if (mesh.triangles.rows() == 0) throw InputError(args.mesh, {}, "the file has no triangles to check");
  const auto start = std::chrono::steady_clock::now();
  const MeshCheck check = check_mesh(mesh);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (console.options().json) {
    nlohmann::json j = check_report_json(check);
    j["file"] = args.mesh;
    j["seconds"] = seconds;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  console.print("file            " + args.mesh);
  for (const auto& line : mesh_check_lines(check)) console.print(line);
  console.print(fmt::format("time            {:.2f} s", seconds));
  return 0;
}

}  // namespace clustersurf::cli
