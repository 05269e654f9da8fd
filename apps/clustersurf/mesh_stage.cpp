#include "mesh_stage.hpp"

#include <clustersurf/errors.hpp>
#include <clustersurf/implicit_surface.hpp>
#include <clustersurf/mesh_colors.hpp>
#include <clustersurf/mesh_extraction.hpp>
#include <clustersurf/mesh_trim.hpp>
#include <clustersurf/point_cloud_io.hpp>

#include <fmt/format.h>

#include <chrono>

namespace clustersurf::cli {

namespace {

/// --resolution's number (CLI11 checked the range already; this guards other callers).
std::uint32_t parse_resolution(const std::string& text) {
  std::size_t used = 0;
  unsigned long value = 0;
  try {
    value = std::stoul(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || value < 2 || value > 100000)
    throw OptionError("--resolution must be a whole number from 2 to 100000 or \"auto\", not \"" + text + "\"");
  return static_cast<std::uint32_t>(value);
}

}  // namespace

nlohmann::json write_tree_mesh(Console& console, const ClusterTree& tree, const MeshArgs& args, const std::string& output,
                               const PointCloud* cloud) {
  if (args.color != "none" && args.color != "leaf" && args.color != "distance")
    throw OptionError("--color must be none, leaf or distance, not \"" + args.color + "\"");
  if (args.color == "distance" && cloud == nullptr)
    throw OptionError("--color distance needs the input points (--points FILE)");
  const auto t0 = std::chrono::steady_clock::now();
  LevelOfDetail lod;
  lod.max_depth = args.lod_depth;
  if (args.lod_error) lod.max_error = *args.lod_error * tree.bbox.diagonal();
  const ImplicitSurface surface(tree, lod);
  MeshOptions options;
  options.voxel_size = args.voxel_size;
  // The default: cells matched to the points where they are at hand, else MeshOptions' count.
  const bool automatic = args.resolution == "auto" || (args.resolution.empty() && cloud != nullptr);
  if (automatic) {
    if (!options.voxel_size) {  // --voxel-size overrides --resolution, auto included
      if (cloud == nullptr) throw OptionError("--resolution auto needs the input points (--points FILE)");
      options.voxel_size = cell_size_for_points(*cloud);
    }
  } else if (!args.resolution.empty()) {
    options.resolution = parse_resolution(args.resolution);
  }
  options.progress = console.progress();
  MeshReport report;
  TriangleMesh mesh = extract_mesh(surface, options, &report);
  console.end_progress();
  // Trimmed to the clustered points: an outlier next to an extrapolated flap must not keep it.
  TrimReport trimmed;
  if (cloud != nullptr) {
    TrimOptions trim;
    trim.spread_factor = args.trim;
    trim.min_component_points = args.min_component_points;
    trim.close_pinholes = args.close_pinholes;
    mesh = trim_to_points(mesh, clustered_points(tree, cloud->positions), trim, &trimmed);
  }
  if (args.color == "leaf") mesh.colors = colors_by_node(mesh, surface);
  if (args.color == "distance") mesh.colors = colors_by_distance(mesh, cloud->positions, 0.005 * tree.bbox.diagonal());
  const auto t1 = std::chrono::steady_clock::now();
  PlyWriteOptions ply;
  ply.binary = !args.ascii;
  write_triangle_mesh(output, mesh, ply);
  const MeshTopology topo = mesh_topology(mesh);
  const double seconds = std::chrono::duration<double>(t1 - t0).count();
  console.print(fmt::format("mesh            {} vertices, {} triangles ({} blended nodes, voxel {:.4g}), {} boundary edges, "
                            "{} non-manifold edges",
                            topo.vertices, topo.triangles, surface.cut().size(), report.voxel_size, topo.boundary_edges,
                            topo.non_manifold_edges));
  if (trimmed.removed_triangles > 0 || trimmed.closed_pinholes > 0)
    console.print(fmt::format("trimmed         {} triangles beyond the data or on {} unsupported fragments; {} pinholes closed",
                              trimmed.removed_triangles, trimmed.removed_components, trimmed.closed_pinholes));
  console.print(fmt::format("mesh time       {:.3f} s", seconds));
  console.print("wrote           " + output);
  return {{"file", output},
          {"vertices", topo.vertices},
          {"triangles", topo.triangles},
          {"boundary_edges", topo.boundary_edges},
          {"non_manifold_edges", topo.non_manifold_edges},
          {"euler_characteristic", topo.euler_characteristic},
          {"blended_nodes", surface.cut().size()},
          {"voxel_size", report.voxel_size},
          {"surface_cells", report.surface_cells},
          {"evaluated_corners", report.evaluated_corners},
          {"trimmed_triangles", trimmed.removed_triangles},
          {"removed_components", trimmed.removed_components},
          {"closed_pinholes", trimmed.closed_pinholes},
          {"mesh_seconds", seconds}};
}

}  // namespace clustersurf::cli
