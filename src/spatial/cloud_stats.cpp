#include <clustersurf/spatial/cloud_stats.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include "spatial/spatial_order.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace clustersurf {

namespace {

/// The rows point_spacing() samples among `count`: every one up to `max_samples`, then an even
/// stride.
std::vector<Eigen::Index> sampled_rows(std::size_t count, std::size_t max_samples) {
  const std::size_t samples = std::min(count, max_samples);
  const double stride = static_cast<double>(count) / static_cast<double>(samples);
  std::vector<Eigen::Index> rows(samples);
  for (std::size_t j = 0; j < samples; ++j) rows[j] = static_cast<Eigen::Index>(static_cast<double>(j) * stride);
  return rows;
}

/// The mean and the median of the sampled nearest-neighbour distances (reordered).
PointSpacing summarize(std::vector<double>& nearest) {
  PointSpacing out;
  const std::size_t samples = nearest.size();
  // Summation in sample order keeps the result independent of the thread count.
  out.mean = std::accumulate(nearest.begin(), nearest.end(), 0.0) / static_cast<double>(samples);
  std::nth_element(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(samples / 2), nearest.end());
  out.median = nearest[samples / 2];
  return out;
}

}  // namespace

PointSpacing point_spacing(const KdTree& index, std::size_t max_samples) {
  return point_spacing(index, max_samples, index.size());
}

PointSpacing point_spacing(const KdTree& index, std::size_t max_samples, std::size_t rows) {
  const Points& points = index.points();
  const auto count = std::min(rows, static_cast<std::size_t>(points.rows()));
  if (count < 1 || points.rows() < 2 || max_samples == 0) return {};
  const std::vector<Eigen::Index> rows_sampled = sampled_rows(count, max_samples);
  const std::size_t samples = rows_sampled.size();
  // Queried in Morton order (the answers do not depend on it; the cache hits do).
  const std::vector<std::uint32_t> order = detail::spatial_order(points, rows_sampled);
  std::vector<double> nearest(samples);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples, 1024), [&](const auto& r) {
    std::vector<Neighbor> nb;
    for (std::size_t o = r.begin(); o != r.end(); ++o) {
      const std::size_t j = order[o];
      const Eigen::Index i = rows_sampled[j];
      // The nearest point at another position: the query itself and its repeats left out.
      index.knn(points.row(i).transpose(), 2, nb);
      if (nb.size() > 1 && nb[1].distance_squared == 0)
        index.knn(points.row(i).transpose(), kRepeatsLookedPast + 1, nb);
      const auto other = std::find_if(nb.begin(), nb.end(), [](const Neighbor& q) { return q.distance_squared > 0; });
      nearest[j] = other == nb.end() ? 0.0 : std::sqrt(other->distance_squared);
    }
  });
  return summarize(nearest);
}

PointSpacing point_spacing(std::span<const double> nearest, std::size_t max_samples) {
  if (nearest.empty() || max_samples == 0) return {};
  const std::vector<Eigen::Index> rows_sampled = sampled_rows(nearest.size(), max_samples);
  std::vector<double> sampled(rows_sampled.size());
  for (std::size_t j = 0; j < sampled.size(); ++j) sampled[j] = nearest[static_cast<std::size_t>(rows_sampled[j])];
  return summarize(sampled);
}

CloudStats compute_stats(const PointCloud& cloud, std::size_t max_samples) {
  CloudStats s;
  s.points = static_cast<std::size_t>(cloud.size());
  s.bbox = bounding_box(cloud.positions);
  s.diagonal = s.bbox.diagonal();
  if (!s.bbox.empty()) s.bbox.min += cloud.origin, s.bbox.max += cloud.origin;
  s.origin = cloud.origin;
  s.has_normals = cloud.has_normals();
  s.has_colors = cloud.has_colors();
  for (const PointAttribute& a : cloud.attributes) s.attributes.push_back(a.name);
  s.scanners = static_cast<std::size_t>(cloud.scanner_positions.rows());
  s.scans = scan_count(cloud);
  if (s.points < 2 || max_samples == 0) return s;
  const PointSpacing spacing = point_spacing(KdTree(cloud.positions), max_samples);
  s.mean_spacing = spacing.mean;
  s.median_spacing = spacing.median;
  return s;
}

}  // namespace clustersurf
