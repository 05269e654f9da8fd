// Isolated points by their k-nearest-neighbour spread, against their neighbours' and the cloud's.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/outliers.hpp>

#include "spatial/neighborhood_shape.hpp"
#include "spatial/spatial_order.hpp"

#include <Eigen/Eigenvalues>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <utility>

namespace clustersurf {

namespace {

/// The median of `values` (reordered).
double median_of(std::vector<double>& values) {
  if (values.empty()) return 0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

/// Whether point `row` lies on the plane of its `k` nearest other points, and they on it
/// (OutlierOptions::global_ratio): their spread across the plane, and the point's distance from
/// it, at most kSparseSurfaceFlatness times their spread along it.
bool on_a_plane(const Points& points, const KdTree& index, Eigen::Index row, std::size_t k,
                std::vector<Neighbor>& near) {
  index.neighbors_of(row, k, near);
  if (near.size() < 3) return false;
  const detail::NeighborhoodShape shape = detail::neighborhood_shape(points, near);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(shape.covariance);  // ascending
  if (eig.info() != Eigen::Success) return false;
  const double across = std::max(0.0, eig.eigenvalues()(0)), along = eig.eigenvalues()(1);
  const double off = (points.row(row).transpose() - shape.mean).dot(eig.eigenvectors().col(0));
  const double limit = kSparseSurfaceFlatness * kSparseSurfaceFlatness * along;
  return along > 0 && across <= limit && off * off <= limit;
}

OutlierReport nothing_flagged(std::size_t n) {
  OutlierReport report;
  report.kept.resize(n);
  for (std::size_t i = 0; i < n; ++i) report.kept[i] = static_cast<Eigen::Index>(i);
  return report;
}

/// The spreads among the kept points (OutlierReport::kept_spread): `spread` where none of a
/// point's `k` nearest (`neighbors`, row o for the o-th point of `order`) is an outlier; else
/// its k nearest kept points, from queries of the whole cloud widened until they hold k.
std::vector<double> kept_spreads(const KdTree& index, std::size_t k, std::span<const std::uint32_t> order,
                                 std::span<const std::uint32_t> neighbors, std::span<const std::uint8_t> outlier,
                                 std::span<const double> spread, std::span<const Eigen::Index> kept) {
  const std::size_t n = spread.size();
  std::vector<double> own(spread.begin(), spread.end());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& r) {
    std::vector<Neighbor> nb;
    for (std::size_t o = r.begin(); o != r.end(); ++o) {
      const std::size_t i = order[o];
      if (outlier[i]) continue;
      const auto row = neighbors.subspan(o * k, k);
      if (std::none_of(row.begin(), row.end(), [&](std::uint32_t j) { return outlier[j] != 0; })) continue;
      for (std::size_t want = 2 * k;; want *= 2) {
        index.neighbors_of(static_cast<Eigen::Index>(i), std::min(want, n - 1), nb);
        double sum = 0;
        std::size_t found = 0;
        for (const Neighbor& q : nb)
          if (!outlier[q.index] && found < k) sum += std::sqrt(q.distance_squared), ++found;
        if (found == k || want >= n - 1) {
          own[i] = found > 0 ? sum / static_cast<double>(found) : 0;
          break;
        }
      }
    }
  });
  std::vector<double> out(kept.size());
  for (std::size_t j = 0; j < kept.size(); ++j) out[j] = own[static_cast<std::size_t>(kept[j])];
  return out;
}

/// find_outliers() against `median_spread`, or the points' own median spread when null.
OutlierReport flag_outliers(const Points& points, const KdTree& index, const OutlierOptions& options,
                            const double* median_spread);

}  // namespace

OutlierReport find_outliers(const Points& points, const OutlierOptions& options) {
  if (points.rows() < static_cast<Eigen::Index>(std::max(options.min_points, options.neighbors + 2)))
    return nothing_flagged(static_cast<std::size_t>(points.rows()));
  return find_outliers(points, KdTree(points), options);
}

OutlierReport find_outliers(const Points& points, const KdTree& index, const OutlierOptions& options) {
  return flag_outliers(points, index, options, nullptr);
}

OutlierReport find_outliers(const Points& points, const KdTree& index, const OutlierOptions& options,
                            double median_spread) {
  if (!(median_spread >= 0) || !std::isfinite(median_spread))
    throw OptionError("outlier test: the median spread must be finite and >= 0");
  return flag_outliers(points, index, options, &median_spread);
}

namespace {

OutlierReport flag_outliers(const Points& points, const KdTree& index, const OutlierOptions& options,
                            const double* median_spread) {
  if (options.neighbors < 1) throw OptionError("outlier test: neighbors must be at least 1");
  if (options.plane_neighbors < 3) throw OptionError("outlier test: plane_neighbors must be at least 3");
  if (!(options.local_ratio >= 0) || !(options.global_ratio >= 0) || !std::isfinite(options.local_ratio) ||
      !std::isfinite(options.global_ratio))
    throw OptionError("outlier test: ratios must be finite and >= 0 (0 turns a test off)");
  const auto n = static_cast<std::size_t>(points.rows());
  const std::size_t k = options.neighbors;
  if (index.size() != n) throw OptionError("outlier test: the k-d tree is not one of these points");
  if (n < std::max(options.min_points, k + 2)) return nothing_flagged(n);
  OutlierReport report;
  // Spread of every point, and its k neighbours (the query itself, at distance 0, left out).
  // The points are queried in spatial order, and the neighbours of the o-th query are stored
  // at row o: both passes write and read that table sequentially.
  std::vector<double> spread(n);
  report.nearest.resize(n);
  report.coincident.assign(n, 0);
  std::vector<std::uint32_t> neighbors(n * k);
  const std::vector<std::uint32_t> order = detail::spatial_order(points);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& r) {
    std::vector<Neighbor> nb;
    for (std::size_t o = r.begin(); o != r.end(); ++o) {
      const std::size_t i = order[o];
      index.neighbors_of(static_cast<Eigen::Index>(i), k, nb);
      double sum = 0;
      for (std::size_t j = 0; j < k; ++j) {
        neighbors[o * k + j] = nb[j].index;
        sum += std::sqrt(nb[j].distance_squared);
      }
      spread[i] = sum / static_cast<double>(k);
      // The nearest point at another position: repeats of this one's say nothing of the spacing.
      const auto other = std::find_if(nb.begin(), nb.end(), [](const Neighbor& q) { return q.distance_squared > 0; });
      report.nearest[i] = other == nb.end() ? 0.0 : std::sqrt(other->distance_squared);
      report.coincident[i] = other != nb.begin();
    }
  });
  if (median_spread != nullptr) {
    report.median_spread = *median_spread;
  } else {
    std::vector<double> sorted = spread;
    report.median_spread = median_of(sorted);
  }
  const double global_limit = options.global_ratio > 0 && report.median_spread > 0
                                  ? options.global_ratio * report.median_spread
                                  : std::numeric_limits<double>::infinity();
  std::vector<std::uint8_t> outlier(n, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& r) {
    std::vector<double> around(k);
    std::vector<Neighbor> near;
    for (std::size_t o = r.begin(); o != r.end(); ++o) {
      const std::size_t i = order[o];
      for (std::size_t j = 0; j < k; ++j) around[j] = spread[neighbors[o * k + j]];
      const double reference = std::max(median_of(around), 0.5 * report.median_spread);
      const bool local = options.local_ratio > 0 && reference > 0 && spread[i] > options.local_ratio * reference;
      outlier[i] = local || (spread[i] > global_limit &&
                             !on_a_plane(points, index, static_cast<Eigen::Index>(i), options.plane_neighbors, near));
    }
  });
  for (std::size_t i = 0; i < n; ++i)
    (outlier[i] ? report.outliers : report.kept).push_back(static_cast<Eigen::Index>(i));
  report.kept_spread = kept_spreads(index, k, order, neighbors, outlier, spread, report.kept);
  return report;
}

}  // namespace

}  // namespace clustersurf
