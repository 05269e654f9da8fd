#include "commands.hpp"
#include "input.hpp"
#include "mesh_stage.hpp"
#include "tree_report.hpp"

#include <clustersurf/errors.hpp>
#include <clustersurf/orientation.hpp>
#include <clustersurf/tree_file.hpp>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include <chrono>
#include <iostream>

namespace clustersurf::cli {

namespace {

ProxyKind parse_proxy(const std::string& s) {
  if (s == "plane") return ProxyKind::Plane;
  if (s == "poly") return ProxyKind::Poly;
  if (s == "quadric") return ProxyKind::Quadric;
  throw OptionError("--proxy must be plane, poly or quadric, not \"" + s + "\"");
}

BuildOptions build_options(const ReconstructArgs& a) {
  BuildOptions o;
  o.proxy = parse_proxy(a.proxy);
  if (a.splitter == "split-plane") o.splitter = SplitterKind::SplitPlane;
  else if (a.splitter == "lloyd") o.splitter = SplitterKind::Lloyd;
  else throw OptionError("--splitter must be split-plane or lloyd, not \"" + a.splitter + "\"");
  if (a.error_metric == "rms") o.metric = ErrorMetric::Rms;
  else if (a.error_metric == "max") o.metric = ErrorMetric::Max;
  else throw OptionError("--error must be rms or max, not \"" + a.error_metric + "\"");
  if (a.absolute_error) {
    o.threshold_mode = ThresholdMode::Absolute;
    o.threshold = *a.absolute_error;
  } else {
    // The tolerance on top of the estimated noise; a noise factor of 0 ignores the noise.
    o.threshold_mode = a.noise_factor > 0 ? ThresholdMode::Auto : ThresholdMode::Relative;
    if (a.noise_factor > 0) o.noise_factor = a.noise_factor;
  }
  if (!a.absolute_error && a.max_error != "auto") {
    std::size_t used = 0;
    try {
      o.threshold = std::stod(a.max_error, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != a.max_error.size() || !(o.threshold >= 0))
      throw OptionError("--max-error must be \"auto\" or a non-negative fraction of the diagonal, not \"" + a.max_error + "\"");
  }
  if (a.min_points != "auto") {
    std::size_t used = 0;
    unsigned long value = 0;
    try {
      value = std::stoul(a.min_points, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != a.min_points.size() || value < 1 || value > (1u << 30))
      throw OptionError("--min-points must be \"auto\" or a whole number from 1 to 2^30, not \"" + a.min_points + "\"");
    o.min_points = static_cast<std::uint32_t>(value);
  }
  o.max_depth = a.max_depth;
  o.alpha = a.alpha;
  o.kstep = a.kstep;
  o.lloyd_restarts = a.lloyd_restarts;
  o.proxy_lloyd_iterations = a.proxy_lloyd;
  o.support_factor = a.support_factor;
  o.seed = a.seed;
  o.keep_point_leaves = !a.no_point_leaves;
  o.remove_outliers = !a.keep_outliers;
  o.use_normals = !a.ignore_normals;
  return o;
}

/// Refuses a cloud that spans no surface: every point at one place, or all on one line (the
/// spread across the main direction vanishes next to the spread along it). Computed about the
/// centroid, so a cloud far from the origin is judged as one near it.
void require_surface_extent(const std::string& file, const PointCloud& cloud) {
  const Eigen::RowVector3d mean = cloud.positions.colwise().mean();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i) {
    const Eigen::Vector3d d = (cloud.positions.row(i) - mean).transpose();
    covariance.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d spread = eig.eigenvalues();  // ascending
  const std::string n = std::to_string(cloud.size());
  if (!(spread(2) > 0)) throw InputError(file, {}, "all " + n + " points coincide: there is no surface to reconstruct");
  if (!(spread(1) > 1e-18 * spread(2)))
    throw InputError(file, {}, "all " + n + " points lie on one line: there is no surface to reconstruct");
}

}  // namespace

int run_reconstruct(Console& console, const ReconstructArgs& args) {
  if (args.tree_output.empty() && args.mesh_output.empty())
    throw OptionError("nothing to write: give -o TREE.cstree and/or --mesh MESH.ply");
  BuildOptions options = build_options(args);
  const auto t0 = std::chrono::steady_clock::now();
  const PointCloud cloud = read_input(console, args.input);
  require_surface_extent(args.input.file, cloud);
  const auto t1 = std::chrono::steady_clock::now();
  options.progress = console.progress();
  ClusterTree tree = build_cluster_tree(cloud, options);
  console.end_progress();
  PointCloud positions_only;
  if (args.ignore_normals) positions_only.positions = cloud.positions;
  const OrientationReport orientation = orient_tree(tree, args.ignore_normals ? positions_only : cloud);
  const auto t2 = std::chrono::steady_clock::now();
  // Every long step (build, mesh) runs before any file is written, so an interrupted run leaves
  // no output at all.
  const auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  const std::string oriented =
      orientation.used_normals ? std::string("by input normals")
                               : fmt::format("by propagation ({} component{})", orientation.components,
                                             orientation.components == 1 ? "" : "s");

  if (console.options().json) {
    nlohmann::json j = tree_report_json(tree);
    j["input"] = args.input.file;
    if (!args.tree_output.empty()) j["tree"] = args.tree_output;
    j["timing"] = {{"read_seconds", seconds(t0, t1)}, {"build_seconds", seconds(t1, t2)}};
    j["orientation"] = {{"used_normals", orientation.used_normals}, {"components", orientation.components},
                        {"flipped", orientation.flipped}};
    if (!args.mesh_output.empty()) j["mesh"] = write_tree_mesh(console, tree, args.mesh, args.mesh_output, &cloud);
    if (!args.tree_output.empty()) save_tree(args.tree_output, tree);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  for (const auto& line : tree_report_lines(tree)) console.print(line);
  console.print("orientation     " + oriented);
  console.print(fmt::format("time            read {:.3f} s, build {:.3f} s", seconds(t0, t1), seconds(t1, t2)));
  if (!args.mesh_output.empty()) write_tree_mesh(console, tree, args.mesh, args.mesh_output, &cloud);
  if (!args.tree_output.empty()) {
    save_tree(args.tree_output, tree);
    console.print("wrote           " + args.tree_output);
  }
  return 0;
}

}  // namespace clustersurf::cli
