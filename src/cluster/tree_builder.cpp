// Recursive construction of the cluster tree (thesis ch. 3), subtrees in parallel.

#include <clustersurf/cluster_tree.hpp>
#include <clustersurf/errors.hpp>
#include <clustersurf/kd_tree.hpp>
#include <clustersurf/noise.hpp>

#include "core/splitmix.hpp"
#include "cluster/residual_structure.hpp"
#include "cluster/splitters.hpp"
#include "cluster/support_sampler.hpp"
#include "core/progress_reporter.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>

namespace clustersurf {

namespace {

/// Clusters at least this large build their two subtrees as parallel tasks.
constexpr std::size_t kParallelGrain = 2048;
/// The support check evaluates at most about this many of the points inside a support.
constexpr std::size_t kSupportSample = 2048;
/// A leaf failing the support check shrinks its support by this factor, at most this often.
constexpr double kSupportShrinkFactor = 0.8;
constexpr int kSupportShrinkSteps = 10;
/// A support sphere holds about this many times its cluster's points (measured on scans).
constexpr std::size_t kSupportPointsPerClusterPoint = 8;
/// The support fit leaves out points farther than this many thresholds from the cluster's fit.
constexpr double kSupportFitReach = 3;
/// Fewer support points than this keep the cluster's own fit.
constexpr std::size_t kMinSupportFitPoints = 12;
/// Rounds of the trimmed support fit: points farther than kSupportFitReach times the fit's
/// weighted RMS (or the threshold) from it are left out and the rest refitted, as long as they
/// are isolated strays: at most kMaxTrimmedShare of the points (or one; more is a second sheet
/// or real detail, which the split and the support checks deal with).
constexpr int kTrimRounds = 2;
constexpr double kMaxTrimmedShare = 0.05;
/// A support sphere holds at least this many input points (MPU's N_min): the supports of small
/// clusters overlap their neighbours' instead of leaving gaps between them, and their refit
/// rests on enough points. It grows to at most kMaxSupportGrowth times its alpha radius, so a
/// few stray points never reach across a gap.
constexpr std::size_t kMinSupportPoints = 30;
constexpr double kMaxSupportGrowth = 4;
/// The noise a test allows is σ² (1 + kNoiseMargin √(2/n)) for an RMS over n (effective)
/// points: the RMS² of pure noise varies by a relative √(2/n), so a cluster or a support is not
/// split or shrunk for noise alone (about 2 standard deviations of margin).
constexpr double kNoiseMargin = 2;
/// A would-be leaf on two sheets facing apart is split into them while each keeps this many
/// points (a plane's worth): a sheet's few points are real surface, and a leaf's proxy rests
/// on its support fit (at least kMinSupportPoints) rather than on its own points alone.
constexpr std::size_t kMinSheetPoints = 3;

/// The error a test over n points allows: the tolerance plus the noise with its margin.
double allowed_error(double tolerance, double noise, double n) {
  const double margin = n > 0 ? 1 + kNoiseMargin * std::sqrt(2 / n) : 1;
  return std::sqrt(tolerance * tolerance + noise * noise * margin);
}

struct BuildNode {
  ClusterNode node;
  std::uint32_t begin = 0;  // offset of the cluster's rows in the working copy
  std::unique_ptr<BuildNode> left, right;
};

/// The points in cluster order: every cluster's points are contiguous rows, so the passes over
/// a cluster read memory sequentially instead of gathering from the whole input.
struct WorkingSet {
  Points positions;               // positions[j] = input.positions[ids[j]]
  std::vector<std::uint32_t> ids; // input index of each row
  std::vector<std::uint32_t> local;  // the splitters' index ranges; local[j] == j between splits

  /// Moves rows [begin, begin + order.size()) into the order a splitter left in `order`
  /// (a permutation of those rows), and makes `order` the identity again.
  void apply(std::uint32_t begin, std::span<std::uint32_t> order) {
    const auto m = static_cast<Eigen::Index>(order.size());
    Points rows(m, 3);
    std::vector<std::uint32_t> moved(order.size());
    for (Eigen::Index k = 0; k < m; ++k) {
      const auto j = order[static_cast<std::size_t>(k)];
      rows.row(k) = positions.row(j);
      moved[static_cast<std::size_t>(k)] = ids[j];
    }
    positions.middleRows(begin, m) = rows;
    std::copy(moved.begin(), moved.end(), ids.begin() + begin);
    std::iota(order.begin(), order.end(), begin);
  }
};

/// Smallest sphere containing spheres a and b.
Sphere enclose(const Sphere& a, const Sphere& b) {
  const Eigen::Vector3d d = b.center - a.center;
  const double dist = d.norm();
  if (dist + b.radius <= a.radius) return a;
  if (dist + a.radius <= b.radius) return b;
  const double r = 0.5 * (dist + a.radius + b.radius);
  // Pad by a relative epsilon so rounding never leaves a child's sphere sticking out.
  return Sphere{a.center + d * ((r - a.radius) / dist), r * (1 + 1e-12)};
}

class Builder {
 public:
  /// `tolerance`: the error a leaf may keep beyond the noise; `noise`: the noise level the
  /// leaves may keep (0 when the threshold ignores noise). Both in the input's units.
  /// `normals`: the input normals, indexed like the input cloud (WorkingSet::ids), or null.
  Builder(const Points& input, const Points* normals, WorkingSet& work, const detail::SupportSampler* index,
          const BuildOptions& options, double tolerance, double noise, detail::ProgressReporter& progress)
      : input_(input),
        normals_(normals),
        work_(work),
        points_(work.positions),
        index_(index),
        options_(options),
        tolerance_(tolerance),
        noise_(noise),
        progress_(progress) {}

  void build(BuildNode& bn, std::span<std::uint32_t> range, std::uint32_t depth, std::uint64_t path_seed) const {
    progress_.check();
    ClusterNode& node = bn.node;
    node.depth = depth;
    node.point_count = static_cast<std::uint32_t>(range.size());

    const Frame frame = pca_frame(points_, range);
    node.proxy = options_.proxy == ProxyKind::Poly ? Proxy(fit_poly_in_frame(frame, points_, range))
                                                   : fit_proxy(options_.proxy, points_, range);
    const ProxyError err = proxy_error(node.proxy, points_, range);
    node.rms_error = err.rms;
    node.max_error = err.max;
    BoundingBox box;
    for (auto i : range) box.extend(points_.row(i).transpose());
    node.support = Sphere{frame.origin, options_.alpha * box.diagonal()};
    const double cover = std::min(coverage_radius(frame.origin), kMaxSupportGrowth * node.support.radius);
    node.support.radius = std::max(node.support.radius, cover);
    node.bound = node.support;

    const double e = options_.metric == ErrorMetric::Rms ? err.rms : err.max;
    const bool can_split = depth < options_.max_depth && range.size() >= 2 * std::size_t{options_.min_points};
    const double threshold = allowed(tolerance_, static_cast<double>(range.size()));
    // Over its support a proxy may keep the noise plus support_factor times the tolerance.
    const auto support_fails = [&](const SupportError& s, double tolerance) {
      return s.rms > allowed(options_.support_factor * tolerance, s.effective_points);
    };
    std::optional<SupportError> support;  // the support check's error, once computed
    std::size_t k = 0;
    // A cluster is split when its error exceeds the threshold, when its residuals show structure
    // that noise does not leave, or when its proxy fails over its support.
    if (can_split && (e > threshold || systematic_misfit(node.proxy, frame, range) ||
                      (index_ != nullptr && support_fails(*(support = check_support(node, range)), tolerance_)))) {
      k = options_.splitter == SplitterKind::SplitPlane ? detail::split_plane(points_, range, frame, options_, noise_)
                                                        : detail::lloyd_split(points_, range, options_, detail::splitmix64(path_seed));
    } else if (range.size() >= 2) {
      // The proxy fits, but the cluster may be two parts with empty space between them (below
      // 2 × min_points only stray points across a wide gap are cut off).
      k = detail::split_at_gap(points_, range, frame, options_.min_points);
    }
    // A would-be leaf on two sheets facing apart (both sides of a thin part, the faces of a
    // deep fold) becomes one leaf per sheet, below min_points if need be.
    if ((k == 0 || k >= range.size()) && normals_ != nullptr && depth < options_.max_depth)
      k = detail::split_two_sheets(*normals_, work_.ids, range, kMinSheetPoints);
    if (k == 0 || k >= range.size()) {
      // A leaf that cannot be split (too few points, or no split helps) but whose proxy is off
      // over its support — typically a cluster of two small patches far apart — keeps only the
      // part of its support where the proxy holds, so it does not blend nonsense into its
      // neighbours' surface.
      if (index_ != nullptr) {
        if (!support) support = check_support(node, range);
        // A leaf held at min_points may miss the threshold on its own points too; measure its
        // support against what it achieves there.
        const double own = std::sqrt(std::max(0.0, e * e - noise_ * noise_));
        const double tolerance = std::max(tolerance_, own);
        for (int shrink = 0; shrink < kSupportShrinkSteps && support_fails(*support, tolerance) && node.support.radius > cover; ++shrink) {
          node.support.radius = std::max(cover, node.support.radius * kSupportShrinkFactor);
          support = check_support(node, range);
        }
        node.bound = node.support;
      }
      std::iota(range.begin(), range.end(), bn.begin);
      progress_.advance(range.size());
      return;
    }
    work_.apply(bn.begin, range);
    bn.left = std::make_unique<BuildNode>();
    bn.right = std::make_unique<BuildNode>();
    bn.left->begin = bn.begin;
    bn.right->begin = bn.begin + static_cast<std::uint32_t>(k);
    const auto left_range = range.subspan(0, k);
    const auto right_range = range.subspan(k);
    const std::uint64_t ls = detail::splitmix64(path_seed * 2 + 1), rs = detail::splitmix64(path_seed * 2 + 2);
    if (range.size() >= kParallelGrain) {
      tbb::parallel_invoke([&] { build(*bn.left, left_range, depth + 1, ls); },
                           [&] { build(*bn.right, right_range, depth + 1, rs); });
    } else {
      build(*bn.left, left_range, depth + 1, ls);
      build(*bn.right, right_range, depth + 1, rs);
    }
    node.bound = enclose(enclose(node.support, bn.left->node.bound), bn.right->node.bound);
  }

 private:
  /// The radius around `center` that holds kMinSupportPoints input points (0 without an index).
  double coverage_radius(const Eigen::Vector3d& center) const {
    if (index_ == nullptr) return 0;
    thread_local std::vector<Neighbor> nearest;
    index_->full().knn(center, kMinSupportPoints, nearest);
    return nearest.empty() ? 0 : std::sqrt(nearest.back().distance_squared);
  }

  double allowed(double tolerance, double n) const { return allowed_error(tolerance, noise_, n); }

  /// Whether the proxy's residuals over the cluster correlate between neighbours more than
  /// independent noise lets them: kNoiseMargin times its spread, at most √(2/n) (relief the
  /// proxy does not follow, even below the noise the threshold allows). Without noise in the
  /// threshold the error alone decides, and nothing is computed.
  bool systematic_misfit(const Proxy& proxy, const Frame& frame, std::span<const std::uint32_t> range) const {
    if (!(noise_ > 0)) return false;
    const double limit = kNoiseMargin * std::sqrt(2 / static_cast<double>(range.size()));
    return detail::residual_correlation(points_, range, frame, proxy) > limit;
  }

  /// The weighted RMS of |Q| over a support and the effective number of points behind it,
  /// (Σw)² / Σw².
  struct SupportError {
    double rms = 0;
    double effective_points = 0;
  };

  /// The support check: a bounded sample of the input points inside the node's support; a
  /// polynomial proxy is refitted to them (below); returns the weighted RMS of |Q| over them.
  SupportError check_support(ClusterNode& node, std::span<const std::uint32_t> range) const {
    const double r2 = node.support.radius * node.support.radius;
    if (!(r2 > 0)) return {};
    thread_local std::vector<Neighbor> inside;
    index_->inside(node.support.center, node.support.radius, kSupportPointsPerClusterPoint * node.point_count,
                   kSupportSample, inside);
    if (std::holds_alternative<PolyProxy>(node.proxy.variant())) fit_to_support(node, range, inside);
    double sum = 0, weight = 0, weight2 = 0;
    for (const auto& nb : inside) {
      const double w = blend_weight(nb.distance_squared / r2);
      const double q = node.proxy.value(input_.row(nb.index).transpose());
      sum += w * q * q;
      weight += w;
      weight2 += w * w;
    }
    if (!(weight > 0)) return {};
    return {std::sqrt(sum / weight), weight * weight / weight2};
  }

  /// Refits a polynomial proxy, in its cluster's frame, to the support points weighted by the
  /// blending weight (as in MPU): the proxy is then accurate wherever the blend uses it, and
  /// averages the noise over its whole support. Points beyond kSupportFitReach times the
  /// threshold or the cluster's own error from the cluster's fit (another sheet, outliers) are
  /// left out; then, kTrimRounds times, those beyond kSupportFitReach times the support fit's
  /// own weighted RMS (a stray point near the surface that bent the cluster's fit) are left out
  /// and the rest refitted. The node's errors are re-measured on its own points, but for a few
  /// strays beyond that reach.
  void fit_to_support(ClusterNode& node, std::span<const std::uint32_t> range, std::span<const Neighbor> inside) const {
    const PolyProxy& cluster_fit = std::get<PolyProxy>(node.proxy.variant());
    const double r2 = node.support.radius * node.support.radius;
    const double threshold = allowed(tolerance_, static_cast<double>(range.size()));
    const double reach = kSupportFitReach * std::max(threshold, node.rms_error);
    thread_local std::vector<std::uint32_t> ids;
    thread_local std::vector<double> weights;
    ids.clear();
    weights.clear();
    for (const auto& nb : inside) {
      if (!(std::abs(node.proxy.value(input_.row(nb.index).transpose())) <= reach)) continue;
      ids.push_back(nb.index);
      weights.push_back(blend_weight(nb.distance_squared / r2));
    }
    if (ids.size() < kMinSupportFitPoints) return;
    Proxy fit = fit_poly_in_frame(cluster_fit.frame, input_, ids, weights);
    // |Q| of `fit` at every support point, and the residual beyond which a point is a stray.
    thread_local std::vector<double> residual;
    const auto measure = [&] {
      residual.resize(ids.size());
      double sum = 0, weight = 0;
      for (std::size_t j = 0; j < ids.size(); ++j) {
        residual[j] = std::abs(fit.value(input_.row(ids[j]).transpose()));
        sum += weights[j] * residual[j] * residual[j];
        weight += weights[j];
      }
      return kSupportFitReach * std::max(threshold, weight > 0 ? std::sqrt(sum / weight) : 0.0);
    };
    const auto few = [](std::size_t strays, std::size_t total) {
      return static_cast<double>(strays) <= std::max(1.0, kMaxTrimmedShare * static_cast<double>(total));
    };
    const std::size_t support_points = ids.size();
    double cut = measure();
    for (int round = 0; round < kTrimRounds; ++round) {
      const auto kept = static_cast<std::size_t>(std::count_if(residual.begin(), residual.end(), [&](double q) { return q <= cut; }));
      if (kept == ids.size() || kept < kMinSupportFitPoints || !few(support_points - kept, support_points)) break;
      std::size_t k = 0;
      for (std::size_t j = 0; j < ids.size(); ++j) {
        if (!(residual[j] <= cut)) continue;
        ids[k] = ids[j];
        weights[k++] = weights[j];
      }
      ids.resize(k);
      weights.resize(k);
      fit = fit_poly_in_frame(cluster_fit.frame, input_, ids, weights);
      cut = measure();
    }
    // Kept only while the cluster's own points still meet the threshold (or what the cluster's
    // fit achieved): a leaf's error on its points stays within the threshold. A few own points
    // beyond the stray cut (a stray that bent the cluster's fit) are not counted.
    double inlier_sum = 0, inlier_max = 0, all_sum = 0, all_max = 0;
    std::size_t inliers = 0;
    for (auto i : range) {
      const double q = std::abs(fit.value(points_.row(i).transpose()));
      all_sum += q * q;
      all_max = std::max(all_max, q);
      if (!(q <= cut)) continue;
      inlier_sum += q * q;
      inlier_max = std::max(inlier_max, q);
      ++inliers;
    }
    const bool trim = inliers > 0 && few(range.size() - inliers, range.size());
    const double rms = trim ? std::sqrt(inlier_sum / static_cast<double>(inliers)) : std::sqrt(all_sum / static_cast<double>(range.size()));
    const double max = trim ? inlier_max : all_max;
    const double e = options_.metric == ErrorMetric::Rms ? rms : max;
    const double own = options_.metric == ErrorMetric::Rms ? node.rms_error : node.max_error;
    if (!(e <= std::max(threshold, own))) return;
    node.proxy = std::move(fit);
    node.rms_error = rms;
    node.max_error = max;
  }

  /// The blending weight (1 − s)³ at s = d²/r² (the implicit surface's).
  static double blend_weight(double s) {
    const double t = 1 - s;
    return t * t * t;
  }

  const Points& input_;   // the clustered points in input order (indexed by the k-d tree)
  const Points* normals_; // the input cloud's normals (rows: WorkingSet::ids), or null
  WorkingSet& work_;      // the input in cluster order; subtrees touch disjoint rows
  const Points& points_;  // work_.positions
  const detail::SupportSampler* index_;
  const BuildOptions& options_;
  double tolerance_;
  double noise_;
  detail::ProgressReporter& progress_;
};

void validate(const PointCloud& cloud, const BuildOptions& o) {
  if (cloud.empty()) throw OptionError("cannot build a tree from an empty point cloud");
  if (cloud.size() > std::numeric_limits<std::int32_t>::max()) throw OptionError("too many points (at most 2^31-1)");
  if (!(o.threshold >= 0) || !std::isfinite(o.threshold)) throw OptionError("error threshold must be a non-negative number");
  if (!(o.noise_factor > 0) || !std::isfinite(o.noise_factor)) throw OptionError("noise factor must be positive");
  if (!(o.alpha > 0) || !std::isfinite(o.alpha)) throw OptionError("alpha must be positive");
  if (!(o.support_factor >= 0) || !std::isfinite(o.support_factor)) throw OptionError("support factor must be >= 0");
}

/// Pre-order flattening; children are appended after their parent.
void flatten(BuildNode& root, ClusterTree& tree, std::vector<std::uint32_t>* leaf_begin) {
  struct Item {
    BuildNode* node;
    std::int32_t parent;
    bool is_left;
  };
  std::vector<Item> stack{{&root, -1, false}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    const auto index = static_cast<std::int32_t>(tree.nodes.size());
    ClusterNode n = it.node->node;
    n.parent = it.parent;
    n.left = n.right = -1;
    tree.nodes.push_back(n);
    if (leaf_begin != nullptr) leaf_begin->push_back(it.node->begin);
    if (it.parent >= 0) {
      ClusterNode& p = tree.nodes[static_cast<std::size_t>(it.parent)];
      (it.is_left ? p.left : p.right) = index;
    }
    if (it.node->left) {
      stack.push_back({it.node->right.get(), index, false});
      stack.push_back({it.node->left.get(), index, true});
    }
  }
}

}  // namespace

const char* to_string(SplitterKind kind) { return kind == SplitterKind::SplitPlane ? "split-plane" : "lloyd"; }
const char* to_string(ErrorMetric metric) { return metric == ErrorMetric::Rms ? "rms" : "max"; }
const char* to_string(ThresholdMode mode) {
  switch (mode) {
    case ThresholdMode::Relative: return "relative";
    case ThresholdMode::Absolute: return "absolute";
    case ThresholdMode::Auto: return "auto";
  }
  return "unknown";
}

std::uint32_t leaf_min_points(double noise, double tolerance) {
  constexpr double kCoefficients = 6;
  constexpr double kClean = 15, kNoisy = 20;
  if (!(noise > 0)) return static_cast<std::uint32_t>(kClean);
  const double n = tolerance > 0 ? kCoefficients * (noise / tolerance) * (noise / tolerance) : kNoisy;
  return static_cast<std::uint32_t>(std::clamp(std::ceil(n), kClean, kNoisy));
}

double cluster_error_threshold(const TreeParameters& p, double points) {
  const double noise = p.threshold_mode == ThresholdMode::Auto ? p.noise_factor * p.noise_sigma : 0.0;
  const double tolerance = std::sqrt(std::max(0.0, p.error_threshold * p.error_threshold - noise * noise));
  return allowed_error(tolerance, noise, points);
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

ClusterTree build_cluster_tree(const PointCloud& cloud, const BuildOptions& options) {
  validate(cloud, options);
  ClusterTree tree;
  tree.input_points = static_cast<std::uint64_t>(cloud.size());
  TreeParameters& p = tree.parameters;
  p.proxy = options.proxy;
  p.splitter = options.splitter;
  p.metric = options.metric;
  p.threshold_mode = options.threshold_mode;
  p.threshold = options.threshold;
  p.noise_factor = options.noise_factor;
  p.max_depth = options.max_depth;
  p.alpha = options.alpha;
  p.kstep = options.kstep;
  p.lloyd_restarts = options.lloyd_restarts;
  p.proxy_lloyd_iterations = options.proxy_lloyd_iterations;
  p.support_factor = options.support_factor;
  p.seed = options.seed;

  // The points clustered: the input, or the input without its outliers. One k-d tree of them
  // serves the noise estimate and the support check.
  const bool need_index = options.support_factor > 0 || options.threshold_mode == ThresholdMode::Auto;
  std::optional<KdTree> index;
  Points kept_positions;
  std::vector<std::uint32_t> ids;  // input index of each clustered point
  const Points* points = &cloud.positions;
  // The input normals, indexed like the input (the working set's ids), outliers or not.
  const bool use_normals = options.use_normals && cloud.normals.rows() == cloud.positions.rows() && cloud.size() > 0;
  const Points* normals = use_normals ? &cloud.normals : nullptr;
  if (options.remove_outliers) {
    if (options.progress && !options.progress("finding outliers", 0.0)) throw Cancelled();
    KdTree all(cloud.positions);
    const OutlierReport found = find_outliers(cloud.positions, all, options.outliers);
    if (!found.outliers.empty() && !found.kept.empty()) {
      kept_positions = cloud.positions(found.kept, Eigen::all);
      points = &kept_positions;
      ids.assign(found.kept.begin(), found.kept.end());
    } else if (need_index) {
      index.emplace(std::move(all));
    }
  }
  if (ids.empty()) {
    ids.resize(static_cast<std::size_t>(cloud.size()));
    std::iota(ids.begin(), ids.end(), 0u);
  }
  if (need_index && !index) index.emplace(*points);

  tree.bbox = bounding_box(*points);
  const double diagonal = tree.bbox.diagonal();
  const double tolerance = options.threshold_mode == ThresholdMode::Absolute ? options.threshold : options.threshold * diagonal;
  double noise = 0;  // the noise the leaves may keep on top of the tolerance
  if (options.threshold_mode == ThresholdMode::Auto) {
    if (options.progress && !options.progress("estimating noise", 0.0)) throw Cancelled();
    p.noise_sigma = estimate_noise(*points, *index);
    noise = options.noise_factor * p.noise_sigma;
  }
  p.error_threshold = std::hypot(tolerance, noise);
  std::optional<detail::SupportSampler> sampler;
  if (options.support_factor > 0) sampler.emplace(*points, *index);

  BuildOptions resolved = options;  // the options with min_points decided
  if (resolved.min_points == 0) resolved.min_points = leaf_min_points(noise, tolerance);
  p.min_points = resolved.min_points;

  const auto n = ids.size();
  WorkingSet work{*points, std::move(ids), std::vector<std::uint32_t>(n)};
  std::iota(work.local.begin(), work.local.end(), 0u);
  detail::ProgressReporter progress(options.progress, "building tree", n);
  BuildNode root;
  Builder(*points, normals, work, sampler ? &*sampler : nullptr, resolved, tolerance, noise, progress)
      .build(root, work.local, 0, options.seed);
  progress.finish();
  const std::vector<std::uint32_t>& perm = work.ids;

  std::vector<std::uint32_t> begins;
  flatten(root, tree, options.keep_point_leaves ? &begins : nullptr);
  if (options.keep_point_leaves) {
    tree.point_leaf.assign(static_cast<std::size_t>(cloud.size()), -1);
    for (std::size_t n = 0; n < tree.nodes.size(); ++n) {
      if (!tree.nodes[n].is_leaf()) continue;
      for (std::uint32_t k = 0; k < tree.nodes[n].point_count; ++k)
        tree.point_leaf[perm[begins[n] + k]] = static_cast<std::int32_t>(n);
    }
  }
  return tree;
}

}  // namespace clustersurf
