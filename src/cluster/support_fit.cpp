// The support check and the support fit of a would-be leaf (MPU's local fit).

#include <clustersurf/proxy/moments.hpp>

#include "cluster/halves_test.hpp"
#include "cluster/support_fit.hpp"
#include "proxy/crease_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace clustersurf::detail {

namespace {

/// The support check evaluates at most about this many of the points inside a support.
constexpr std::size_t kSupportSample = 2048;
/// A support sphere holds about this many times its cluster's points (measured on scans).
constexpr std::size_t kSupportPointsPerClusterPoint = 8;
/// The support fit leaves out points farther than this many thresholds from the cluster's fit.
constexpr double kSupportFitReach = 3;
/// Fewer support points than this keep the cluster's own fit.
constexpr std::size_t kMinSupportFitPoints = 12;
/// A cluster's fit is refitted without a stray only when at least this many points remain: a
/// quadratic's six coefficients and one to spare (the refit picks the support points with it,
/// the support fit then rests on them all).
constexpr std::size_t kMinUnbentPoints = 7;
/// Larger clusters are split instead (one point bends a fit of many little).
constexpr std::size_t kMaxUnbentPoints = 40;
/// Rounds of the trimmed support fit: points farther than kSupportFitReach times the fit's
/// weighted RMS (or the threshold) from it are left out and the rest refitted, as long as they
/// are isolated strays: at most kMaxTrimmedShare of the points (or one; more is a second sheet
/// or real detail, which the split and the support checks deal with).
constexpr int kTrimRounds = 2;
constexpr double kMaxTrimmedShare = 0.05;
/// A support grows to hold BuildOptions::support_points input points (MPU's N_min) up to
/// kMaxSupportGrowth times its alpha radius, so a few stray points never reach across a gap.
constexpr double kMaxSupportGrowth = 4;
/// The normals' weight λ in the support fit (a squared length: the ratio of the position fit's
/// residual variance to its normals') compares the slopes the normals give with those the
/// positions give over the support: λ / r² is about the ratio of their information (r the
/// support radius). The normals enter only where they add at least about a tenth of the
/// positions' information (λ ≥ 0.3² r²): below that they gain little, and a scanner's normals,
/// computed from the same noisy positions, count the noise twice (virtual scans lost 1–5 %
/// with every normal in). λ is capped at 100 r², where the positions only set the height.
constexpr double kMinNormalWeight = 0.3 * 0.3;
constexpr double kMaxNormalWeight = 100;
/// A support point beyond the support fit's reach whose normal faces more than 135° away from
/// the leaf's own sheet (cosine below minus this) lies on another sheet: the far side of a thin
/// part, the opposite wall of a fold.
constexpr double kOtherSheetCos = std::numbers::sqrt2 / 2;
/// A support stops at the kOtherSheetPoints-th nearest point of another sheet: a stray or two
/// of the noise do not make one.
constexpr std::size_t kOtherSheetPoints = 3;

}  // namespace

SupportFit::SupportFit(const Points& input, const Points& cluster_points, const SupportSampler& sampler,
                       const BuildOptions& options, double tolerance, double noise, const Points* normals)
    : input_(input),
      points_(cluster_points),
      sampler_(sampler),
      options_(options),
      tolerance_(tolerance),
      noise_(noise),
      normals_(normals) {}

double SupportFit::coverage_radius(const Eigen::Vector3d& center, double alpha_radius) const {
  thread_local std::vector<Neighbor> nearest;
  if (options_.support_points == 0) return 0;
  sampler_.full().knn(center, options_.support_points, nearest);
  const double holding = nearest.empty() ? 0 : std::sqrt(nearest.back().distance_squared);
  return std::min(holding, kMaxSupportGrowth * alpha_radius);
}

bool SupportFit::own_points_cover(std::span<const std::uint32_t> range, const Eigen::Vector3d& center,
                                  double radius) const {
  const std::size_t needed = options_.support_points;
  if (needed == 0) return true;
  if (range.size() < needed) return false;
  // The margin keeps the answer exact against the k-d tree's own rounding of the distances.
  const double r2 = radius * radius * (1 - 1e-9);
  std::size_t inside = 0;
  for (auto i : range)
    if ((points_.row(i).transpose() - center).squaredNorm() < r2 && ++inside == needed) return true;
  return false;
}

SupportError SupportFit::check(ClusterNode& node, std::span<const std::uint32_t> range) const {
  const double r2 = node.support.radius * node.support.radius;
  if (!(r2 > 0)) return {};
  thread_local std::vector<Neighbor> inside;
  sampler_.inside(node.support.center, node.support.radius, kSupportPointsPerClusterPoint * node.point_count,
                  kSupportSample, inside);
  if (std::holds_alternative<PolyProxy>(node.proxy.variant())) refit(node, range, inside);
  return weighted_error(node.proxy, node.support, inside);
}

SupportError SupportFit::weighted_error(const Proxy& proxy, const Sphere& support,
                                        std::span<const Neighbor> inside) const {
  const double r2 = support.radius * support.radius;
  double sum = 0, weight = 0, weight2 = 0;
  for (const auto& nb : inside) {
    const double w = blend_weight(nb.distance_squared / r2);
    const double q = proxy.value(input_.row(nb.index).transpose());
    sum += w * q * q;
    weight += w;
    weight2 += w * w;
  }
  if (!(weight > 0)) return {};
  return {std::sqrt(sum / weight), weight * weight / weight2};
}

bool SupportFit::halves_fit_better(const ClusterNode& node, const Frame& frame) const {
  const double r2 = node.support.radius * node.support.radius;
  if (!(r2 > 0) || !(noise_ > 0)) return false;
  thread_local std::vector<Neighbor> inside;
  sampler_.inside(node.support.center, node.support.radius, kSupportPointsPerClusterPoint * node.point_count,
                  kSupportSample, inside);
  constexpr std::size_t kFewest = 24;  // four times a quadratic's coefficients
  if (inside.size() < kFewest) return false;
  std::vector<std::uint32_t> ids(inside.size());
  std::vector<double> weights(inside.size());
  double sum = 0, sum2 = 0;
  for (std::size_t k = 0; k < inside.size(); ++k) {
    ids[k] = inside[k].index;
    weights[k] = blend_weight(inside[k].distance_squared / r2);
    sum += weights[k];
    sum2 += weights[k] * weights[k];
  }
  if (!(sum > 0)) return false;
  const std::array<HalvesDrop, 2> drops = halves_drops(input_, ids, weights, frame);
  const double bound = halves_drop_bound(noise_, sum2 / sum);
  return drops[0].drop > bound || drops[1].drop > bound;
}

std::optional<SupportFit::SupportCrease> SupportFit::crease(const ClusterNode& node, const Frame& frame) const {
  if (!(node.support.radius > 0)) return std::nullopt;
  thread_local std::vector<Neighbor> inside;
  thread_local std::vector<std::uint32_t> ids;
  sampler_.inside(node.support.center, node.support.radius, kSupportPointsPerClusterPoint * node.point_count,
                  kSupportSample, inside);
  ids.clear();
  for (const auto& nb : inside) ids.push_back(nb.index);
  const auto fit = fit_crease(input_, ids, frame, 2 * node.support.radius);
  if (!fit) return std::nullopt;
  return SupportCrease{fit->proxy, weighted_error(fit->proxy, node.support, inside)};
}

double SupportFit::other_sheet_distance(const ClusterNode& node, std::span<const std::uint32_t> range) const {
  const double radius = node.support.radius;
  if (normals_ == nullptr || !(radius > 0)) return radius;
  thread_local std::vector<Neighbor> inside;
  sampler_.inside(node.support.center, radius, kSupportPointsPerClusterPoint * node.point_count, kSupportSample,
                  inside);
  const double threshold = allowed_error(tolerance_, noise_, static_cast<double>(range.size()));
  const double reach = kSupportFitReach * std::max(threshold, node.rms_error);
  // The way the leaf's own sheet faces: the mean input normal of the support points its proxy
  // fits.
  Eigen::Vector3d facing = Eigen::Vector3d::Zero();
  for (const auto& nb : inside)
    if (std::abs(node.proxy.value(input_.row(nb.index).transpose())) <= reach)
      facing += normals_->row(nb.index).transpose();
  if (!(facing.squaredNorm() > 0)) return radius;
  facing.normalize();
  // The kOtherSheetPoints nearest points off the proxy that face the other way, nearest first:
  // one or two may be strays.
  std::array<double, kOtherSheetPoints> nearest2;
  nearest2.fill(radius * radius);
  for (const auto& nb : inside) {
    if (!(nb.distance_squared < nearest2.back())) continue;
    if (!(facing.dot(normals_->row(nb.index).transpose()) < -kOtherSheetCos)) continue;
    if (!(std::abs(node.proxy.value(input_.row(nb.index).transpose())) > reach)) continue;
    auto at = std::upper_bound(nearest2.begin(), nearest2.end(), nb.distance_squared);
    std::move_backward(at, nearest2.end() - 1, nearest2.end());
    *at = nb.distance_squared;
  }
  return std::sqrt(nearest2.back());
}

std::optional<Proxy> SupportFit::unbent(const ClusterNode& node, std::span<const std::uint32_t> range, double threshold,
                                        double& rms) const {
  if (!(node.rms_error > threshold) || range.size() < kMinUnbentPoints + 1 || range.size() > kMaxUnbentPoints)
    return std::nullopt;
  const Frame& frame = std::get<PolyProxy>(node.proxy.variant()).frame;
  // The point whose removal leaves the others' fit the least error (their moments less its
  // own, an O(1) refit each): the stray, when the others then meet the threshold.
  PolyMoments moments(frame, node.extent);
  for (auto i : range) moments.add(points_.row(i).transpose());
  double best_rms = threshold;
  std::optional<std::size_t> stray;
  for (std::size_t j = 0; j < range.size(); ++j) {
    const Eigen::Vector3d p = points_.row(range[j]).transpose();
    PolyMoments others = moments;
    others.remove(p);
    if (const double e = others.rms_error(); e <= best_rms) best_rms = e, stray = j;
  }
  if (!stray) return std::nullopt;
  thread_local std::vector<std::uint32_t> others;
  others.assign(range.begin(), range.end());
  others.erase(others.begin() + static_cast<std::ptrdiff_t>(*stray));
  Proxy fit(fit_poly_in_frame(frame, points_, others));
  if (!(std::abs(fit.value(points_.row(range[*stray]).transpose())) > kSupportFitReach * threshold))
    return std::nullopt;
  rms = proxy_error(fit, points_, range).rms;  // over all the points, as the cluster fit's own RMS
  return fit;
}

/// Refits a polynomial proxy, in its cluster's frame, to the support points weighted by the
/// blending weight (as in MPU): the proxy is then accurate wherever the blend uses it, and
/// averages the noise over its whole support. Points beyond kSupportFitReach times the
/// threshold or the cluster's own error from the cluster's fit (another sheet, outliers) are
/// left out; then, kTrimRounds times, those beyond kSupportFitReach times the support fit's
/// own weighted RMS (a stray point near the surface that bent the cluster's fit) are left out
/// and the rest refitted. The node's errors are re-measured on its own points, but for a few
/// strays beyond that reach.
void SupportFit::refit(ClusterNode& node, std::span<const std::uint32_t> range,
                       std::span<const Neighbor> inside) const {
  const PolyProxy& cluster_fit = std::get<PolyProxy>(node.proxy.variant());
  const double r2 = node.support.radius * node.support.radius;
  const double threshold = allowed_error(tolerance_, noise_, static_cast<double>(range.size()));
  // The support points are picked by a fit of the cluster's points; one that misses the
  // threshold because a stray bent it picks them by the fit of the other points, when those
  // meet the threshold without it.
  double picker_rms = node.rms_error;
  const std::optional<Proxy> others_fit = unbent(node, range, threshold, picker_rms);
  const Proxy& picker = others_fit ? *others_fit : node.proxy;
  const double reach = kSupportFitReach * std::max(threshold, picker_rms);
  thread_local std::vector<std::uint32_t> ids;
  thread_local std::vector<double> weights;
  ids.clear();
  weights.clear();
  for (const auto& nb : inside) {
    if (!(std::abs(picker.value(input_.row(nb.index).transpose())) <= reach)) continue;
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
    const auto kept =
        static_cast<std::size_t>(std::count_if(residual.begin(), residual.end(), [&](double q) { return q <= cut; }));
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
  // With input normals, the fit also follows their slopes (Hermite data), weighted by the
  // ratio of the position fit's residuals to its normals' (inverse variances: exact normals on
  // noisy positions count much, a scanner's noisy normals little). The position fit stays where
  // the Hermite fit would take the cluster's own points beyond the threshold.
  if (normals_ != nullptr) {
    const PolyProxy& poly = std::get<PolyProxy>(fit.variant());
    const auto& c = poly.coeffs;
    double position = 0, slope = 0;
    for (std::size_t j = 0; j < ids.size(); ++j) {
      const Eigen::Vector3d l = poly.frame.to_local(input_.row(ids[j]).transpose());
      Eigen::Vector3d m = poly.frame.axes.transpose() * normals_->row(ids[j]).transpose();
      if (m.z() < 0) m = -m;
      const double gu = m.z() * (c[1] + 2 * c[3] * l.x() + c[4] * l.y()) + m.x();
      const double gv = m.z() * (c[2] + c[4] * l.x() + 2 * c[5] * l.y()) + m.y();
      position += weights[j] * residual[j] * residual[j];
      slope += weights[j] * (gu * gu + gv * gv);
    }
    const double ratio = slope > 0 ? position / slope : 0;
    if (ratio >= kMinNormalWeight * r2 && std::isfinite(ratio)) {
      Proxy hermite =
          fit_poly_in_frame(poly.frame, input_, ids, weights, normals_, std::min(ratio, kMaxNormalWeight * r2));
      if (accept(node, range, threshold, cut, std::move(hermite))) return;
    }
  }
  accept(node, range, threshold, cut, std::move(fit));
}

/// Takes `fit` as the node's proxy while the cluster's own points still meet the threshold (or
/// what the cluster's fit achieved): a leaf's error on its points stays within the threshold. A
/// few own points beyond the stray `cut` (a stray that bent the cluster's fit) are not counted.
bool SupportFit::accept(ClusterNode& node, std::span<const std::uint32_t> range, double threshold, double cut,
                        Proxy fit) const {
  const auto few = [](std::size_t strays, std::size_t total) {
    return static_cast<double>(strays) <= std::max(1.0, kMaxTrimmedShare * static_cast<double>(total));
  };
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
  const double rms = trim ? std::sqrt(inlier_sum / static_cast<double>(inliers))
                          : std::sqrt(all_sum / static_cast<double>(range.size()));
  const double max = trim ? inlier_max : all_max;
  const double e = options_.metric == ErrorMetric::Rms ? rms : max;
  const double own = options_.metric == ErrorMetric::Rms ? node.rms_error : node.max_error;
  if (!(e <= std::max(threshold, own))) return false;
  node.proxy = std::move(fit);
  node.rms_error = rms;
  node.max_error = max;
  return true;
}

}  // namespace clustersurf::detail
