// Recursive construction of the cluster tree (thesis ch. 3), subtrees in parallel: a node's fit,
// crease and split, a leaf's support.

#include <clustersurf/cluster/cluster_tree.hpp>

#include "cluster/build_state.hpp"
#include "cluster/cluster_frame.hpp"
#include "cluster/halves_test.hpp"
#include "cluster/residual_structure.hpp"
#include "cluster/splitters.hpp"
#include "cluster/support_fit.hpp"
#include "cluster/tree_builder.hpp"
#include "core/progress_reporter.hpp"
#include "core/splitmix.hpp"
#include "proxy/crease_fit.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <span>
#include <variant>

namespace clustersurf {

namespace {

using detail::BuildNode;
using detail::WorkingSet;

/// Clusters at least this large build their two subtrees as parallel tasks.
constexpr std::size_t kParallelGrain = 2048;
/// A leaf failing the support check shrinks its support by this factor, at most this often.
constexpr double kSupportShrinkFactor = 0.8;
constexpr int kSupportShrinkSteps = 10;
/// A would-be leaf on two sheets facing apart is split into them while each keeps this many
/// points (a plane's worth): a sheet's few points are real surface, and a leaf's proxy rests
/// on its support fit (at least MPU's N_min points) rather than on its own points alone.
constexpr std::size_t kMinSheetPoints = 3;
/// A split below min_points leaves at least this many points on each side: a quadratic's six
/// coefficients and two to spare, so that its residual can tell relief from a stray point.
constexpr std::size_t kMinDetailPoints = 8;
/// A leaf's support stopped short of another sheet keeps at least this many times its
/// cluster's extent (its own points lie within about half the extent of its centre).
constexpr double kMinSheetReach = 0.5;

class Builder {
 public:
  /// `tolerance`: the error a leaf may keep beyond the noise; `noise`: the noise level the
  /// leaves may keep (0 when the threshold ignores noise). Both in the input's units.
  /// `normals`: the input normals, indexed like the input cloud (WorkingSet::ids), or null;
  /// `frame_normals`: the normals the clusters' frames may follow (the input's, or estimated).
  /// `support`: the support checks, or null when they are off. `bias_tests`: whether a would-be
  /// leaf is split where halving it fits significantly better (significant_split()).
  /// `detail_splits`: whether a leaf
  /// may be split below options.min_points (detail_split(); when min_points was "auto").
  Builder(const Points* normals, const detail::FrameNormals& frame_normals, WorkingSet& work,
          const detail::SupportFit* support, const BuildOptions& options, double tolerance, double noise,
          bool bias_tests, bool detail_splits, detail::ProgressReporter& progress, const NoiseField* field,
          double sigma)
      : normals_(normals),
        frame_normals_(frame_normals),
        work_(work),
        points_(work.positions),
        support_(support),
        options_(options),
        tolerance_(tolerance),
        noise_(noise),
        cloud_noise_(noise),
        field_(field != nullptr && !field->empty() && sigma > 0 ? field : nullptr),
        sigma_(sigma),
        bias_tests_(bias_tests),
        detail_splits_(detail_splits),
        progress_(progress) {}

  /// Builds the subtree of `range` at the noise where it lies (build_here()).
  void build(BuildNode& bn, std::span<std::uint32_t> range, std::uint32_t depth, std::uint64_t path_seed) const {
    if (field_ == nullptr) return build_here(bn, range, depth, path_seed);
    Builder local = *this;
    local.noise_ = local_noise(range);
    local.build_here(bn, range, depth, path_seed);
  }

 private:
  /// The noise the cluster `range` keeps: the cloud's, raised where the field reads more at its
  /// centroid, by at most kMaxLocalNoise.
  double local_noise(std::span<const std::uint32_t> range) const {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const std::uint32_t i : range) c += points_.row(i).transpose();
    c /= static_cast<double>(range.size());
    return cloud_noise_ * std::clamp(field_->at(c) / sigma_, 1.0, kMaxLocalNoise);
  }

  /// Fits the node of `range`, splits it while the tests ask and builds its two subtrees, or
  /// makes it a leaf; at this builder's noise.
  void build_here(BuildNode& bn, std::span<std::uint32_t> range, std::uint32_t depth, std::uint64_t path_seed) const {
    progress_.check();
    ClusterNode& node = bn.node;
    node.depth = depth;
    double cover = 0;
    const detail::ClusterFrame fitted = fit(node, range, cover);
    const Frame& frame = fitted.frame;
    double e = error(node);
    const bool can_split = depth < options_.max_depth && range.size() >= 2 * std::size_t{options_.min_points};
    const double threshold = allowed(tolerance_, static_cast<double>(range.size()));
    // The node as fitted before a crease took it, restored if it is split.
    const std::optional<ClusterNode> smooth = try_crease(node, range, frame, threshold, e);
    std::optional<detail::SupportError> support;  // the support check's error, once computed
    std::size_t k = 0;
    // A cluster is split when its error exceeds the threshold, or, when its frame is determined,
    // when its residuals show structure that noise does not leave or its proxy fails over its
    // support. A blob as thick as it is wide has a frame the noise chooses: its proxy's misfit,
    // there and over its support, is the noise's, and splitting it leaves smaller blobs.
    if (can_split &&
        (e > threshold ||
         (fitted.determined &&
          (systematic_misfit(node.proxy, frame, range) ||
           (support_ != nullptr && support_fails(*(support = support_->check(node, range)), tolerance_)))))) {
      k = options_.splitter == SplitterKind::SplitPlane
              ? detail::split_plane(points_, range, frame, options_, noise_)
              : detail::lloyd_split(points_, range, options_, detail::splitmix64(path_seed));
    } else if (const std::size_t refined =
                   can_split && fitted.determined && !smooth ? significant_split(range, frame, node) : 0;
               refined != 0) {
      k = refined;
    } else if (range.size() >= 2) {
      // The proxy fits, but the cluster may be two parts with empty space between them (below
      // 2 × min_points only stray points across a wide gap are cut off).
      k = detail::split_at_gap(points_, range, frame, options_.min_points);
      if ((k == 0 || k >= range.size()) && detail_splits_ && !can_split && depth < options_.max_depth &&
          fitted.determined) {
        if (e > threshold) {
          k = detail_split(range, frame, e, nullptr);
        } else if (support_ != nullptr) {
          if (!support) support = support_->check(node, range);
          if (support_fails(*support, tolerance_)) k = detail_split(range, frame, threshold, &*support);
        }
      }
    }
    // A would-be leaf on two sheets facing apart (both sides of a thin part, the faces of a
    // deep fold) becomes one leaf per sheet, below min_points if need be.
    // A crease leaf is one already: its two faces are the two planes it holds.
    if ((k == 0 || k >= range.size()) && normals_ != nullptr && depth < options_.max_depth && !smooth)
      k = detail::split_two_sheets(points_, *normals_, work_.ids, range, kMinSheetPoints);
    // A leaf held at min_points that misses the threshold on two groups of points apart (two
    // legs of a sparse sample) becomes one leaf per group, below min_points if need be (when
    // min_points is "auto", as for detail_split()).
    if ((k == 0 || k >= range.size()) && detail_splits_ && !can_split && e > threshold && depth < options_.max_depth &&
        !smooth)
      k = detail::split_at_linkage_gap(points_, range, kMinSheetPoints);
    if (k == 0 || k >= range.size()) {
      // A leaf that cannot be split (too few points, or no split helps) but whose proxy is off
      // over its support — typically a cluster of two small patches far apart — keeps only the
      // part of its support where the proxy holds, so it does not blend nonsense into its
      // neighbours' surface.
      if (support_ != nullptr) fit_leaf_support(node, range, frame, threshold, smooth.has_value(), e, cover, support);
      std::iota(range.begin(), range.end(), bn.begin);
      progress_.advance(range.size());
      return;
    }
    if (smooth) node = *smooth;  // split after all: an inner node keeps the smooth proxy
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
    node.bound = detail::enclose(detail::enclose(node.support, bn.left->node.bound), bn.right->node.bound);
  }

  /// A cluster on the two faces of a sharp edge: two planes meeting at a crease, where one
  /// smooth proxy rounds the edge and its split leaves a lumpy blend along it. The crease is
  /// kept when it meets the threshold and explains the smooth proxy's misfit `e`: it leaves at
  /// most a quarter of the misfit beyond the noise (half its RMS). Two planes fit any cluster a
  /// little better than one quadric; only an edge makes them fit it much better. Returns the
  /// node as it was when the crease took it (`e` then the crease's error), else nullopt.
  std::optional<ClusterNode> try_crease(ClusterNode& node, std::span<const std::uint32_t> range, const Frame& frame,
                                        double threshold, double& e) const {
    if (!options_.creases || !(e > threshold)) return std::nullopt;
    const auto crease = detail::fit_crease(points_, range, frame, node.extent);
    if (!crease) return std::nullopt;
    const double ce = options_.metric == ErrorMetric::Rms ? crease->error.rms : crease->error.max;
    if (!(ce <= threshold && explains(ce, e))) return std::nullopt;
    std::optional<ClusterNode> smooth = node;
    node.proxy = crease->proxy;
    node.rms_error = crease->error.rms;
    node.max_error = crease->error.max;
    e = ce;
    return smooth;
  }

  /// Over its support a proxy may keep the noise plus support_factor times the tolerance.
  bool support_fails(const detail::SupportError& s, double tolerance) const {
    return s.rms > allowed(options_.support_factor * tolerance, s.effective_points);
  }

  /// A leaf's support, fitted to where its proxy holds: a crease where its support reaches over
  /// a sharp edge, a radius that stops short of another sheet, shrunk while the proxy fails
  /// there; `e` (its error), `cover` and `support` (its support check) follow.
  void fit_leaf_support(ClusterNode& node, std::span<const std::uint32_t> range, const Frame& frame, double threshold,
                        bool crease_fitted, double& e, double& cover,
                        std::optional<detail::SupportError>& support) const {
    if (!support) support = support_->check(node, range);
    // A leaf beside a sharp edge whose support reaches the other face: its smooth proxy,
    // extended across the edge, would blend a lip into the edge. When a crease fits the
    // support points (the edge within the support), still fits the leaf's own points, and
    // explains the support misfit as above, the leaf takes it.
    if (options_.creases && !crease_fitted && support->rms > allowed(tolerance_, support->effective_points)) {
      if (const auto crease = support_->crease(node, frame)) {
        const ProxyError own = proxy_error(Proxy(crease->proxy), points_, range);
        const double ce = options_.metric == ErrorMetric::Rms ? own.rms : own.max;
        if (ce <= std::max(threshold, e) && explains(crease->error.rms, support->rms)) {
          node.proxy = crease->proxy;
          node.rms_error = own.rms;
          node.max_error = own.max;
          e = ce;
          support = crease->error;
        }
      }
    }
    if (cover < 0) cover = support_->coverage_radius(node.support.center, options_.alpha * node.extent);
    // A support reaching another sheet (the far side of a thin part, the opposite wall of
    // a fold) stops short of it: its proxy, pointing the other way there, would push that
    // sheet's surface out. It keeps at least half the cluster's extent.
    const double sheet = std::max(kMinSheetReach * node.extent, support_->other_sheet_distance(node, range));
    if (sheet < node.support.radius) {
      node.support.radius = sheet;
      cover = std::min(cover, sheet);
      support = support_->check(node, range);
    }
    // A leaf held at min_points may miss the threshold on its own points too; measure its
    // support against what it achieves there.
    const double own = std::sqrt(std::max(0.0, e * e - noise_ * noise_));
    const double tolerance = std::max(tolerance_, own);
    for (int shrink = 0;
         shrink < kSupportShrinkSteps && support_fails(*support, tolerance) && node.support.radius > cover; ++shrink) {
      node.support.radius = std::max(cover, node.support.radius * kSupportShrinkFactor);
      support = support_->check(node, range);
    }
    node.bound = node.support;
  }

  double allowed(double tolerance, double n) const { return detail::allowed_error(tolerance, noise_, n); }

  /// Fits `node` to the points `range`: its frame (returned), proxy, errors and extent, and its
  /// support: alpha × extent, grown to `cover`, the radius that holds MPU's N_min points (-1
  /// when the cluster's own points show it to be within alpha × extent: only leaves need it).
  detail::ClusterFrame fit(ClusterNode& node, std::span<const std::uint32_t> range, double& cover) const {
    node.point_count = static_cast<std::uint32_t>(range.size());
    const detail::ClusterFrame fitted = detail::cluster_frame(points_, range, frame_normals_, work_.ids, noise_);
    const Frame& frame = fitted.frame;
    node.proxy = options_.proxy == ProxyKind::Poly ? Proxy(fit_poly_in_frame(frame, points_, range))
                                                   : fit_proxy(options_.proxy, points_, range);
    const ProxyError err = proxy_error(node.proxy, points_, range);
    node.rms_error = err.rms;
    node.max_error = err.max;
    BoundingBox box;
    for (auto i : range) box.extend(points_.row(i).transpose());
    node.extent = box.diagonal();
    node.support = Sphere{frame.origin, options_.alpha * node.extent};
    if (support_ == nullptr)
      cover = 0;
    else if (support_->own_points_cover(range, frame.origin, node.support.radius))
      cover = -1;  // within alpha × extent; a leaf queries it when it needs it
    else
      cover = support_->coverage_radius(frame.origin, node.support.radius);
    node.support.radius = std::max(node.support.radius, cover);
    node.bound = node.support;
    return fitted;
  }

  /// The node's error by the metric of the options.
  double error(const ClusterNode& node) const {
    return options_.metric == ErrorMetric::Rms ? node.rms_error : node.max_error;
  }

  /// Whether `after` leaves at most a quarter of the misfit of `before` beyond the noise (half
  /// its RMS): the rule by which a crease or a split below min_points explains a misfit.
  bool explains(double after, double before) const {
    const double noise2 = noise_ * noise_;
    return after * after - noise2 <= 0.25 * (before * before - noise2);
  }

  /// A leaf held at min_points whose proxy misses the threshold (`support` null; relief finer
  /// than the cluster: a lip, an eyelid, a fold) or fails over its support (`support`: that
  /// check's error) is split below min_points when that resolves it: into two halves of at
  /// least two thirds of min_points and kMinDetailPoints (8 for clean data) whose proxies each
  /// meet the threshold or explain() the cluster's misfit `error`, and, for a support failure, whose support checks
  /// each pass or explain the cluster's. A stray point that bends a proxy leaves its half's misfit about as large as
  /// the cluster's, so no split is made for it; nor for a misfit the halves cannot resolve.
  /// Only when min_points is "auto". Returns the split position (`range` reordered), or 0.
  std::size_t detail_split(std::span<std::uint32_t> range, const Frame& frame, double error,
                           const detail::SupportError* support) const {
    const std::size_t smallest =
        std::max<std::size_t>(kMinDetailPoints, (2 * std::size_t{options_.min_points} + 2) / 3);
    if (range.size() < 2 * smallest) return 0;
    BuildOptions halves = options_;
    halves.min_points = static_cast<std::uint32_t>(smallest);
    const std::size_t k = detail::split_plane(points_, range, frame, halves, noise_);
    if (k < smallest || range.size() - k < smallest) return 0;
    for (const auto half : {range.subspan(0, k), range.subspan(k)}) {
      ClusterNode h;
      double cover = 0;
      fit(h, half, cover);
      const double e = this->error(h);
      if (!(e <= allowed(tolerance_, static_cast<double>(half.size())) || explains(e, error))) return 0;
      if (support == nullptr) continue;
      const detail::SupportError hs = support_->check(h, half);
      if (!(hs.rms <= allowed(options_.support_factor * tolerance_, hs.effective_points) ||
            explains(hs.rms, support->rms)))
        return 0;
    }
    return k;
  }

  /// The split plane's k (split_plane() on `range`) when the node's points, halved at the median
  /// of either of its first two frame axes, are fitted by a quadratic per half significantly
  /// better than by one (halves_drops() beyond halves_drop_bound(): nested least squares, whose
  /// drop under noise alone is the noise's variance times a chi-square of six degrees of
  /// freedom), or the points of its support are (SupportFit::halves_fit_better(): the blend
  /// reaches the proxy out to the support's rim). So a leaf's misfit is held to the standard
  /// error of its own fit, which its residual's spread cannot show once it holds more than a few
  /// dozen points. Without input normals, the halves along the first axis must spread across
  /// the frame's plane by kDeterminedSpread times the noise's variance, or no test runs: the test
  /// takes the noise for heights alone, and in a blob as thick as it is wide the noise moves the
  /// points across the plane as much. Else 0.
  std::size_t significant_split(std::span<std::uint32_t> range, const Frame& frame, const ClusterNode& node) const {
    if (!bias_tests_ || !(noise_ > 0) || !std::holds_alternative<PolyProxy>(node.proxy.variant()) ||
        options_.splitter != SplitterKind::SplitPlane)
      return 0;
    const std::array<detail::HalvesDrop, 2> drops = detail::halves_drops(points_, range, {}, frame);
    if (frame_normals_.input == nullptr && drops[0].spread < detail::kDeterminedSpread * noise_ * noise_)
      return 0;  // a blob: no test holds
    const double bound = detail::halves_drop_bound(noise_);
    if (drops[0].drop > bound || drops[1].drop > bound ||
        (support_ != nullptr && support_->halves_fit_better(node, frame)))
      return detail::split_plane(points_, range, frame, options_, noise_);
    return 0;
  }

  /// Whether the proxy's residuals over the cluster correlate between neighbours more than
  /// independent noise lets them: kNoiseMargin times its spread, at most √(2/n) (relief the
  /// proxy does not follow, even below the noise the threshold allows). Without noise in the
  /// threshold the error alone decides, and nothing is computed.
  bool systematic_misfit(const Proxy& proxy, const Frame& frame, std::span<const std::uint32_t> range) const {
    if (!(noise_ > 0)) return false;
    const double limit = kNoiseMargin * std::sqrt(2 / static_cast<double>(range.size()));
    return detail::residual_correlation(points_, range, frame, proxy) > limit;
  }

  const Points* normals_;  // the input cloud's normals (rows: WorkingSet::ids), or null
  detail::FrameNormals frame_normals_;
  WorkingSet& work_;      // the input in cluster order; subtrees touch disjoint rows
  const Points& points_;  // work_.positions
  const detail::SupportFit* support_;
  const BuildOptions& options_;
  double tolerance_;
  double noise_;        // the noise this node keeps
  double cloud_noise_;  // the noise the leaves keep where the field reads no more than its estimate
  const NoiseField* field_;
  double sigma_;  // the estimate field_ scales
  bool bias_tests_;
  bool detail_splits_;
  detail::ProgressReporter& progress_;
};

}  // namespace

void detail::build_nodes(BuildNode& root, const Points* normals, const FrameNormals& frame_normals, WorkingSet& work,
                         const SupportFit* support, const BuildOptions& options, double tolerance, double noise,
                         bool bias_tests, bool detail_splits, ProgressReporter& progress, const NoiseField* field,
                         double sigma) {
  Builder(normals, frame_normals, work, support, options, tolerance, noise, bias_tests, detail_splits, progress, field,
          sigma)
      .build(root, work.local, 0, options.seed);
}

}  // namespace clustersurf
