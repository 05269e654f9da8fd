// The cluster tree of a cloud: options checked, outliers left out, the scale (spacing, noise)
// measured, the recursion (tree_builder.cpp) run over the working set, the tree flattened.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/cluster/noise.hpp>
#include <clustersurf/cluster/noise_field.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/cloud_index.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>
#include <clustersurf/spatial/repeated_positions.hpp>

#include "cluster/build_state.hpp"
#include "cluster/cluster_frame.hpp"
#include "cluster/estimated_normals.hpp"
#include "cluster/support_fit.hpp"
#include "cluster/support_sampler.hpp"
#include "cluster/tree_builder.hpp"
#include "core/progress_reporter.hpp"

#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

namespace clustersurf {

namespace {

void validate(const PointCloud& cloud, const BuildOptions& o) {
  if (cloud.empty()) throw OptionError("cannot build a tree from an empty point cloud");
  if (cloud.size() > std::numeric_limits<std::int32_t>::max()) throw OptionError("too many points (at most 2^31-1)");
  if (!(o.tolerance >= 0) || !std::isfinite(o.tolerance)) throw OptionError("tolerance must be a non-negative number");
  if (!(o.noise_factor >= 0) || !std::isfinite(o.noise_factor)) throw OptionError("noise factor must be >= 0");
  if (!(o.alpha >= 0) || !std::isfinite(o.alpha)) throw OptionError("alpha must be positive (or 0: automatic)");
  if (!(o.support_factor >= 0) || !std::isfinite(o.support_factor)) throw OptionError("support factor must be >= 0");
}

}  // namespace

ClusterTree build_cluster_tree(const PointCloud& cloud, const BuildOptions& options, const ProgressCallback& progress) {
  return build_cluster_tree(CloudIndex(cloud), options, progress);
}

ClusterTree build_cluster_tree(const CloudIndex& cloud_index, const BuildOptions& options,
                               const ProgressCallback& progress) {
  const PointCloud& cloud = cloud_index.cloud();
  validate(cloud, options);
  const auto stage = [&progress](std::string_view name) {
    if (progress && !progress(name, 0.0)) throw Cancelled();
  };
  // The k-d tree of the whole input finds the outliers, and the same neighbour pass gives the
  // point spacing; the points clustered are the input without them, and the k-d tree of those
  // serves the noise estimate and the support checks (and, through the index, the trim).
  stage("indexing points");
  cloud_index.points();
  detail::BuildScale scale;
  std::vector<std::uint32_t> ids;        // input index of each clustered point
  std::vector<std::uint8_t> coincident;  // the outlier test's rows with a repeat, when it ran
  if (options.remove_outliers) {
    stage("finding outliers");
    OutlierReport found = cloud_index.outliers(options.outliers);
    if (!found.outliers.empty() && !found.kept.empty()) ids.assign(found.kept.begin(), found.kept.end());
    coincident = std::move(found.coincident);
  }
  scale.point_spacing = cloud_index.median_spacing();
  if (ids.empty()) {
    ids.resize(static_cast<std::size_t>(cloud.size()));
    std::iota(ids.begin(), ids.end(), 0u);
  }
  // A point at the very position of an earlier one is left out like an outlier.
  ids = first_of_each_position(cloud.positions, std::move(ids), coincident);
  const CloudIndex::Subset clustered = cloud_index.rows(ids);
  scale.bbox = bounding_box(clustered.positions);
  // The input normals of the clustered points (rows as of clustered.positions), or null.
  const bool normals = options.use_normals && cloud.normals.rows() == cloud.positions.rows() && cloud.size() > 0;
  const bool subset = ids.size() != static_cast<std::size_t>(cloud.size());
  const Points subset_normals = normals && subset ? Points(cloud.normals(ids, Eigen::all)) : Points();
  const Points* clustered_normals = !normals ? nullptr : subset ? &subset_normals : &cloud.normals;
  NoiseEstimate noise_estimate;
  if (options.threshold_mode == ThresholdMode::Auto && options.noise_factor > 0) {
    stage("estimating noise");
    // With input normals, the two sides of a thin part or a narrow fold are not taken for noise.
    const Points* facing = options.noise.facing_normals ? clustered_normals : nullptr;
    noise_estimate =
        options.noise.local
            ? estimate_noise_field(clustered.positions, clustered.index, options.noise, facing)
            : NoiseEstimate{estimate_noise(clustered.positions, clustered.index, options.noise, facing), {}};
    scale.noise_sigma = noise_estimate.sigma;
    scale.noise_field = &noise_estimate.field;
  }
  return detail::build_tree(cloud, ids, clustered.positions, clustered.positions, clustered_normals, clustered.index,
                            scale, options, progress);
}

namespace {

/// The parameters the tree records of `options` (min_points decided later).
TreeParameters tree_parameters(const BuildOptions& options) {
  TreeParameters p;
  p.proxy = options.proxy;
  p.splitter = options.splitter;
  p.metric = options.metric;
  // Counting none of the noise is the relative tolerance alone: no estimate is made.
  const bool ignore_noise = options.threshold_mode == ThresholdMode::Auto && options.noise_factor == 0;
  p.threshold_mode = ignore_noise ? ThresholdMode::Relative : options.threshold_mode;
  p.tolerance = options.tolerance;
  p.noise_factor = options.noise_factor;
  p.max_depth = options.max_depth;
  p.alpha = options.alpha;
  p.kstep = options.kstep;
  p.lloyd_restarts = options.lloyd_restarts;
  p.proxy_lloyd_iterations = options.proxy_lloyd_iterations;
  p.support_factor = options.support_factor;
  p.seed = options.seed;
  p.creases = options.creases;
  return p;
}

/// Each input point's leaf (-1 for points not clustered): leaf n holds perm[begins[n] ...] in order.
std::vector<std::int32_t> point_leaves(const ClusterTree& tree, const std::vector<std::uint32_t>& begins,
                                       const std::vector<std::uint32_t>& perm, Eigen::Index input_points) {
  std::vector<std::int32_t> leaf(static_cast<std::size_t>(input_points), -1);
  for (std::size_t n = 0; n < tree.nodes.size(); ++n) {
    if (!tree.nodes[n].is_leaf()) continue;
    for (std::uint32_t k = 0; k < tree.nodes[n].point_count; ++k)
      leaf[perm[begins[n] + k]] = static_cast<std::int32_t>(n);
  }
  return leaf;
}

}  // namespace

ClusterTree detail::build_tree(const PointCloud& cloud, std::vector<std::uint32_t> ids, const Points& clustered,
                               const Points& support_points, const Points* support_normals, const KdTree& support_index,
                               const BuildScale& scale, const BuildOptions& options, const ProgressCallback& progress) {
  validate(cloud, options);
  if (ids.empty()) throw OptionError("cannot build a tree without points to cluster");
  ClusterTree tree;
  tree.input_points = static_cast<std::uint64_t>(cloud.size());
  tree.parameters = tree_parameters(options);
  TreeParameters& p = tree.parameters;

  // The input normals, indexed like the input (the working set's ids), outliers or not.
  const bool use_normals = options.use_normals && cloud.normals.rows() == cloud.positions.rows() && cloud.size() > 0;
  const Points* normals = use_normals ? &cloud.normals : nullptr;
  tree.point_spacing = scale.point_spacing;
  tree.bbox = bounding_box(clustered);
  tree.origin = cloud.origin;
  tree.up = cloud.up;
  const double diagonal = scale.bbox.diagonal();
  const double tolerance =
      p.threshold_mode == ThresholdMode::Absolute ? options.tolerance : options.tolerance * diagonal;
  double noise = 0;  // the noise the leaves may keep on top of the tolerance
  if (p.threshold_mode == ThresholdMode::Auto) {
    tree.noise_sigma = scale.noise_sigma;
    noise = options.noise_factor * tree.noise_sigma;
  }
  tree.error_threshold = std::hypot(tolerance, noise);

  BuildOptions resolved = options;  // the options with min_points and alpha decided
  if (resolved.min_points == 0) resolved.min_points = leaf_min_points(noise, scale.point_spacing);
  if (resolved.alpha == 0) resolved.alpha = support_alpha(noise, scale.point_spacing);
  p.min_points = resolved.min_points;
  p.alpha = resolved.alpha;

  const auto n = ids.size();
  detail::WorkingSet work{clustered, std::move(ids), std::vector<std::uint32_t>(n)};
  std::iota(work.local.begin(), work.local.end(), 0u);
  std::optional<detail::SupportSampler> sampler;
  std::optional<detail::SupportFit> support;
  if (options.support_factor > 0) {
    sampler.emplace(support_points, support_index);
    support.emplace(support_points, work.positions, *sampler, resolved, tolerance, noise,
                    use_normals && options.fit_normals ? support_normals : nullptr);
  }
  // The clusters' frames follow the input normals, or without them normals estimated over each
  // point's neighbourhood (slopes from a wider scale than a blob's own spread).
  std::optional<detail::EstimatedNormals> estimated;
  detail::FrameNormals frame_normals;
  if (options.frames_from_normals && normals != nullptr) {
    frame_normals.input = normals;
  } else if (options.frames_from_normals && noise > 0) {
    estimated.emplace(support_index, static_cast<std::size_t>(cloud.size()));
    frame_normals.estimated = &*estimated;
  }
  detail::ProgressReporter reporter(progress, "building tree", n);
  detail::BuildNode root;
  // Noise that is the points' own: below it the estimate reads facets and relief, and so would
  // the noise field.
  const bool noise_counts = noise > 0 && noise >= detail::kNoiseCountsShare * scale.point_spacing;
  const bool bias_tests = noise >= detail::kNoiseCountsShare * scale.point_spacing;
  detail::build_nodes(root, normals, frame_normals, work, support ? &*support : nullptr, resolved, tolerance, noise,
                      bias_tests, options.min_points == 0, reporter, noise_counts ? scale.noise_field : nullptr,
                      scale.noise_sigma);
  reporter.finish();
  const std::vector<std::uint32_t>& perm = work.ids;

  std::vector<std::uint32_t> begins;
  detail::flatten(root, tree, options.keep_point_leaves ? &begins : nullptr);
  if (options.keep_point_leaves) tree.point_leaf = point_leaves(tree, begins, perm, cloud.size());
  return tree;
}

}  // namespace clustersurf
