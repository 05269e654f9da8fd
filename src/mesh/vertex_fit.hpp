#pragma once
// A vertex's weighted quadratic fits of the input points around it: the move each asks for along
// the vertex's normal, that move's variance under the noise, and the noise its residuals show.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <span>

namespace clustersurf::detail {

/// One vertex's local fit: the move it asks for along the normal, and that move's variance
/// per unit variance of the noise.
struct LocalFit {
  double move = 0;
  /// The fit's height's variance; refit_vertices() takes the blend's share of it away (the
  /// move is the fit's height less the blend's, whose noise is part of the fit's).
  double unit_variance = 0;
  /// The noise variance its residuals show (Σw r² over its expectation per unit variance,
  /// Σw − tr(A⁻¹B): its degrees of freedom), relief included.
  double residual_variance = 0;
  double dof = 0;
  double radius = 0;  ///< the farthest of its points
  bool valid = false;
};

/// The weighted quadratic height field over the `near` points of `data` around `x` in the frame
/// of `normal`, evaluated at x: its height is the move. Undetermined (not valid) where its
/// weighted RMS residual exceeds what `tree` allows a cluster of as many effective points: the
/// points are not one smooth sheet there (a sharp edge, both sides of a thin part). Its
/// residuals' degrees of freedom and noise variance only `with_residual_noise`.
LocalFit fit_at(const Eigen::Vector3d& x, const Eigen::Vector3d& normal, const Points& data,
                std::span<const Neighbor> near, const ClusterTree& tree, bool with_residual_noise);

/// The noise variance the residuals of two nested fits show, the relief they also hold taken
/// away. Anything but noise leaves a quadratic's residuals a variance that grows with the
/// radius, at least as its square (as a crease's kink does; a smooth surface's cubic terms, once
/// the radius is small against them, as its sixth power); noise leaves one that does not grow.
/// So with q the squared ratio of the radii, (q R_narrow − R_wide) / (q − 1) holds the noise
/// and at most none of the relief (at least 0). On pure noise it spreads no more than a
/// chi-square mean of the narrow fit's degrees of freedom, Σw − tr(A⁻¹B), which the refit's
/// margin takes for it. The narrow fit's own where the wide one is undetermined.
double relief_free_noise(const LocalFit& narrow, const LocalFit& wide);

/// How many widths a vertex's fit is tried at: VertexRefitOptions::points nearest points, then
/// twice as many, and so on.
inline constexpr int kFitWidths = 2;

/// The widest of the fits at x to the nearest 1, 2, … kFitWidths times `points` of `near`
/// (sorted by distance) whose confidence interval, move ± kNoiseMargin standard deviations,
/// meets those of all narrower ones (Goldenshluger and Nemirovski's intersection of confidence
/// intervals): a wider fit averages more noise away and is taken while its bias does not show.
/// Its noise is the one the narrowest two fits' residuals show without their relief
/// (relief_free_noise()), with the narrowest fit's degrees of freedom.
LocalFit widest_consistent_fit(const Eigen::Vector3d& x, const Eigen::Vector3d& normal, const Points& data,
                               std::span<const Neighbor> near, std::size_t points, const ClusterTree& tree);

}  // namespace clustersurf::detail
