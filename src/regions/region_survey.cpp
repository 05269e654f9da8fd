// What each region measures for the cloud's scale, and the scale the regions share.

#include <clustersurf/cluster/noise.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/regions/regions.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>
#include <clustersurf/spatial/outliers.hpp>
#include <clustersurf/spatial/repeated_positions.hpp>

#include <algorithm>
#include <numeric>
#include <span>

namespace clustersurf {

namespace {

/// The median of `value` over the surveys, each counted with its points (the lower median).
template <class Member>
double weighted_median(std::span<const RegionSurvey> surveys, Member value) {
  std::vector<std::size_t> order;
  std::uint64_t total = 0;
  for (std::size_t r = 0; r < surveys.size(); ++r)
    if (surveys[r].points > 0) order.push_back(r), total += surveys[r].points;
  if (order.empty()) return 0;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const double va = surveys[a].*value, vb = surveys[b].*value;
    return va < vb || (va == vb && a < b);
  });
  std::uint64_t seen = 0;
  for (const std::size_t r : order) {
    seen += surveys[r].points;
    if (2 * seen >= total) return surveys[r].*value;
  }
  return surveys[order.back()].*value;
}

}  // namespace

RegionSurvey survey_region(const RegionCloud& region, std::uint64_t cloud_points, const BuildOptions& options) {
  const Points& points = region.points.positions;
  if (region.own > static_cast<std::size_t>(points.rows()))
    throw OptionError("a region cannot own more points than it holds");
  RegionSurvey survey;
  survey.points = region.own;
  if (region.own == 0) return survey;
  const KdTree index(points);
  std::vector<Eigen::Index> kept;
  std::vector<double> nearest;           // the outlier test's nearest-neighbour distances, when it ran
  std::vector<std::uint8_t> coincident;  // and its rows with a repeat
  if (options.remove_outliers) {
    OutlierReport found = find_outliers(points, index, options.outliers);
    survey.median_spread = found.median_spread;
    for (const Eigen::Index r : found.kept)
      if (r < static_cast<Eigen::Index>(region.own)) kept.push_back(r);
    survey.outliers = region.own - kept.size();
    nearest = std::move(found.nearest);
    coincident = std::move(found.coincident);
  }
  // The region's own rows' spacing, their neighbours among the halo too: from the outlier
  // test's pass when it ran (the same samples and values), else queried.
  survey.median_spacing = nearest.empty() ? point_spacing(index, 200000, region.own).median
                                          : point_spacing(std::span<const double>(nearest).first(region.own)).median;
  // As build_cluster_tree(): a test that flags every point flags none.
  if (kept.empty()) {
    kept.resize(region.own);
    std::iota(kept.begin(), kept.end(), Eigen::Index{0});
    survey.outliers = 0;
  }
  // As build_cluster_tree(): one point per position.
  const std::vector<std::uint32_t> distinct =
      first_of_each_position(points, std::vector<std::uint32_t>(kept.begin(), kept.end()), coincident);
  const Points clustered = points(distinct, Eigen::all);
  survey.bbox = bounding_box(clustered);
  if (options.threshold_mode == ThresholdMode::Auto && options.noise_factor > 0) {
    // As build_cluster_tree(): the input normals keep facing sheets apart.
    const Points& normals = region.points.normals;
    const bool facing =
        options.use_normals && options.noise.facing_normals && normals.rows() == points.rows() && points.rows() > 0;
    const Points clustered_normals = facing ? Points(normals(distinct, Eigen::all)) : Points();
    survey.noise_sigma = estimate_noise(clustered, KdTree(clustered), options.noise,
                                        facing ? &clustered_normals : nullptr, cloud_points);
  }
  return survey;
}

CloudScale combine_surveys(std::span<const RegionSurvey> surveys) {
  CloudScale scale;
  for (const RegionSurvey& s : surveys) {
    scale.points += s.points;
    if (!s.bbox.empty()) scale.bbox.extend(s.bbox.min), scale.bbox.extend(s.bbox.max);
  }
  scale.point_spacing = weighted_median(surveys, &RegionSurvey::median_spacing);
  scale.median_spread = weighted_median(surveys, &RegionSurvey::median_spread);
  scale.noise_sigma = weighted_median(surveys, &RegionSurvey::noise_sigma);
  return scale;
}

}  // namespace clustersurf
