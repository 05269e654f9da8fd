#include "commands.hpp"

#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/mesh/mesh_check.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>

namespace clustersurf::cli {

namespace {

std::string describe(const MeshTopology& t) {
  if (t.triangles == 0) return fmt::format("point cloud, {} points", t.vertices);
  return fmt::format(
      "{} vertices, {} faces, {} boundary edges ({:.3g} of boundary per square root of area), {} "
      "non-manifold edges, {} components ({} loose fragments under {:g} % of the area), {}",
      t.vertices, t.triangles, t.boundary_edges, boundary_per_sqrt_area(t), t.non_manifold_edges, t.components,
      t.small_components, 100 * kSmallComponentShare, is_watertight(t) ? "watertight" : "not watertight");
}

}  // namespace

int run_eval(Console& console, const EvalArgs& args) {
  ReadOptions read;
  read.warn = [&console](const std::string& message) { console.warn(message); };
  const TriangleMesh recon = read_triangle_mesh(args.reconstruction, read);
  const TriangleMesh reference = read_triangle_mesh(args.reference, read);
  ComparisonOptions options;
  options.samples = args.samples;
  options.seed = args.seed;
  const SurfaceComparison e = compare_surfaces(recon, reference, options);
  const auto or_null = [](double x) { return std::isnan(x) ? nlohmann::json(nullptr) : nlohmann::json(x); };
  if (console.options().json) {
    nlohmann::json j{{"reconstruction", args.reconstruction},
                     {"reference", args.reference},
                     {"diagonal", e.diagonal},
                     {"accuracy", e.accuracy},
                     {"completeness", e.completeness},
                     {"chamfer", e.chamfer},
                     {"hausdorff", e.hausdorff},
                     {"distance_p95", e.distance_p95},
                     {"normal_consistency", or_null(e.normal_consistency)},
                     {"far_share", or_null(e.far_share)},
                     {"volume_iou", or_null(e.volume_iou)},
                     {"reference_spacing", e.reference_spacing},
                     {"samples", {{"reconstruction", e.reconstruction_samples}, {"reference", e.reference_samples}}},
                     {"reconstruction_mesh", nlohmann::json::parse(mesh_topology_json(e.reconstruction_topology))},
                     {"reference_mesh", nlohmann::json::parse(mesh_topology_json(e.reference_topology))}};
    for (const FScore& f : e.fscores)
      j["fscore"].push_back(
          {{"tau", f.threshold}, {"precision", f.precision}, {"recall", f.recall}, {"fscore", f.fscore}});
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  console.print(fmt::format("reconstruction  {} ({})", args.reconstruction, describe(e.reconstruction_topology)));
  console.print(fmt::format("reference       {} ({})", args.reference, describe(e.reference_topology)));
  console.print(fmt::format("distances as fractions of the reference diagonal ({:.6g})", e.diagonal));
  console.print(fmt::format("accuracy        {:.6f}  (reconstruction -> reference, mean)", e.accuracy));
  console.print(fmt::format("completeness    {:.6f}  (reference -> reconstruction, mean)", e.completeness));
  console.print(fmt::format("chamfer         {:.6f}", e.chamfer));
  console.print(fmt::format("95th percentile {:.6f}  (of both directions' distances)", e.distance_p95));
  console.print(fmt::format("hausdorff       {:.6f}", e.hausdorff));
  console.print(std::isnan(e.normal_consistency)
                    ? std::string("normals         n/a (one side has no normals)")
                    : fmt::format("normals         {:.4f}  (mean |n.n'|)", e.normal_consistency));
  if (!std::isnan(e.far_share))
    console.print(fmt::format("far surface     {:.4f} %  (farther than {:g} point spacings of the reference, {:.6g})",
                              100 * e.far_share, options.far_spacings, e.reference_spacing));
  if (!std::isnan(e.volume_iou))
    console.print(fmt::format("volume IoU      {:.4f}  (of the solids both closed meshes bound)", e.volume_iou));
  for (const FScore& f : e.fscores)
    console.print(fmt::format("F-score @{:.2f}%  {:.4f}  (precision {:.4f}, recall {:.4f})", 100 * f.threshold,
                              f.fscore, f.precision, f.recall));
  return 0;
}

}  // namespace clustersurf::cli
