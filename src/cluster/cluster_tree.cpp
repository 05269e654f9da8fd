// ClusterTree's members, the option names and their parsers, and the thresholds a tree implies.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/errors.hpp>

#include "cluster/build_state.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace clustersurf {

namespace {

std::string quoted(std::string_view text) { return "\"" + std::string(text) + "\""; }

}  // namespace

const char* to_string(SplitterKind kind) { return kind == SplitterKind::SplitPlane ? "split-plane" : "lloyd"; }
const char* to_string(ErrorMetric metric) { return metric == ErrorMetric::Rms ? "rms" : "max"; }
const char* to_string(ThresholdMode mode) {
  switch (mode) {
    case ThresholdMode::Relative:
      return "relative";
    case ThresholdMode::Absolute:
      return "absolute";
    case ThresholdMode::Auto:
      return "auto";
  }
  return "unknown";
}

SplitterKind parse_splitter(std::string_view text) {
  for (SplitterKind kind : {SplitterKind::SplitPlane, SplitterKind::Lloyd})
    if (text == to_string(kind)) return kind;
  throw OptionError("splitter must be split-plane or lloyd, not " + quoted(text));
}

ErrorMetric parse_error_metric(std::string_view text) {
  for (ErrorMetric metric : {ErrorMetric::Rms, ErrorMetric::Max})
    if (text == to_string(metric)) return metric;
  throw OptionError("error metric must be rms or max, not " + quoted(text));
}

std::uint32_t leaf_min_points(double noise, double spacing) {
  constexpr double kCoefficients = 6;
  constexpr double kSparse = 12, kNoisy = 20;
  if (!(noise > 0)) return static_cast<std::uint32_t>(kSparse);
  if (!(spacing > 0)) return static_cast<std::uint32_t>(kNoisy);
  const double ratio = 4 * noise / spacing;  // the noise against a quarter of the spacing
  const double n = kCoefficients * ratio * ratio;
  return static_cast<std::uint32_t>(std::clamp(std::ceil(n), kSparse, kNoisy));
}

double support_alpha(double noise, double spacing) {
  constexpr double kNarrow = 0.75, kWide = 1.0;
  constexpr double kLowNoise = detail::kNoiseCountsShare, kHighNoise = 0.5;  // σ / h where the widening starts and ends
  if (!(noise > 0) || !(spacing > 0)) return kNarrow;
  const double share = std::clamp((noise / spacing - kLowNoise) / (kHighNoise - kLowNoise), 0.0, 1.0);
  return kNarrow + share * (kWide - kNarrow);
}

double cluster_error_threshold(const ClusterTree& tree, double points, double noise_scale) {
  const TreeParameters& p = tree.parameters;
  const double noise = p.threshold_mode == ThresholdMode::Auto ? p.noise_factor * tree.noise_sigma : 0.0;
  const double tolerance = std::sqrt(std::max(0.0, tree.error_threshold * tree.error_threshold - noise * noise));
  return detail::allowed_error(tolerance, noise_scale * noise, points);
}

std::vector<std::int32_t> ClusterTree::leaves() const {
  std::vector<std::int32_t> out;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].is_leaf()) out.push_back(static_cast<std::int32_t>(i));
  return out;
}

std::uint32_t ClusterTree::depth() const {
  std::uint32_t d = 0;
  for (const auto& n : nodes) d = std::max(d, n.depth);
  return d;
}

}  // namespace clustersurf
