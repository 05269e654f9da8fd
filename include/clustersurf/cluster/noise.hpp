#pragma once
// Estimating the noise level of a scan, for the automatic error threshold.

#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <cmath>

namespace clustersurf {

/// Options of estimate_noise().
struct NoiseOptions {
  std::size_t neighbors = 96;  ///< points per local fit: enough that the fit cannot follow the noise
  std::size_t samples = 4000;  ///< local fits (evenly strided points, deterministic)
  /// A neighbourhood narrower than this many times the estimated noise lets the fit follow the
  /// noise (the estimate then falls short); the estimate is repeated on every 4th point (twice
  /// as wide neighbourhoods) until the neighbourhoods are this wide.
  double min_width_ratio = 6;
  /// The fits are repeated on the nearest half and quarter of each neighbourhood. A narrower
  /// fit whose median residual is below this fraction of the wider one's measured the model's
  /// detail, not noise (noise leaves the same residual at every width); it is taken instead,
  /// if its neighbourhoods are still min_width_ratio times wider than that residual. Clearly
  /// below: a real scan's noise is not independent from point to point, and reads somewhat less
  /// in narrower neighbourhoods too (Stanford's bun000: 0.66 of the widest fits' at half their
  /// points). 0 keeps the widest fits' estimate.
  double detail_ratio = 0.6;
  /// Where the widest fits' neighbourhoods (their median radius) are smaller than this many
  /// times the residual they read, noise dominates them, and a narrow fit follows a measurable
  /// part of it and reads less than the noise (24 points within 4 σ: 0.87 of it; 96 points
  /// within 7 σ: 0.97). There each width's residual is first corrected for that, by simulating
  /// the same fit on a noisy plane of the same radius and points; noise then reads the same at
  /// every width, and a narrower width that reads less measured the model's detail and is
  /// taken (neither min_width_ratio nor detail_ratio applies; a width too narrow for a reliable
  /// correction is not taken). The correction only ever lowers the estimate below what the
  /// rule above gives. 0 turns it off.
  double noisy_width_ratio = 12;
  /// Also estimate the noise from the differences of neighbouring points' residuals in the
  /// narrowest fits (Rice's difference estimator): independent noise counts twice in them,
  /// detail the fit leaves is nearly the same at neighbours and cancels. Taken where the fits
  /// read more than twice as much: relief the fits cannot follow, as in a sparse scan of a
  /// detailed model, not noise. Noise correlated from point to point (a real range scan's:
  /// Stanford's bun000 reads 0.55 of the fits' in the differences) and the faceting of clean
  /// mesh samples (about 0.75) keep the fits' estimate.
  bool residual_differences = true;
  /// With input normals (estimate_noise()'s `normals`; the tree builder passes the input's
  /// unless BuildOptions::use_normals is off), each local fit keeps the neighbours facing its
  /// centre's way: the two sides of a thin part or of a narrow fold are two surfaces, not one
  /// noisy layer (two clean sheets 4 spacings apart read as noise of 2 spacings without it).
  bool facing_normals = true;
  /// Each cluster keeps the noise where it lies (NoiseField: the sampled fits' residuals over
  /// the surface, between the estimate and kMaxLocalNoise times it), not the estimate, a median
  /// set by the quietest half of the surface: scans overlapping at grazing angles, a scanner's
  /// noise growing with range. Off: the estimate everywhere.
  bool local = true;
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<NoiseOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("neighbors", o.neighbors);
  f("samples", o.samples);
  f("min_width_ratio", o.min_width_ratio);
  f("detail_ratio", o.detail_ratio);
  f("noisy_width_ratio", o.noisy_width_ratio);
  f("residual_differences", o.residual_differences);
  f("facing_normals", o.facing_normals);
  f("local", o.local);
}

/// Robust estimate of the standard deviation of the points' normal-direction noise: the median
/// over sampled neighbourhoods of the RMS residual of a local quadratic height-field fit,
/// corrected for the fit's degrees of freedom, taken on a subsample coarse enough that the
/// neighbourhoods are wide relative to the noise, and at the narrowest of three widths where
/// the residual is still shrinking (detail, not noise; where noise dominates, after correcting
/// each width for the noise its fit follows); or, where less than half of that, the median
/// estimate from the differences of neighbouring residuals in the narrowest fits
/// (NoiseOptions::residual_differences), which detail the fits leave hardly reaches. Smooth noise-free samples give a
/// value near 0; clean scans of detailed models a value well below their detail's misfit at the widest scale.
double estimate_noise(const Points& points, const NoiseOptions& options = {});
/// The same estimate with a k-d tree of `points` the caller already has. With `normals` (one
/// row per point, oriented consistently, or null) and NoiseOptions::facing_normals, each local
/// fit keeps only the neighbours whose normal is within 90° of its centre point's. Where
/// `points` are one region of a cloud of `cloud_points` points (0: the whole cloud), the sample
/// is coarsened as far as the whole cloud's would be, so that a region reads the noise at the
/// same scale as the whole cloud does.
double estimate_noise(const Points& points, const KdTree& index, const NoiseOptions& options = {},
                      const Points* normals = nullptr, std::uint64_t cloud_points = 0);

/// Standard deviations of margin a test of noise allows: the mean of n (effective) squared
/// residuals of pure noise varies by a relative √(2/n), so a fit is not taken for detail for
/// noise alone.
inline constexpr double kNoiseMargin = 2;
/// The factor 1 + kNoiseMargin √(2/n) by which such a test lets a mean of n squared residuals
/// exceed the noise's variance (1 for n ≤ 0).
inline double noise_variance_margin(double n) { return n > 0 ? 1 + kNoiseMargin * std::sqrt(2 / n) : 1; }
/// The upper quantile, kNoiseMargin standard deviations out, of a mean of n squared standard
/// normal values (Wilson and Hilferty's cube-root normal form; 1 for n ≤ 0): the margin for a mean
/// of few squares, whose long tail noise_variance_margin() understates (5.1 against 3.8 for
/// one square, 2.1 against 1.9 for ten).
inline double noise_variance_quantile(double n) {
  if (!(n > 0)) return 1;
  const double c = 2 / (9 * n);
  const double root = 1 - c + kNoiseMargin * std::sqrt(c);
  return root * root * root;
}

}  // namespace clustersurf
