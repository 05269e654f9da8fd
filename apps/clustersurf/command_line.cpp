// The command line of the `clustersurf` tool (command_line.hpp): the library's option schema
// as CLI11 options, with the other arguments of each subcommand.

#include "command_line.hpp"

#include <clustersurf/pipeline/option_schema.hpp>
#include <clustersurf/render/render_option_schema.hpp>
#include <clustersurf/version.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <string>

namespace clustersurf::cli {

namespace {

void add_input(CLI::App& cmd, InputArgs& in) {
  cmd.add_option("input", in.file, "Point cloud (.ply, .xyz/.pts/.txt/.csv, .obj, .las, .e57, .ptx, .pcd)")->required();
  cmd.add_flag("--drop-non-finite", in.drop_non_finite,
               "Drop points with NaN/Inf coordinates (counted in a warning) instead of failing");
  cmd.add_option("--mesh-samples", in.mesh_samples,
                 "A mesh input (PLY/OBJ with faces) with fewer vertices than this is read as this many points drawn "
                 "uniformly on its faces (seeded); 0 reads every mesh's vertices")
      ->capture_default_str();
}

/// The CLI flag of a schema name: --kebab-case.
std::string flag_name(const std::string& name) {
  std::string flag = "--" + name;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

/// The options of `stage` in `schema`, each given one appended to `values` as the schema's
/// text; the library checks them.
template <class Options>
void add_schema_options(CLI::App& cmd, const std::vector<OptionSpecOf<Options>>& schema, OptionStage stage,
                        OptionValues& values) {
  for (const OptionSpecOf<Options>& spec : schema) {
    if (spec.stage != stage) continue;
    const std::string names = flag_name(spec.name) + (spec.alias.empty() ? "" : "," + flag_name(spec.alias));
    if (spec.kind == OptionKind::Flag) {
      cmd.add_flag_function(
          names, [&values, name = spec.name](std::int64_t) { values.emplace_back(name, "true"); }, spec.help);
      continue;
    }
    CLI::Option* option = cmd.add_option_function<std::string>(
        names, [&values, name = spec.name](const std::string& text) { values.emplace_back(name, text); }, spec.help);
    std::string type = spec.kind == OptionKind::Whole    ? "UINT"
                       : spec.kind == OptionKind::Number ? "FLOAT"
                       : spec.kind == OptionKind::Vector ? "X,Y,Z"
                                                         : "";
    for (const std::string& word : spec.words) type += (type.empty() ? "" : "|") + word;
    option->type_name(type);
    if (const std::string value = default_text(spec); !value.empty()) option->default_str(value);
  }
}

/// The reconstruct options of `stage`.
void add_schema_options(CLI::App& cmd, OptionStage stage, OptionValues& values) {
  add_schema_options(cmd, reconstruct_option_schema(), stage, values);
}

void add_mesh_options(CLI::App& cmd, MeshArgs& m) {
  add_schema_options(cmd, OptionStage::Mesh, m.options);
  cmd.add_flag("--mesh-ascii", m.ascii, "Write the mesh as ascii PLY instead of binary");
}

/// The `convert` subcommand, its arguments bound to `args`.
void add_convert_command(CLI::App& app, ConvertArgs& args) {
  CLI::App* c = app.add_subcommand("convert", "Convert a point cloud between formats, optionally reduced");
  add_input(*c, args.input);
  c->add_option("output", args.output, "Output file (.ply, .xyz, .obj)")->required();
  c->add_option("--subsample", args.subsample, "Keep N points chosen uniformly at random")->check(CLI::PositiveNumber);
  c->add_option("--voxel", args.voxel, "Average the points in each cube of this side")->check(CLI::PositiveNumber);
  c->add_option("--seed", args.seed, "Random seed for --subsample")->default_val(1);
  c->add_flag("--ascii", args.ascii, "Write ascii PLY instead of binary");
  c->add_flag("--double", args.double_precision, "Store PLY coordinates as double (bit-exact)");
}

/// The `stats` subcommand, its arguments bound to `args`.
void add_stats_command(CLI::App& app, StatsArgs& args) {
  CLI::App* s = app.add_subcommand("stats", "Point count, bounding box, spacing, attributes of a cloud");
  add_input(*s, args.input);
}

/// The `reconstruct` subcommand, its arguments bound to `args`.
void add_reconstruct_command(CLI::App& app, ReconstructArgs& args) {
  CLI::App* r = app.add_subcommand("reconstruct", "Build the cluster tree of a point cloud (and save it)");
  add_input(*r, args.input);
  r->add_option("-o,--output", args.tree_output, "Tree file to write (.cstree)");
  r->add_option("--mesh", args.mesh_output, "Also mesh the surface into this file (.ply, .obj, .off, .stl or .glb)");
  add_mesh_options(*r, args.mesh);
  add_schema_options(*r, OptionStage::Build, args.build);
  r->add_option("--memory-limit", args.memory_limit,
                "Build and mesh out of core within about this much memory (e.g. 4G): the input is split into "
                "regions on disk, each built and meshed in turn, the tiles welded into one mesh");
  r->add_option("--work-dir", args.work_dir,
                "Where an out-of-core run keeps its files (default: the mesh or tree file's name + .work); a run "
                "interrupted and started again resumes there. A folder holding other files is used alongside them: "
                "only the run's "
                "own files are removed when it is done, and the folder only if the run created it");
  r->add_flag("--keep-work-dir", args.keep_work_dir, "Keep an out-of-core run's files when it is done");
}

/// The `info` subcommand, its arguments bound to `args`.
void add_info_command(CLI::App& app, InfoArgs& args) {
  CLI::App* i = app.add_subcommand("info", "Describe a tree file: sizes, depth, proxies, errors, parameters");
  i->add_option("tree", args.tree, "Tree file (.cstree)")->required();
}

/// The `mesh` subcommand, its arguments bound to `args`.
void add_mesh_command(CLI::App& app, MeshCommandArgs& args) {
  CLI::App* m = app.add_subcommand("mesh", "Mesh the implicit surface of a tree file");
  m->add_option("tree", args.tree, "Tree file (.cstree)")->required();
  m->add_option("-o,--output", args.output, "Mesh file to write (.ply, .obj, .off, .stl or .glb)")->required();
  m->add_option("--points", args.mesh.points, "The tree's input cloud, for --trim and --color distance or input");
  add_mesh_options(*m, args.mesh);
}

/// The `sample` subcommand, its arguments bound to `args`.
void add_sample_command(CLI::App& app, SampleArgs& args) {
  CLI::App* sm = app.add_subcommand("sample",
                                    "Draw area-uniform random points (with normals) from a triangle mesh, or scan it "
                                    "with a virtual range scanner (--scanner)");
  sm->add_option("mesh", args.mesh, "Triangle mesh (.ply or .obj)")->required();
  sm->add_option("-o,--output", args.output, "Point cloud to write (.ply, .xyz)")->required();
  sm->add_option("-n,--n", args.count, "Number of surface points (--scanner: about this many)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  sm->add_option("--noise", args.noise,
                 "Gaussian noise sigma as a fraction of the bbox diagonal (--scanner: along the line of sight)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sm->add_option("--outliers", args.outliers, "Uniform outliers in the bbox, as a fraction of N")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sm->add_option("--seed", args.seed, "Random seed")->capture_default_str();
  sm->add_flag("--ascii", args.ascii, "Write ascii PLY instead of binary");
  sm->add_flag("--no-normals", args.no_normals, "Do not write the normals");
  sm->add_option("--scanner", args.scanner,
                 "Scan from N viewpoints around the mesh instead: occlusion holes, grazing returns dropped, normals "
                 "from each scan's grid towards its scanner")
      ->check(CLI::PositiveNumber);
  sm->add_option("--registration", args.registration,
                 "--scanner: each scan's rigid misregistration, sigma as a fraction of the bbox diagonal")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sm->add_option("--noise-correlation", args.noise_correlation,
                 "--scanner: how many grid steps the range noise is correlated over (the sigma of the Gaussian "
                 "that smooths it; 0: independent)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sm->add_option("--flip-normals", args.flipped_normals,
                 "--scanner: fraction of the returns whose normal points away from its scanner (orientation errors)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  sm->add_option("--scanner-distance", args.scanner_distance, "--scanner: distance to the bbox center, in diagonals")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

/// The `eval` subcommand, its arguments bound to `args`.
void add_eval_command(CLI::App& app, EvalArgs& args) {
  CLI::App* ev = app.add_subcommand("eval", "Accuracy of a reconstruction against a reference surface (mesh or cloud)");
  ev->add_option("reconstruction", args.reconstruction, "Reconstructed mesh or cloud (.ply, .obj, .xyz)")->required();
  ev->add_option("-r,--reference", args.reference, "Reference mesh or cloud (the ground truth)")->required();
  ev->add_option("--samples", args.samples, "Points sampled on each mesh surface")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  ev->add_option("--seed", args.seed, "Random seed for the samples")->capture_default_str();
}

/// The `check` subcommand, its arguments bound to `args`.
void add_check_command(CLI::App& app, CheckArgs& args) {
  CLI::App* ck = app.add_subcommand("check",
                                    "Is a mesh ready to print: boundary and non-manifold edges, orientation, "
                                    "components, Euler characteristic and genus, volume, self-intersections");
  ck->add_option("mesh", args.mesh, "Triangle mesh (.ply or .obj)")->required();
}

/// The `render` subcommand, its arguments bound to `args`.
void add_render_command(CLI::App& app, RenderArgs& args) {
  CLI::App* v = app.add_subcommand("render", "Ray-trace a picture of a tree's surface (or of meshes and point clouds)");
  v->add_option("input", args.inputs, "Tree file (.cstree), mesh or point cloud; several with --grid")->required();
  v->add_option("-o,--output", args.output, "Picture to write (.png)")->required();
  add_schema_options(*v, render_option_schema(), OptionStage::Render, args.options);
  v->add_option("--points", args.points, "The input cloud, for --show error");
  v->add_option("--lod-depth", args.lod_depth, "Blend the tree cut at this depth instead of the leaves");
  v->add_option("--lod-error", args.lod_error, "Blend the shallowest nodes with error <= this fraction of the diagonal")
      ->check(CLI::NonNegativeNumber);
  v->add_flag("--grid", args.grid, "Render every input with the same camera into one labelled picture");
  v->add_option("--columns", args.columns, "--grid: pictures per row (0: as square as possible)")
      ->check(CLI::NonNegativeNumber);
}

/// The `view` subcommand, its arguments bound to `args`.
void add_view_command(CLI::App& app, ViewArgs& args) {
  CLI::App* vw =
      app.add_subcommand("view", "Write an interactive HTML viewer of a tree: clusters, proxies, spheres, mesh");
  vw->add_option("tree", args.tree, "Tree file (.cstree)")->required();
  vw->add_option("-o,--output", args.output, "Page to write (.html, self-contained: open it in a browser)")->required();
  vw->add_option("--points", args.points, "The cloud the tree was built from (tree files do not hold the positions)");
  vw->add_option("--mesh", args.mesh, "A mesh to show as well (.ply, .obj or .glb)");
  vw->add_option("--max-points", args.max_points,
                 "Embed at most this many points, evenly spread over the input (0: all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

}  // namespace

CommandLine parse_command_line(int argc, char** argv, int usage_exit_code) {
  CommandLine out;
  CLI::App app{"clustersurf: surfaces from point clouds by hierarchical clustering"};
  app.set_version_flag("--version", std::string("clustersurf ") + clustersurf::kVersion);
  app.require_subcommand(1);
  app.fallthrough();  // global options may also follow the subcommand (inherited by subcommands)
  app.add_option("--threads", out.global.threads, "Worker threads (0: all cores); results do not depend on it")
      ->check(CLI::NonNegativeNumber)
      ->default_val(0);
  app.add_flag("-q,--quiet", out.global.quiet, "No progress, no human output; errors only");
  app.add_flag("--json", out.global.json, "Machine-readable JSON on stdout");

  add_convert_command(app, out.commands.convert);
  add_stats_command(app, out.commands.stats);
  add_reconstruct_command(app, out.commands.reconstruct);
  add_info_command(app, out.commands.info);
  add_mesh_command(app, out.commands.mesh);
  add_sample_command(app, out.commands.sample);
  add_eval_command(app, out.commands.eval);
  add_check_command(app, out.commands.check);
  add_render_command(app, out.commands.render);
  add_view_command(app, out.commands.view);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, version or the usage error
    out.exit = code == 0 ? 0 : usage_exit_code;
    return out;
  }
  for (CLI::App* sub : app.get_subcommands()) out.command = sub->get_name();
  return out;
}

}  // namespace clustersurf::cli
