#include <clustersurf/cluster/cluster_tree.hpp>

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

}  // namespace clustersurf
