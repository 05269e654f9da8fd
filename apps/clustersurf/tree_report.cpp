#include "tree_report.hpp"

#include <fmt/format.h>

namespace clustersurf::cli {

nlohmann::json tree_report_json(const ClusterTree& tree) { return nlohmann::json::parse(tree_info_json(tree)); }

std::vector<std::string> tree_report_lines(const ClusterTree& tree) {
  const TreeSummary s = summarize(tree);
  const TreeParameters& p = tree.parameters;
  const double diag = tree.bbox.diagonal();
  std::vector<std::string> out;
  out.push_back(tree.outliers() == 0 ? fmt::format("points          {}", tree.input_points)
                                     : fmt::format("points          {} ({} left out: outliers, repeated positions)",
                                                   tree.input_points, tree.outliers()));
  out.push_back(fmt::format("nodes           {} ({} leaves), depth {}", s.nodes, s.leaves, s.depth));
  std::string hist;
  for (std::size_t k = 0; k < kProxyKinds; ++k)
    if (s.proxy_histogram[k] != 0)
      hist +=
          fmt::format("{}{} {}", hist.empty() ? "" : ", ", s.proxy_histogram[k], to_string(static_cast<ProxyKind>(k)));
  out.push_back(fmt::format("leaf proxies    {}", hist));
  const auto& ls = s.leaf_size_percentiles;
  out.push_back(fmt::format("leaf size       min {:.0f}  p25 {:.0f}  median {:.0f}  p75 {:.0f}  max {:.0f}", ls[0],
                            ls[1], ls[2], ls[3], ls[4]));
  const auto& le = s.leaf_rms_percentiles;
  out.push_back(fmt::format("leaf RMS error  min {:.3g}  p25 {:.3g}  median {:.3g}  p75 {:.3g}  max {:.3g}", le[0],
                            le[1], le[2], le[3], le[4]));
  out.push_back(fmt::format(
      "threshold       {:.4g} ({:.4g} % of the diagonal {:.4g}); {} leaves above it (at min-points "
      "or max-depth)",
      tree.error_threshold, diag > 0 ? 100 * tree.error_threshold / diag : 0.0, diag, s.leaves_over_threshold));
  if (p.threshold_mode == ThresholdMode::Auto)
    out.push_back(fmt::format("noise estimate  {:.4g} ({:.4g} % of the diagonal)", tree.noise_sigma,
                              diag > 0 ? 100 * tree.noise_sigma / diag : 0.0));
  if (tree.point_spacing > 0)
    out.push_back(fmt::format("point spacing   {:.4g} (median, {:.4g} % of the diagonal)", tree.point_spacing,
                              diag > 0 ? 100 * tree.point_spacing / diag : 0.0));
  out.push_back(fmt::format(
      "parameters      proxy {}, splitter {}, error {}, tolerance {} {}, min-points {}, "
      "max-depth {}, alpha {}, kstep {}, support-factor {}, seed {}, creases {}",
      to_string(p.proxy), to_string(p.splitter), to_string(p.metric), to_string(p.threshold_mode), p.tolerance,
      p.min_points, p.max_depth, p.alpha, p.kstep == 0 ? std::string("auto") : std::to_string(p.kstep),
      p.support_factor, p.seed, p.creases ? "on" : "off"));
  return out;
}

}  // namespace clustersurf::cli
