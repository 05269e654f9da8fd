#pragma once
// How much of a local fit's noise the leaves' blend shares: both average the same input points,
// so the move from the blend to the fit carries only the difference of their noises.

#include <clustersurf/surface/box_walk.hpp>
#include <clustersurf/surface/implicit_surface.hpp>

#include <Eigen/Core>

namespace clustersurf::detail {

/// The variance of a quadratic height field fitted with the weights (1 − r²)³ to points spread
/// evenly over the unit disk, at squared distance `rho2` (in [0, 1]) from the disk's centre,
/// over its variance at the centre: 1 at the centre, 0.86 at a quarter of the radius, 3.1 at
/// three quarters, 6.4 at nine tenths.
double off_center_variance(double rho2);

/// The blend's noise variance at x over that of a fit of the same kernel centred at x whose
/// points reach `fit_radius`, at the same density, at most 1: the blended supports around x
/// are fits of the same kernel (the leaves' support fits) over their radius R, each off its
/// centre, with the variance (fit_radius / R)² off_center_variance(s); their noises, from
/// overlapping points, are taken as fully correlated (standard deviations added with the
/// blend's weights). 0 where no support reaches x. The supports are found through `near`'s walk
/// (the same as the surface's own, to the bit).
double blend_variance_share(const ImplicitSurface::BoxWalk& near, const Eigen::Vector3d& x, double fit_radius);

}  // namespace clustersurf::detail
