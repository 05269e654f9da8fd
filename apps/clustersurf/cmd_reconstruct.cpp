#include "commands.hpp"
#include "input.hpp"
#include "mesh_stage.hpp"
#include "tree_report.hpp"

#include <clustersurf/errors.hpp>
#include <clustersurf/tiled_run.hpp>
#include <clustersurf/tree_file.hpp>

#include <fmt/format.h>

#include <chrono>
#include <iostream>

namespace clustersurf::cli {

namespace {

/// The library's options with the words of `a` parsed.
ReconstructOptions reconstruct_options(const ReconstructArgs& a) {
  ReconstructOptions o;
  BuildOptions& b = o.build;
  b = a.build;
  b.proxy = parse_proxy_kind(a.proxy);
  b.splitter = parse_splitter(a.splitter);
  b.metric = parse_error_metric(a.error_metric);
  if (a.absolute_tolerance) {
    b.threshold_mode = ThresholdMode::Absolute;
    b.tolerance = *a.absolute_tolerance;
  } else if (const auto tolerance = parse_tolerance(a.tolerance)) {
    b.tolerance = *tolerance;
  }
  b.min_points = parse_min_points(a.min_points);
  b.keep_point_leaves = !a.no_point_leaves;
  b.remove_outliers = !a.keep_outliers;
  b.use_normals = !a.ignore_normals;
  b.creases = !a.no_creases;
  o.mesh = !a.mesh_output.empty();
  o.meshing = surface_mesh_options(a.mesh);
  return o;
}

}  // namespace

int run_reconstruct(Console& console, const ReconstructArgs& args) {
  if (args.tree_output.empty() && args.mesh_output.empty())
    throw OptionError("nothing to write: give -o TREE.cstree and/or --mesh MESH.ply");
  const ReconstructOptions options = reconstruct_options(args);
  const auto t0 = std::chrono::steady_clock::now();
  double read_seconds = 0;  // out of core: reading is part of the build
  Reconstruction result = [&] {
    try {
      if (!args.memory_limit.empty()) {
        OutOfCoreOptions out_of_core;
        out_of_core.memory_limit = parse_memory_size(args.memory_limit);
        out_of_core.work_directory =
            !args.work_dir.empty() ? args.work_dir : (args.mesh_output.empty() ? args.tree_output : args.mesh_output) + ".work";
        out_of_core.remove_work_directory = !args.keep_work_dir;
        out_of_core.read = read_options(console, args.input);
        return reconstruct_out_of_core(args.input.file, options, out_of_core, console.progress());
      }
      const PointCloud cloud = read_input(console, args.input);
      read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return reconstruct(cloud, options, console.progress());
    } catch (const InputError& e) {
      if (!e.file().empty()) throw;
      throw InputError(args.input.file, e.where(), e.message());  // the library judged the points, not a file
    }
  }();
  console.end_progress();
  // Every long step (build, mesh) ran before any file is written, so an interrupted run leaves
  // no output at all.
  const OrientationReport& orientation = result.orientation;
  if (console.options().json) {
    nlohmann::json j = tree_report_json(result.tree);
    j["input"] = args.input.file;
    if (!args.tree_output.empty()) j["tree"] = args.tree_output;
    j["timing"] = {{"read_seconds", read_seconds}, {"build_seconds", result.build_seconds}};
    j["orientation"] = {{"used_normals", orientation.used_normals}, {"used_scanners", orientation.used_scanners},
                        {"components", orientation.components},
                        {"flipped", orientation.flipped}};
    if (result.mesh) j["mesh"] = write_surface_mesh(console, *result.mesh, args.mesh, args.mesh_output);
    if (!args.tree_output.empty()) save_tree(args.tree_output, result.tree);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  for (const auto& line : tree_report_lines(result.tree)) console.print(line);
  console.print("orientation     " + (orientation.used_normals    ? std::string("by input normals")
                                      : orientation.used_scanners ? std::string("towards the scanners")
                                                                  : fmt::format("by propagation ({} component{})", orientation.components,
                                                        orientation.components == 1 ? "" : "s")));
  console.print(fmt::format("time            read {:.3f} s, build {:.3f} s", read_seconds, result.build_seconds));
  if (result.mesh) write_surface_mesh(console, *result.mesh, args.mesh, args.mesh_output);
  if (!args.tree_output.empty()) {
    save_tree(args.tree_output, result.tree);
    console.print("wrote           " + args.tree_output);
  }
  return 0;
}

}  // namespace clustersurf::cli
