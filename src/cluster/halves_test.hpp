#pragma once
// The nested least-squares test of a cluster's halves: whether a quadratic per half fits its
// points significantly better than one quadratic, a misfit its residual's spread cannot show.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/proxy/proxy.hpp>

#include <array>
#include <cstdint>
#include <span>

namespace clustersurf::detail {

/// What halving a cluster along one axis of its frame leaves.
struct HalvesDrop {
  double drop = 0;    ///< weighted residual sum of squares, one quadratic's less the halves' own
  double spread = 0;  ///< the smaller variance of either half along the frame's first two axes
};

/// For each of the first two axes of `frame`: points[ids] halved at the median of that axis
/// (by position alone, so that the drop's null distribution holds: a split chosen to fit best
/// would inflate it), the drop of the residual sum of squares of their heights, weighted by
/// `weights` (one per id; empty: all 1), from one quadratic fitted in `frame` to one per half,
/// and the halves' spread across the plane. Zeros for fewer than two points.
std::array<HalvesDrop, 2> halves_drops(const Points& points, std::span<const std::uint32_t> ids,
                                       std::span<const double> weights, const Frame& frame);

/// The largest drop the noise σ alone leaves, kNoiseMargin deviations out: σ² times the quantile
/// of a chi-square of six degrees of freedom (the halves' six more coefficients), scaled by the
/// weights' own mean weight Σw² / Σw (1 for unit weights; weights at most 1 give at most that).
double halves_drop_bound(double noise, double mean_weight = 1);

}  // namespace clustersurf::detail
