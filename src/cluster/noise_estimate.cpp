#include <clustersurf/errors.hpp>
#include <clustersurf/kd_tree.hpp>
#include <clustersurf/noise.hpp>
#include <clustersurf/proxy.hpp>

#include "core/portable_random.hpp"
#include "core/splitmix.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace clustersurf {

namespace {

/// On pure independent noise the two estimates agree within about 7 % (the fits' is a little
/// high where the surface curves: 0.93–1.0 over the benchmark's noisy inputs of smooth
/// models); with NoiseOptions::residual_differences, the differences' estimate replaces the
/// fits' when lower than this fraction of it, for then the fits' residual holds the model's
/// detail (0.7 on the noisy ogre and beast, 0.75 on clean samples of faceted meshes).
constexpr double kDetailMargin = 0.9;
/// A local fit takes at least this many points (a quadratic's 6 coefficients and 4 to spare).
constexpr std::size_t kMinFitPoints = 10;
/// The sampled neighbourhoods never come from fewer points than this.
constexpr std::size_t kMinCoarsePoints = 4096;

/// The local fits' medians at one neighbourhood size.
struct LocalNoise {
  double sigma = 0;       // median RMS residual of the local fits
  double difference = 0;  // median of the residual differences' estimate (LocalFit::difference)
  double width = 0;       // median neighbourhood radius
};

/// One local fit's two estimates of the noise.
struct LocalFit {
  /// RMS residual, corrected for the fit's six degrees of freedom (E[ss] = (k − 6) σ² for k
  /// points of noise σ): the noise, plus the model's detail that a quadratic cannot follow.
  double residual = 0;
  /// From differences: √(Σ (rᵢ − rⱼ)² / 2n) over each point i and its nearest neighbour j in
  /// the fit's tangent plane (chosen there, so the noise does not choose it). Noise is
  /// independent from point to point, detail is not: detail left by the fit is nearly the same
  /// at neighbouring points and cancels, noise counts twice (Rice's difference estimator).
  /// Computed on request only (0 otherwise): it costs k² distances per fit.
  double difference = 0;
};

/// The quadratic height-field fit to points[idx] and its estimates of the noise (the
/// differences' only when `differences` is set).
LocalFit fit_residual(const Points& points, const std::vector<std::uint32_t>& idx, bool differences) {
  const Frame frame = pca_frame(points, idx);
  const PolyProxy poly = fit_poly_in_frame(frame, points, idx);
  thread_local std::vector<Eigen::Vector3d> local;  // tangent-plane position, residual
  local.clear();
  double ss = 0;
  for (auto j : idx) {
    const Eigen::Vector3d l = frame.to_local(points.row(j).transpose());
    const double r = l.z() - poly.height(l.x(), l.y());
    local.emplace_back(l.x(), l.y(), r);
    ss += r * r;
  }
  double sd = 0;
  for (std::size_t i = 0; differences && i < local.size(); ++i) {
    double nearest = std::numeric_limits<double>::infinity(), dr = 0;
    for (std::size_t j = 0; j < local.size(); ++j) {
      if (j == i) continue;
      const double d = (local[i].head<2>() - local[j].head<2>()).squaredNorm();
      if (d < nearest) nearest = d, dr = local[i].z() - local[j].z();
    }
    sd += dr * dr;
  }
  // Both corrected for the fit's six degrees of freedom: its residuals, and so their
  // differences, carry (k − 6) / k of the noise's variance.
  const auto dof = static_cast<double>(idx.size() - 6);
  return {std::sqrt(ss / dof), std::sqrt(sd / (2 * dof))};
}

/// Median noise and neighbourhood radius over evenly strided points of `points`, for the
/// neighbourhood sizes options.neighbors, /2, /4 (nested: the nearest of one query). With
/// `normals`, a neighbourhood holds the neighbours facing the same way as its centre (when at
/// least kMinFitPoints do; all of them otherwise).
std::array<LocalNoise, 3> local_noise(const Points& points, const KdTree& tree, const NoiseOptions& options,
                                      const Points* normals) {
  const auto n = static_cast<std::size_t>(points.rows());
  const std::size_t k = std::min(options.neighbors, n);
  const std::size_t samples = std::min(options.samples, n);
  const double stride = static_cast<double>(n) / static_cast<double>(samples);
  std::array<std::vector<double>, 3> sigma, difference, width;
  for (auto& v : sigma) v.resize(samples);
  for (auto& v : difference) v.resize(samples);
  for (auto& v : width) v.resize(samples);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples), [&](const auto& r) {
    std::vector<Neighbor> nb;
    std::vector<std::uint32_t> idx;
    for (std::size_t s = r.begin(); s != r.end(); ++s) {
      const auto i = static_cast<Eigen::Index>(static_cast<double>(s) * stride);
      tree.knn(points.row(i).transpose(), k, nb);
      if (normals != nullptr) {
        const Eigen::Vector3d facing = normals->row(i).transpose();
        const auto other_way = [&](const Neighbor& q) { return !(normals->row(q.index).dot(facing) > 0); };
        if (nb.size() - static_cast<std::size_t>(std::count_if(nb.begin(), nb.end(), other_way)) >= kMinFitPoints)
          nb.erase(std::remove_if(nb.begin(), nb.end(), other_way), nb.end());
      }
      for (std::size_t scale = 0; scale < 3; ++scale) {
        // At least kMinFitPoints per fit (estimate_noise() needs k ≥ that, so nb holds them).
        const std::size_t m = std::max<std::size_t>(nb.size() >> scale, kMinFitPoints);
        idx.clear();
        for (std::size_t j = 0; j < m; ++j) idx.push_back(nb[j].index);
        width[scale][s] = std::sqrt(nb[m - 1].distance_squared);
        // Only the narrowest fits' differences are ever used (estimate_noise()).
        const LocalFit fit = fit_residual(points, idx, options.residual_differences && scale == 2);
        sigma[scale][s] = fit.residual;
        difference[scale][s] = fit.difference;
      }
    }
  });
  const auto median = [&](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(samples / 2), v.end());
    return v[samples / 2];
  };
  std::array<LocalNoise, 3> out;
  for (std::size_t scale = 0; scale < 3; ++scale)
    out[scale] = {median(sigma[scale]), median(difference[scale]), median(width[scale])};
  return out;
}

/// Simulated neighbourhoods per calibration of a fit's bias (plane_fit_bias()).
constexpr std::size_t kBiasTrials = 256;
/// Fixed-point rounds that solve σ = s / bias(w / σ) for the noise σ behind a median residual s.
constexpr int kBiasRounds = 4;
/// A narrower scale is only read when its neighbourhoods span at least this many of its
/// corrected noise deviations: below, the fit follows so much of the noise that the bias
/// varies steeply with the width and the correction is no longer reliable.
constexpr double kMinCorrectedWidth = 3.5;
/// Neighbourhoods wider than this many noise deviations are taken as unbiased (the simulated
/// bias is within 0.5 % of 1 there), which spares clean inputs the simulation.
constexpr double kUnbiasedWidth = 30;

/// The median ratio of fit_residual()'s estimate to the true noise σ for a plane sampled with
/// isotropic Gaussian noise, at `k` points per fit and neighbourhoods `width_over_sigma` noise
/// deviations wide: a narrow fit follows part of the noise (its frame tilts towards it, its
/// height field bends to it) and reads less than the noise (0.87 at 24 points 4 σ wide; 0.97 at
/// 96 points 7 σ wide). Simulated with the estimate's own fit, deterministically: kBiasTrials
/// discs of 4k points holding k within `width`, each fitted around its point nearest the centre.
double plane_fit_bias(std::size_t k, double width_over_sigma) {
  const std::size_t disc = 4 * k;
  const double sigma = 1 / width_over_sigma;  // widths in units of the neighbourhood width
  std::vector<double> ratio(kBiasTrials);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kBiasTrials), [&](const auto& r) {
    Points points(static_cast<Eigen::Index>(disc), 3);
    std::vector<std::pair<double, std::uint32_t>> by_distance(disc);
    std::vector<std::uint32_t> idx;
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      detail::PortableRandom random(detail::splitmix64(t + 1));
      Eigen::Index centre = 0;
      for (Eigen::Index i = 0; i < points.rows(); ++i) {
        // Uniform in a disc of radius 2: k points fall within radius 1 on average.
        const double radius = 2 * std::sqrt(random.uniform()), angle = 2 * std::numbers::pi * random.uniform();
        points.row(i) << radius * std::cos(angle), radius * std::sin(angle), 0.0;
        if (points.row(i).head<2>().squaredNorm() < points.row(centre).head<2>().squaredNorm()) centre = i;
      }
      for (Eigen::Index i = 0; i < points.rows(); ++i)
        for (int c = 0; c < 3; ++c) points(i, c) += sigma * random.normal();
      for (std::size_t i = 0; i < disc; ++i)
        by_distance[i] = {(points.row(static_cast<Eigen::Index>(i)) - points.row(centre)).squaredNorm(), static_cast<std::uint32_t>(i)};
      std::nth_element(by_distance.begin(), by_distance.begin() + static_cast<std::ptrdiff_t>(k - 1), by_distance.end());
      idx.clear();
      for (std::size_t j = 0; j < k; ++j) idx.push_back(by_distance[j].second);
      ratio[t] = fit_residual(points, idx, false).residual / sigma;
    }
  });
  std::nth_element(ratio.begin(), ratio.begin() + kBiasTrials / 2, ratio.end());
  return ratio[kBiasTrials / 2];
}

/// The noise σ behind the median residual of one scale, corrected for the fit's bias at its
/// width: σ = residual / plane_fit_bias(k, width / σ), solved by fixed-point rounds.
double corrected_noise(const LocalNoise& e, std::size_t k) {
  double sigma = e.sigma;
  for (int round = 0; round < kBiasRounds && sigma > 0 && e.width < kUnbiasedWidth * sigma; ++round)
    sigma = e.sigma / plane_fit_bias(k, e.width / sigma);
  return sigma;
}

/// The noise among the three scales. Noise leaves the same residual at every width, while the
/// model's detail (what a quadratic cannot follow) leaves one that shrinks with the width; a
/// narrower scale is taken while it reads clearly less than the wider one
/// (NoiseOptions::detail_ratio) and its neighbourhoods are still wide compared with it. Where the
/// widest neighbourhoods span fewer than NoiseOptions::noisy_width_ratio noise deviations, each
/// scale is first corrected for the noise its fit follows (corrected_noise()): then noise
/// reads the same at every width, and a narrower scale is taken when it reads less at all
/// (NoiseOptions::noisy_detail_ratio) while its neighbourhoods span kMinCorrectedWidth of its
/// deviations; the estimate never exceeds the widest fits' uncorrected residual.
double pick_scale(const std::array<LocalNoise, 3>& est, std::size_t k, const NoiseOptions& options) {
  const auto points_at = [&](std::size_t scale) { return std::max(k >> scale, kMinFitPoints); };
  const bool noisy = est[0].width < options.noisy_width_ratio * est[0].sigma;
  const double ratio = noisy ? options.noisy_detail_ratio : options.detail_ratio;
  const double min_width = noisy ? kMinCorrectedWidth : options.min_width_ratio;
  double sigma = noisy ? corrected_noise(est[0], points_at(0)) : est[0].sigma;
  for (std::size_t scale = 1; scale < 3; ++scale) {
    const LocalNoise& e = est[scale];
    if (!(e.sigma < ratio * sigma)) break;
    const double value = noisy ? corrected_noise(e, points_at(scale)) : e.sigma;
    if (!(value < ratio * sigma) || e.width < min_width * value) break;
    sigma = value;
  }
  // Never above what the widest fits read: their residual holds the noise and the detail, and
  // where they are too narrow to correct reliably (a small cloud that cannot be coarsened),
  // a correction would only add to both.
  return noisy ? std::min(sigma, est[0].sigma) : sigma;
}

/// The points of the nested subsample of `level` (about 4^-level of them; the support
/// sampler's levels).
Points subsample(const Points& points, unsigned level) {
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    if (detail::in_subsample(static_cast<std::uint64_t>(i), level)) keep.push_back(i);
  Points out(static_cast<Eigen::Index>(keep.size()), 3);
  for (std::size_t j = 0; j < keep.size(); ++j) out.row(static_cast<Eigen::Index>(j)) = points.row(keep[j]);
  return out;
}

}  // namespace

double estimate_noise(const Points& points, const NoiseOptions& options) {
  const auto n = static_cast<std::size_t>(points.rows());
  if (std::min(options.neighbors, n) < kMinFitPoints || options.samples == 0) return 0;
  return estimate_noise(points, KdTree(points), options);
}

double estimate_noise(const Points& points, const KdTree& tree, const NoiseOptions& options, const Points* normals) {
  const auto n = static_cast<std::size_t>(points.rows());
  if (std::min(options.neighbors, n) < kMinFitPoints || options.samples == 0) return 0;
  if (normals != nullptr && normals->rows() != points.rows()) throw OptionError("noise estimate: one normal per point is needed");
  if (!options.facing_normals) normals = nullptr;
  auto est = local_noise(points, tree, options, normals);
  // Dense samples of a noisy surface: the neighbourhoods are thin slabs of noise, and the
  // local fit follows it. Coarsen until the neighbourhoods are wide compared with the noise.
  for (unsigned level = 1; est[0].width < options.min_width_ratio * est[0].sigma && (n >> (2 * level)) >= kMinCoarsePoints; ++level) {
    const Points coarse = subsample(points, level);
    const Points coarse_normals = normals != nullptr ? subsample(*normals, level) : Points();
    est = local_noise(coarse, KdTree(coarse), options, normals != nullptr ? &coarse_normals : nullptr);
  }
  // The residual differences at the narrowest width see the least detail: they replace the
  // fits' residual where it is clearly higher, by detail.
  const double fitted = pick_scale(est, std::min(options.neighbors, n), options);
  return options.residual_differences && est[2].difference < kDetailMargin * fitted ? est[2].difference : fitted;
}

}  // namespace clustersurf
