#include <clustersurf/cluster/cluster_tree.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>

namespace clustersurf {

namespace {
std::array<double, 5> quartiles(std::vector<double> v) {
  std::array<double, 5> q{};
  if (v.empty()) return q;
  std::sort(v.begin(), v.end());
  for (int k = 0; k < 5; ++k) {
    const double pos = 0.25 * k * static_cast<double>(v.size() - 1);
    const auto lo = static_cast<std::size_t>(pos);
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    q[static_cast<std::size_t>(k)] = v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
  }
  return q;
}
}  // namespace

TreeSummary summarize(const ClusterTree& tree) {
  TreeSummary s;
  s.nodes = tree.nodes.size();
  s.depth = tree.depth();
  std::vector<double> sizes, errors;
  for (const auto& n : tree.nodes) {
    if (!n.is_leaf()) continue;
    ++s.leaves;
    ++s.proxy_histogram[static_cast<std::size_t>(n.proxy.kind())];
    sizes.push_back(n.point_count);
    errors.push_back(n.rms_error);
    const double e = tree.parameters.metric == ErrorMetric::Rms ? n.rms_error : n.max_error;
    if (e > cluster_error_threshold(tree, n.point_count)) ++s.leaves_over_threshold;
  }
  s.leaf_size_percentiles = quartiles(std::move(sizes));
  s.leaf_rms_percentiles = quartiles(std::move(errors));
  return s;
}

std::string tree_info_json(const ClusterTree& tree) {
  const TreeSummary s = summarize(tree);
  const TreeParameters& p = tree.parameters;
  nlohmann::json hist;
  for (std::size_t k = 0; k < kProxyKinds; ++k) hist[to_string(static_cast<ProxyKind>(k))] = s.proxy_histogram[k];
  const auto pct = [](const std::array<double, 5>& a) {
    return nlohmann::json{{"min", a[0]}, {"p25", a[1]}, {"median", a[2]}, {"p75", a[3]}, {"max", a[4]}};
  };
  const nlohmann::json report = {
      {"nodes", s.nodes},
      {"leaves", s.leaves},
      {"depth", s.depth},
      {"input_points", tree.input_points},
      {"outliers", tree.outliers()},
      {"has_point_leaves", !tree.point_leaf.empty()},
      {"bbox_min", {tree.bbox.min.x(), tree.bbox.min.y(), tree.bbox.min.z()}},
      {"bbox_max", {tree.bbox.max.x(), tree.bbox.max.y(), tree.bbox.max.z()}},
      {"diagonal", tree.bbox.diagonal()},
      {"leaf_proxies", hist},
      {"leaf_size", pct(s.leaf_size_percentiles)},
      {"leaf_rms_error", pct(s.leaf_rms_percentiles)},
      {"leaves_over_threshold", s.leaves_over_threshold},
      {"noise_sigma", tree.noise_sigma},
      {"error_threshold", tree.error_threshold},
      {"point_spacing", tree.point_spacing},
      {"parameters",
       {{"proxy", to_string(p.proxy)},
        {"splitter", to_string(p.splitter)},
        {"error_metric", to_string(p.metric)},
        {"threshold_mode", to_string(p.threshold_mode)},
        {"tolerance", p.tolerance},
        {"creases", p.creases},
        {"noise_factor", p.noise_factor},
        {"min_points", p.min_points},
        {"max_depth", p.max_depth},
        {"alpha", p.alpha},
        {"kstep", p.kstep},
        {"lloyd_restarts", p.lloyd_restarts},
        {"proxy_lloyd_iterations", p.proxy_lloyd_iterations},
        {"support_factor", p.support_factor},
        {"seed", p.seed}}},
  };
  return report.dump();
}

}  // namespace clustersurf
