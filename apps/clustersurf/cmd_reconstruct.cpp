#include "commands.hpp"
#include "input.hpp"
#include "mesh_stage.hpp"
#include "tree_report.hpp"

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

#include <fmt/format.h>

#include <chrono>
#include <iostream>

namespace clustersurf::cli {

namespace {

/// The library's options with those given set (set_options()).
ReconstructOptions reconstruct_options(const ReconstructArgs& a) {
  ReconstructOptions o;
  set_options(o, a.build, {OptionStage::Build});
  set_options(o, a.mesh.options, {OptionStage::Mesh});
  o.mesh = !a.mesh_output.empty();
  return o;
}

}  // namespace

namespace {

/// `reconstruct --memory-limit`: out of core, the mesh written tile by tile.
int run_out_of_core(Console& console, const ReconstructArgs& args, const ReconstructOptions& options) {
  OutOfCoreOptions out_of_core;
  out_of_core.memory_limit = parse_memory_size(args.memory_limit);
  out_of_core.work_directory =
      !args.work_dir.empty() ? std::filesystem::path(args.work_dir)
                             : default_work_directory(args.mesh_output.empty() ? args.tree_output : args.mesh_output);
  out_of_core.remove_work_directory = !args.keep_work_dir;
  out_of_core.read = read_options(console, args.input);
  out_of_core.mesh_output = args.mesh_output;
  out_of_core.ply.binary = !args.mesh.ascii;
  const OutOfCoreReconstruction result =
      reconstruct_out_of_core(args.input.file, options, out_of_core, console.progress());
  console.end_progress();
  if (!args.tree_output.empty()) save_tree(args.tree_output, result.tree);
  nlohmann::json mesh;
  if (result.mesh) {
    mesh = nlohmann::json::parse(written_mesh_json(*result.mesh));
  }
  if (console.options().json) {
    nlohmann::json j = tree_report_json(result.tree);
    j["input"] = args.input.file;
    j["out_of_core"] = {{"memory_limit", out_of_core.memory_limit},
                        {"work_dir", out_of_core.work_directory.string()},
                        {"regions", result.regions},
                        {"work_bytes", result.work_bytes}};
    if (!args.tree_output.empty()) j["tree"] = args.tree_output;
    j["timing"] = {{"build_seconds", result.build_seconds}};
    for (const auto& [stage, seconds] : result.stage_seconds) j["timing"][stage + "_seconds"] = seconds;
    j["orientation"] = {{"used_normals", result.orientation.used_normals},
                        {"used_scanners", result.orientation.used_scanners}};
    if (result.mesh) j["mesh"] = mesh;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  for (const auto& line : tree_report_lines(result.tree)) console.print(line);
  console.print("orientation     " + std::string(result.orientation.used_normals    ? "by input normals"
                                                 : result.orientation.used_scanners ? "towards the scanners"
                                                                                    : "by propagation in each region"));
  std::string stages;
  for (const auto& [stage, seconds] : result.stage_seconds)
    stages += fmt::format("{}{} {:.2f} s", stages.empty() ? "" : ", ", stage, seconds);
  console.print(fmt::format("out of core     {} regions within {} ({:.0f} MB of work files): {}", result.regions,
                            args.memory_limit, static_cast<double>(result.work_bytes) / 1e6, stages));
  if (result.mesh) {
    const WrittenMesh& m = *result.mesh;
    console.print(fmt::format("mesh            {} vertices, {} triangles ({} blended nodes, voxel {:.4g}){}",
                              m.vertices, m.triangles, m.blended_nodes, m.grid.voxel_size,
                              m.streamed ? ", written tile by tile" : ""));
    console.print(fmt::format("mesh time       {:.3f} s", m.seconds));
    console.print("wrote           " + m.file.string());
  }
  if (!args.tree_output.empty()) console.print("wrote           " + args.tree_output);
  return 0;
}

}  // namespace

int run_reconstruct(Console& console, const ReconstructArgs& args) {
  if (args.tree_output.empty() && args.mesh_output.empty())
    throw OptionError("nothing to write: give -o TREE.cstree and/or --mesh MESH.ply");
  const ReconstructOptions options = reconstruct_options(args);
  if (!args.memory_limit.empty()) return run_out_of_core(console, args, options);
  const auto t0 = std::chrono::steady_clock::now();
  const PointCloud cloud = read_input(console, args.input);
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Reconstruction result = [&] {
    try {
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
    j["orientation"] = {{"used_normals", orientation.used_normals},
                        {"used_scanners", orientation.used_scanners},
                        {"components", orientation.components},
                        {"flipped", orientation.flipped}};
    if (const ScanRegistration& r = result.registration; r.scans > 1)
      j["registration"] = {{"scans", r.scans},
                           {"overlaps", r.overlaps},
                           {"median_offset", r.median_offset},
                           {"rms_offset", r.rms_offset},
                           {"point_spacing", result.tree.point_spacing}};
    if (result.mesh) j["mesh"] = write_surface_mesh(console, *result.mesh, args.mesh, args.mesh_output);
    if (!args.tree_output.empty()) save_tree(args.tree_output, result.tree);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  for (const auto& line : tree_report_lines(result.tree)) console.print(line);
  console.print("orientation     " + (orientation.used_normals ? std::string("by input normals")
                                      : orientation.used_scanners
                                          ? std::string("towards the scanners")
                                          : fmt::format("by propagation ({} component{})", orientation.components,
                                                        orientation.components == 1 ? "" : "s")));
  if (const ScanRegistration& r = result.registration; r.scans > 1)
    console.print(r.overlaps == 0
                      ? fmt::format("registration    {} scans that do not overlap", r.scans)
                      : fmt::format("registration    {} scans, offset where they overlap: median {:.4g} ({:.2f} point "
                                    "spacings), rms {:.4g} ({} samples)",
                                    r.scans, r.median_offset,
                                    result.tree.point_spacing > 0 ? r.median_offset / result.tree.point_spacing : 0.0,
                                    r.rms_offset, r.overlaps));
  console.print(fmt::format("time            read {:.3f} s, build {:.3f} s", read_seconds, result.build_seconds));
  if (result.mesh) write_surface_mesh(console, *result.mesh, args.mesh, args.mesh_output);
  if (!args.tree_output.empty()) {
    save_tree(args.tree_output, result.tree);
    console.print("wrote           " + args.tree_output);
  }
  return 0;
}

}  // namespace clustersurf::cli
