// A region's subtree, built at the whole cloud's scale.

#include <clustersurf/cluster/noise_field.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/regions/regions.hpp>
#include <clustersurf/spatial/cloud_index.hpp>
#include <clustersurf/spatial/outliers.hpp>
#include <clustersurf/spatial/repeated_positions.hpp>
#include <clustersurf/surface/orientation.hpp>

#include "cluster/build_state.hpp"

#include <numeric>

namespace clustersurf {

void mark_outliers(RegionCloud& region, const CloudScale& scale, const OutlierOptions& options) {
  const Points& points = region.points.positions;
  region.outliers.assign(static_cast<std::size_t>(points.rows()), 0);
  const OutlierReport found = find_outliers(points, KdTree(points), options, scale.median_spread);
  for (const Eigen::Index r : found.outliers) region.outliers[static_cast<std::size_t>(r)] = 1;
  mark_repeated_positions(region, found.coincident);
}

void mark_repeated_positions(RegionCloud& region, std::span<const std::uint8_t> coincident) {
  const auto n = static_cast<std::size_t>(region.points.size());
  if (!region.outliers.empty() && region.outliers.size() != n)
    throw OptionError("the region's outlier marks do not match its points");
  std::vector<std::uint32_t> rows;  // the unmarked rows
  for (std::size_t r = 0; r < n; ++r)
    if (region.outliers.empty() || !region.outliers[r]) rows.push_back(static_cast<std::uint32_t>(r));
  const std::vector<std::uint32_t> kept = first_of_each_position(region.points.positions, rows, coincident);
  if (kept.size() == rows.size()) return;
  region.outliers.resize(n, 0);
  std::size_t k = 0;  // kept is a subsequence of rows
  for (const std::uint32_t r : rows) {
    if (k < kept.size() && kept[k] == r)
      ++k;
    else
      region.outliers[r] = 1;
  }
}

ClusterTree build_region_tree(const RegionCloud& region, const RegionPlan& plan, std::int32_t region_index,
                              const CloudScale& scale, const BuildOptions& options, OrientationReport* orientation,
                              const ProgressCallback& progress) {
  const PointCloud& cloud = region.points;
  if (region_index < 0 || static_cast<std::size_t>(region_index) >= plan.regions())
    throw OptionError("region " + std::to_string(region_index) + " is not in the plan");
  if (region.own > static_cast<std::size_t>(cloud.size()))
    throw OptionError("a region cannot own more points than it holds");
  ClusterTree tree;
  if (region.own == 0) return tree;  // nothing of the cloud lies in this region
  const CloudIndex index(cloud);
  // The halo's outliers must not enter the support checks either. A test that flags every own
  // point flags none.
  if (!region.outliers.empty() && region.outliers.size() != static_cast<std::size_t>(cloud.size()))
    throw OptionError("the region's outlier marks do not match its points");
  std::vector<std::uint32_t> kept;  // kept rows, own first
  bool own_kept = false;
  for (std::size_t r = 0; r < region.outliers.size(); ++r)
    if (!region.outliers[r]) kept.push_back(static_cast<std::uint32_t>(r)), own_kept = own_kept || r < region.own;
  if (!own_kept) kept.clear();
  if (kept.empty()) {
    kept.resize(static_cast<std::size_t>(cloud.size()));
    std::iota(kept.begin(), kept.end(), 0u);
  }
  const CloudIndex::Subset support = index.rows(kept);
  std::vector<std::uint32_t> ids;  // the own rows clustered
  for (const std::uint32_t r : kept)
    if (r < region.own) ids.push_back(r);
  const Points clustered = cloud.positions(std::vector<Eigen::Index>(ids.begin(), ids.end()), Eigen::all);
  detail::BuildScale build_scale;
  build_scale.bbox = scale.bbox;
  build_scale.point_spacing = scale.point_spacing;
  build_scale.noise_sigma = scale.noise_sigma;
  // The noise over the region, from its points and its halo's, as the whole cloud's would read
  // it there (sampled as coarsely, scaled by the region's own estimate).
  NoiseEstimate local;
  if (options.threshold_mode == ThresholdMode::Auto && options.noise_factor > 0 && options.noise.local &&
      scale.noise_sigma > 0) {
    const bool facing = options.use_normals && options.noise.facing_normals &&
                        cloud.normals.rows() == cloud.positions.rows() && cloud.size() > 0;
    const Points facing_normals = facing ? Points(cloud.normals(kept, Eigen::all)) : Points();
    local = estimate_noise_field(support.positions, support.index, options.noise, facing ? &facing_normals : nullptr,
                                 scale.points);
    build_scale.noise_field = &local.field;
  }
  BuildOptions build = options;
  build.keep_point_leaves = true;  // the orientation follows the points' normals through it
  // The support points' normals, for the support fits that follow them.
  const bool normals = options.use_normals && options.fit_normals && cloud.normals.rows() == cloud.positions.rows();
  const bool subset = kept.size() != static_cast<std::size_t>(cloud.size());
  const Points subset_normals = normals && subset ? Points(cloud.normals(kept, Eigen::all)) : Points();
  const Points* support_normals = !normals ? nullptr : subset ? &subset_normals : &cloud.normals;
  tree = detail::build_tree(cloud, std::move(ids), clustered, support.positions, support_normals, support.index,
                            build_scale, build, progress);
  const OrientationReport oriented = orient_tree(tree, index, options.use_normals);
  if (orientation != nullptr) *orientation = oriented;
  // The tree of the region's own points: the halo belongs to the neighbours' trees.
  tree.input_points = region.own;
  if (options.keep_point_leaves)
    tree.point_leaf.resize(region.own);
  else
    tree.point_leaf.clear();
  return tree;
}

}  // namespace clustersurf
