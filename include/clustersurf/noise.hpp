#pragma once
// Estimating the noise level of a scan, for the automatic error threshold.

#include <clustersurf/kd_tree.hpp>
#include <clustersurf/point_cloud.hpp>

namespace clustersurf {

/// Options of estimate_noise().
struct NoiseOptions {
  std::size_t neighbors = 96;     ///< points per local fit: enough that the fit cannot follow the noise
  std::size_t samples = 4000;     ///< local fits (evenly strided points, deterministic)
  /// A neighbourhood narrower than this many times the estimated noise lets the fit follow the
  /// noise (the estimate then falls short); the estimate is repeated on every 4th point (twice
  /// as wide neighbourhoods) until the neighbourhoods are this wide.
  double min_width_ratio = 6;
};

/// Robust estimate of the standard deviation of the points' normal-direction noise: the median
/// over sampled neighbourhoods of the RMS residual of a local quadratic height-field fit,
/// corrected for the fit's degrees of freedom, taken on a subsample coarse enough that the
/// neighbourhoods are wide relative to the noise. Smooth noise-free samples give a value near 0.
double estimate_noise(const Points& points, const NoiseOptions& options = {});
/// The same estimate with a k-d tree of `points` the caller already has.
double estimate_noise(const Points& points, const KdTree& index, const NoiseOptions& options = {});

}  // namespace clustersurf
