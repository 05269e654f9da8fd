#include "mesh_stage.hpp"

#include "mesh_check_report.hpp"

#include <clustersurf/io/point_cloud_io.hpp>

#include <fmt/format.h>

#include <tbb/parallel_invoke.h>

namespace clustersurf::cli {

SurfaceMeshOptions surface_mesh_options(const MeshArgs& args) {
  ReconstructOptions o;
  set_options(o, args.options, {OptionStage::Mesh});
  return o.meshing;
}

nlohmann::json write_surface_mesh(Console& console, const SurfaceMesh& result, const MeshArgs& args,
                                  const std::string& output) {
  PlyWriteOptions ply;
  ply.binary = !args.ascii;
  MeshTopology topo;  // measured while the file is written
  tbb::parallel_invoke([&] { write_triangle_mesh(output, result.mesh, ply); },
                       [&] { topo = mesh_topology(result.mesh); });
  const TrimReport& trimmed = result.trim;
  console.print(
      fmt::format("mesh            {} vertices, {} triangles ({} blended nodes, voxel {:.4g}), {} boundary edges, "
                  "{} non-manifold edges",
                  topo.vertices, topo.triangles, result.blended_nodes, result.grid.voxel_size, topo.boundary_edges,
                  topo.non_manifold_edges));
  if (trimmed.removed_triangles > 0 || trimmed.closed_pinholes > 0)
    console.print(
        fmt::format("trimmed         {} triangles beyond the data or on {} unsupported fragments; {} pinholes closed",
                    trimmed.removed_triangles, trimmed.removed_components, trimmed.closed_pinholes));
  if (result.closing.closed)
    console.print(
        fmt::format("closed          {} of {} vertices filled in (the \"filled\" attribute), {} triangles; "
                    "{} holes larger than --fill-holes left open; fill grid cell {:.4g}",
                    result.closing.filled_vertices, topo.vertices, result.closing.filled_triangles,
                    result.closing.opened_holes, result.closing.fill_cell));
  if (result.decimation.triangles_after != result.decimation.triangles_before)
    console.print(fmt::format("decimated       {} -> {} triangles, surface moved by at most {:.4g}",
                              result.decimation.triangles_before, result.decimation.triangles_after,
                              result.decimation.deviation));
  console.print(fmt::format("mesh time       {:.3f} s", result.seconds));
  // A closed mesh is meant for printing and solids: say whether it is ready for that.
  if (result.closing.closed)
    for (const auto& line : mesh_check_lines(result.closing.check)) console.print(line);
  console.print("wrote           " + output);
  nlohmann::json report = nlohmann::json::parse(surface_mesh_json(result, topo));
  report["file"] = output;
  return report;
}

}  // namespace clustersurf::cli
