#pragma once
// Finding isolated points (scanner strays, points in the air) before the tree is built.

#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf {

/// Options of find_outliers(). A point's spread d̄ is its mean distance to its k nearest
/// neighbours; surface samples have spreads like their neighbours', isolated points do not.
struct OutlierOptions {
  std::size_t neighbors = kRepeatsLookedPast;  ///< k (by default as many as point_spacing() looks past)
  /// An outlier has a spread this many times its neighbours' median spread (a point standing
  /// off the surface, next to surface points); the reference is at least half the cloud's
  /// median spread, so a point beside a dense patch is not judged by the patch alone.
  double local_ratio = 3;
  /// ... or this many times the cloud's median spread (points in the air, whose neighbours are
  /// other isolated points), unless its `plane_neighbors` nearest points lie on a plane and
  /// it on their plane (their spread across it, and its distance from it, at most
  /// kSparseSurfaceFlatness times their spread along it): a part of the surface sampled far
  /// more sparsely than the rest (a terrestrial scan's far side, the sparse rest of a
  /// multi-view stereo cloud), not points in the air, which scatter in all three directions.
  double global_ratio = 6;
  std::size_t plane_neighbors = 16;  ///< the neighbours whose plane global_ratio's exception tests

  /// Clouds with fewer points are left whole: too few for the statistics.
  std::size_t min_points = 100;
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<OutlierOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("neighbors", o.neighbors);
  f("local_ratio", o.local_ratio);
  f("global_ratio", o.global_ratio);
  f("plane_neighbors", o.plane_neighbors);
  f("min_points", o.min_points);
}

/// OutlierOptions::global_ratio's plane: the spread across it (the square root of the least
/// eigenvalue of the points' covariance) at most this fraction of the spread along it (of the
/// middle one). Points scattered in a ball: about 0.7; on a plane, the noise over the spacing.
inline constexpr double kSparseSurfaceFlatness = 0.25;

/// What find_outliers() found.
struct OutlierReport {
  std::vector<Eigen::Index> kept;      ///< rows that are not outliers, ascending
  std::vector<Eigen::Index> outliers;  ///< rows that are, ascending
  double median_spread = 0;            ///< the cloud's median d̄
  /// Each point's distance to its nearest point at another position (0 where its k nearest all
  /// lie at its own), measured on the way (point_spacing() takes it); empty when the cloud was
  /// too small to test.
  std::vector<double> nearest;
  /// Per row, 1 where another point lies at its very position (first_of_each_position() then
  /// compares only those); empty when the cloud was too small to test.
  std::vector<std::uint8_t> coincident;
  /// Each kept point's spread among the kept points alone (in `kept`'s order; k = neighbors):
  /// what a k-d tree of the kept points gives, the trim's measure of the data's reach
  /// (TrimOptions::neighbors); empty when the cloud was too small to test.
  std::vector<double> kept_spread;
};

/// Splits the rows of `points` into outliers and the rest by the two spread tests above.
/// Deterministic and independent of the thread count. Clouds below `min_points` flag nothing;
/// a ratio of 0 turns its test off.
OutlierReport find_outliers(const Points& points, const OutlierOptions& options = {});
/// The same with a k-d tree of `points` the caller already has.
OutlierReport find_outliers(const Points& points, const KdTree& index, const OutlierOptions& options = {});
/// The same judged against a given median spread instead of the points' own (the whole
/// cloud's, for a region of it with a halo); report.median_spread is that value.
OutlierReport find_outliers(const Points& points, const KdTree& index, const OutlierOptions& options,
                            double median_spread);

}  // namespace clustersurf
