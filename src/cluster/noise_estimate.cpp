#include <clustersurf/cluster/noise.hpp>
#include <clustersurf/cluster/noise_field.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/proxy/proxy.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include "cluster/local_fit.hpp"
#include "core/splitmix.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace clustersurf {

namespace {

/// The differences' estimate replaces the fits' when below this fraction of it: then most of the
/// fits' residual is relief they cannot follow (a sparse scan of a detailed model: Igea's 3,000-
/// and 10,000-point virtual scans read 0.16 and 0.35 of the fits'), not noise. On independent
/// noise the two agree within about 7 %; noise correlated from point to point, as a real range
/// scan's is, and the faceting of clean samples of a mesh read less in the differences too
/// (Stanford's bun000: 0.55; faceted meshes about 0.75; the noisy ogre and beast 0.7), and the
/// fits' estimate is kept there.
constexpr double kDetailMargin = 0.5;
/// A local fit takes at least this many points (a quadratic's 6 coefficients and 4 to spare).
constexpr std::size_t kMinFitPoints = 10;
/// The sampled neighbourhoods never come from fewer points than this.
constexpr std::size_t kMinCoarsePoints = 4096;

/// The local fits' medians at one neighbourhood size.
struct LocalNoise {
  double sigma = 0;        // median RMS residual of the local fits
  double difference = 0;   // median of the residual differences' estimate (LocalFit::difference)
  double width = 0;        // median neighbourhood radius
  std::size_t points = 0;  // median points per fit
};

/// Each sampled fit's place, what it reads against the median fit of its width (the least of
/// its three widths' ratios), its widest fit's kurtosis, and the fits' points (NoiseField).
struct SampledFits {
  Points sites;
  std::vector<double> ratio;
  std::vector<double> kurtosis;
  std::size_t widest_points = 0;
  std::size_t narrowest_points = 0;
};

/// Median noise and neighbourhood radius over evenly strided points of `points`, for the
/// neighbourhood sizes options.neighbors, /2, /4 (nested: the nearest of one query). With
/// `normals`, a neighbourhood holds the neighbours facing the same way as its centre (when at
/// least kMinFitPoints do; all of them otherwise). With `fits`, each fit's place and ratio too.
std::array<LocalNoise, 3> local_noise(const Points& points, const KdTree& tree, const NoiseOptions& options,
                                      const Points* normals, SampledFits* fits) {
  const auto n = static_cast<std::size_t>(points.rows());
  const std::size_t k = std::min(options.neighbors, n);
  const std::size_t samples = std::min(options.samples, n);
  const double stride = static_cast<double>(n) / static_cast<double>(samples);
  std::array<std::vector<double>, 3> sigma, difference, width, size;
  std::vector<double> kurtosis(samples);
  for (auto& v : size) v.resize(samples);
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
        size[scale][s] = static_cast<double>(m);
        // Only the narrowest fits' differences are ever used (estimate_noise()).
        const detail::LocalFit fit = detail::fit_residual(points, idx, options.residual_differences && scale == 2);
        sigma[scale][s] = fit.residual;
        difference[scale][s] = fit.difference;
        if (scale == 0) kurtosis[s] = fit.kurtosis;
      }
    }
  });
  const auto median = [&](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(samples / 2), v.end());
    return v[samples / 2];
  };
  std::array<LocalNoise, 3> out;
  for (std::size_t scale = 0; scale < 3; ++scale)
    out[scale] = {median(sigma[scale]), median(difference[scale]), median(width[scale]),
                  static_cast<std::size_t>(median(size[scale]))};
  if (fits != nullptr) {
    fits->sites.resize(static_cast<Eigen::Index>(samples), 3);
    fits->ratio.assign(samples, std::numeric_limits<double>::infinity());
    fits->kurtosis = std::move(kurtosis);
    fits->widest_points = out[0].points;
    fits->narrowest_points = out[2].points;
    for (std::size_t s = 0; s < samples; ++s) {
      fits->sites.row(static_cast<Eigen::Index>(s)) =
          points.row(static_cast<Eigen::Index>(static_cast<double>(s) * stride));
      for (std::size_t scale = 0; scale < 3; ++scale)
        if (out[scale].sigma > 0) fits->ratio[s] = std::min(fits->ratio[s], sigma[scale][s] / out[scale].sigma);
      if (!std::isfinite(fits->ratio[s])) fits->ratio[s] = 1;
    }
  }
  return out;
}

/// Rounds and relative tolerance of the fixed point σ = residual / bias(width / σ).
constexpr int kBiasRounds = 8;
constexpr double kBiasTolerance = 0.005;
/// A scale is only corrected when its neighbourhoods span at least this many of its corrected
/// noise deviations: narrower, the fit follows so much of the noise that its bias varies
/// steeply with the width (0.75 at 3.4 σ for 24 points) and the correction is not reliable.
constexpr double kMinCorrectedWidth = 3.5;

/// The noise σ behind the median residual of one scale, corrected for the part of the noise its
/// fits follow: the σ for which a noisy plane, fitted alike, reads that residual at that width
/// (detail::plane_fit_bias(), its width calibrated as this scale's is measured). nullopt when
/// no such σ is found, or the neighbourhoods are narrower than kMinCorrectedWidth of it.
std::optional<double> corrected_noise(const LocalNoise& e) {
  if (!(e.sigma > 0) || !(e.width > 0) || !std::isfinite(e.sigma) || !std::isfinite(e.width) ||
      e.points < kMinFitPoints)
    return std::nullopt;
  double sigma = e.sigma, width_scale = 1;
  for (int round = 0; round < kBiasRounds; ++round) {
    const detail::FitBias bias = detail::plane_fit_bias(e.points, e.width / sigma / width_scale);
    const double next = e.sigma / bias.residual;
    if (!std::isfinite(next) || !(next > 0)) return std::nullopt;
    const bool converged = std::abs(next - sigma) <= kBiasTolerance * next;
    sigma = next;
    width_scale = bias.width;
    if (converged) return e.width < kMinCorrectedWidth * sigma ? std::nullopt : std::optional<double>(sigma);
  }
  return std::nullopt;
}

/// The noise among the three scales by their residuals as measured: noise leaves the same
/// residual at every width, the model's detail one that shrinks with it; a narrower scale is
/// taken while it reads clearly less than the wider one (NoiseOptions::detail_ratio) and its
/// neighbourhoods are still min_width_ratio times wider than that.
double measured_scale(const std::array<LocalNoise, 3>& est, const NoiseOptions& options) {
  double sigma = est[0].sigma;
  for (std::size_t scale = 1; scale < 3; ++scale) {
    const LocalNoise& e = est[scale];
    if (!(e.sigma < options.detail_ratio * sigma) || e.width < options.min_width_ratio * e.sigma) break;
    sigma = e.sigma;
  }
  return sigma;
}

/// The noise among the three scales. Where the widest neighbourhoods span fewer than
/// NoiseOptions::noisy_width_ratio of their residuals (noise dominates them), each scale is
/// first corrected for the noise its fits follow (corrected_noise()): noise then reads the same
/// at every width, and a narrower scale that reads less measured detail and is taken. The
/// correction only ever lowers the estimate: never above measured_scale()'s.
double pick_scale(const std::array<LocalNoise, 3>& est, const NoiseOptions& options) {
  const double measured = measured_scale(est, options);
  if (!(est[0].width < options.noisy_width_ratio * est[0].sigma)) return measured;
  const std::optional<double> widest = corrected_noise(est[0]);
  if (!widest) return measured;
  double sigma = *widest;
  for (std::size_t scale = 1; scale < 3; ++scale) {
    const std::optional<double> narrower = corrected_noise(est[scale]);
    if (!narrower || !(*narrower < sigma)) break;
    sigma = *narrower;
  }
  return std::min(sigma, measured);
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

namespace {

/// estimate_noise() and, with `fits`, the sampled fits of the subsample it settled on.
double estimate(const Points& points, const KdTree& tree, const NoiseOptions& options, const Points* normals,
                std::uint64_t cloud_points, SampledFits* fits) {
  const auto n = static_cast<std::size_t>(points.rows());
  if (std::min(options.neighbors, n) < kMinFitPoints || options.samples == 0) return 0;
  if (normals != nullptr && normals->rows() != points.rows())
    throw OptionError("noise estimate: one normal per point is needed");
  if (!options.facing_normals) normals = nullptr;
  auto est = local_noise(points, tree, options, normals, fits);
  // Dense samples of a noisy surface: the neighbourhoods are thin slabs of noise, and the
  // local fit follows it. Coarsen until the neighbourhoods are wide compared with the noise, as
  // far as the whole cloud's subsample keeps kMinCoarsePoints.
  const std::uint64_t whole = std::max<std::uint64_t>(cloud_points, n);
  for (unsigned level = 1;
       est[0].width < options.min_width_ratio * est[0].sigma && (whole >> (2 * level)) >= kMinCoarsePoints; ++level) {
    const Points coarse = subsample(points, level);
    // A small region's subsample may hold too few points for one neighbourhood.
    if (static_cast<std::size_t>(coarse.rows()) < options.neighbors) break;
    const Points coarse_normals = normals != nullptr ? subsample(*normals, level) : Points();
    est = local_noise(coarse, KdTree(coarse), options, normals != nullptr ? &coarse_normals : nullptr, fits);
  }
  // The residual differences at the narrowest width see the least detail: they replace the
  // fits' residual where it is clearly higher, by detail. The fits' variation over the surface
  // is then the detail's too: no field.
  const double fitted = pick_scale(est, options);
  if (!(options.residual_differences && est[2].difference < kDetailMargin * fitted)) return fitted;
  if (fits != nullptr) *fits = {};
  return est[2].difference;
}

}  // namespace

double estimate_noise(const Points& points, const KdTree& tree, const NoiseOptions& options, const Points* normals,
                      std::uint64_t cloud_points) {
  return estimate(points, tree, options, normals, cloud_points, nullptr);
}

NoiseEstimate estimate_noise_field(const Points& points, const KdTree& index, const NoiseOptions& options,
                                   const Points* normals, std::uint64_t cloud_points) {
  SampledFits fits;
  NoiseEstimate out;
  out.sigma = estimate(points, index, options, normals, cloud_points, &fits);
  if (!(out.sigma > 0) || fits.ratio.empty()) return out;
  for (double& r : fits.ratio) r *= out.sigma;
  // Fits of the neighbours facing their centre's way keep a thin part's sides apart.
  if (normals != nullptr && options.facing_normals) fits.kurtosis.clear();
  out.field = NoiseField(std::move(fits.sites), std::move(fits.ratio), std::move(fits.kurtosis), out.sigma,
                         fits.widest_points, fits.narrowest_points);
  return out;
}

}  // namespace clustersurf
