#include "commands.hpp"
#include "input.hpp"

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/render_option_schema.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <variant>

namespace clustersurf::cli {

namespace {

/// One input of the render command, by what its file holds.
using Scene = std::variant<ClusterTree, TriangleMesh, PointCloud>;

bool is_tree_file(const std::string& file) {
  if (std::filesystem::path(file).extension() == ".cstree") return true;
  std::ifstream in(file, std::ios::binary);
  char magic[8] = {};
  in.read(magic, sizeof magic);
  return in.gcount() == 8 && std::string(magic, 8) == std::string(
                                                          "\x89"
                                                          "CSTREE\n",
                                                          8);
}

Scene load_scene(Console& console, const std::string& file) {
  if (is_tree_file(file)) return load_tree(file);
  const FileFormat format = format_from_extension(file);
  if (format == FileFormat::Ply || format == FileFormat::Obj) {
    ReadOptions options;
    options.warn = [&console](const std::string& message) { console.warn(message); };
    TriangleMesh mesh = read_triangle_mesh(file, options);
    if (mesh.triangles.rows() > 0) return mesh;
  }
  return read_input(console, file);
}

/// The scene's bounding box in its file's coordinates (every kind is stored relative to an
/// origin), as the renderers take the framing.
BoundingBox scene_box(const Scene& scene) {
  return std::visit(
      [](const auto& s) -> BoundingBox {
        using T = std::decay_t<decltype(s)>;
        BoundingBox box;
        if constexpr (std::is_same_v<T, ClusterTree>)
          box = s.bbox;
        else if constexpr (std::is_same_v<T, TriangleMesh>)
          box = bounding_box(s.vertices);
        else
          box = bounding_box(s.positions);
        return box.empty() ? box : BoundingBox{box.min + s.origin, box.max + s.origin};
      },
      scene);
}

/// One scene's picture with `options` (a tree's level of detail from the arguments; meshes and
/// clouds as plain surfaces); its kind ("tree", "mesh" or "points") in `kind`.
Image draw_scene(Console& console, const RenderArgs& args, const std::string& input, const Scene& scene,
                 const RenderOptions& options, RenderStats& stats, std::string& kind,
                 const ProgressCallback& progress) {
  if (const auto* tree = std::get_if<ClusterTree>(&scene)) {
    RenderOptions o = options;
    o.lod = level_of_detail(*tree, args.lod_depth, args.lod_error);
    kind = "tree";
    return render_tree(*tree, o, &stats, progress);
  }
  if (options.show != ShowMode::Surface || options.highlight)
    console.warn(input + " is not a tree file: drawn as a plain surface");
  RenderOptions o = options;
  o.show = ShowMode::Surface;
  if (const auto* mesh = std::get_if<TriangleMesh>(&scene)) {
    kind = "mesh";
    return render_mesh(*mesh, o, &stats, progress);
  }
  kind = "points";
  return render_points(std::get<PointCloud>(scene), o, &stats, progress);
}

}  // namespace

int run_render(Console& console, const RenderArgs& args) {
  if (args.inputs.size() > 1 && !args.grid) throw OptionError("several inputs need --grid");
  if (std::filesystem::path(args.output).extension() != ".png") throw OptionError("the output must be a .png file");
  RenderOptions options;
  set_options(options, args.options);
  std::vector<Scene> scenes;
  for (const std::string& file : args.inputs) scenes.push_back(load_scene(console, file));
  PointCloud reference;
  if (!args.points.empty()) {
    reference = read_input(console, args.points);
    options.reference_points = &reference.positions;
  }
  BoundingBox framing;
  for (const Scene& s : scenes) {
    const BoundingBox b = scene_box(s);
    if (!b.empty()) framing.extend(b.min), framing.extend(b.max);
  }
  options.framing = framing;
  const ProgressCallback progress = console.progress();

  std::vector<Image> pictures;
  std::vector<std::string> labels;
  nlohmann::json renders = nlohmann::json::array();
  RenderStats total;
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    RenderStats stats;
    std::string kind;
    pictures.push_back(draw_scene(console, args, args.inputs[k], scenes[k], options, stats, kind, progress));
    console.end_progress();
    labels.push_back(std::filesystem::path(args.inputs[k]).filename().string());
    total.seconds += stats.seconds;
    total.rays += stats.rays;
    total.hits += stats.hits;
    console.print(fmt::format(
        "render          {} ({}): {}x{}, {} spp, {:.3f} s, {:.3g} rays/s, {:.1f} % hit", args.inputs[k], kind,
        options.width, options.height, options.samples, stats.seconds, stats.rays_per_second,
        stats.rays > 0 ? 100.0 * static_cast<double>(stats.hits) * options.samples / static_cast<double>(stats.rays)
                       : 0.0));
    nlohmann::json j = {{"input", args.inputs[k]}, {"kind", kind},       {"seconds", stats.seconds},
                        {"rays", stats.rays},      {"hits", stats.hits}, {"rays_per_second", stats.rays_per_second}};
    if (kind == "tree") j["mode"] = to_string(options.mode), j["show"] = to_string(options.show);
    if (stats.error_scale > 0) j["error_scale"] = stats.error_scale;
    renders.push_back(j);
  }
  const Image picture = args.grid ? compose_grid(pictures, labels, options.background, args.columns) : pictures.front();
  write_png(args.output, picture);
  console.print("wrote           " + args.output);
  if (console.options().json) {
    const nlohmann::json j = {
        {"file", args.output},
        {"width", picture.width},
        {"height", picture.height},
        {"samples", options.samples},
        {"seconds", total.seconds},
        {"rays", total.rays},
        {"rays_per_second", total.seconds > 0 ? static_cast<double>(total.rays) / total.seconds : 0.0},
        {"renders", renders}};
    std::cout << j.dump(2) << "\n";
  }
  return 0;
}

}  // namespace clustersurf::cli
