#pragma once
// A cloud split into regions that build their subtrees apart: the way to clouds larger than
// memory and to many machines. A partition of unity is local, so a region needs only its own
// points and a halo of its neighbours' around them, and the union of the regions' leaves is one
// tree (docs/architecture.md, "Regions and tiles"). Meshing the regions as tiles: tiled_run.hpp.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/core/progress.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace clustersurf {

/// Options of plan_regions().
struct RegionOptions {
  /// The most points a region holds with its halo; a region is not split below a quarter of
  /// this (its halo would then outweigh it).
  std::uint64_t max_points = 4'000'000;
  /// Width of a region's halo, in median point spacings: the neighbours' points this close to
  /// the region come with it, for its outlier test, its leaves' support checks and its tile's
  /// trim. A leaf's support check sees the points within the halo: a support reaches about 30
  /// spacings on detailed surfaces; only the leaves of large flat parts reach farther.
  double halo_spacings = 64;
};

/// A k-d partition of the cloud's bounding box into regions balanced by point count. Cells are
/// half-open: a point whose coordinate along a cell's axis is below its split goes left.
struct RegionPlan {
  struct Cell {
    std::int32_t left = -1, right = -1;  ///< children, -1 for a region's cell
    std::int32_t axis = 0;               ///< split axis (inner cells)
    double split = 0;                    ///< split coordinate (inner cells)
    std::int32_t region = -1;            ///< the region of a leaf cell
    BoundingBox box;                     ///< the cell (the root: the cloud's bounding box)
  };
  std::vector<Cell> cells;                ///< pre-order; cells[0] is the root
  std::vector<std::int32_t> region_cell;  ///< the cell of each region
  double point_spacing = 0;               ///< the spacing the halo was measured in
  double halo = 0;                        ///< halo width, in the cloud's units
  std::uint64_t points = 0;               ///< the cloud's points (plan_regions()'s total_points)

  std::size_t regions() const noexcept { return region_cell.size(); }
  /// The region whose cell holds x (points outside the root box go to the nearest cell).
  std::int32_t region_of(const Eigen::Vector3d& x) const;
  /// The cell of region r.
  const BoundingBox& region_box(std::int32_t r) const {
    return cells[static_cast<std::size_t>(region_cell[static_cast<std::size_t>(r)])].box;
  }
  /// The regions other than region_of(x) whose cell lies within `halo` of x, increasing.
  void halo_regions(const Eigen::Vector3d& x, std::vector<std::int32_t>& out) const;
};

/// Splits `bbox` at the median of `sample` (rows: an even sample of the cloud's points, which
/// number `total_points`) along each cell's longest side until a cell holds at most
/// options.max_points points with its halo, by the sample's count; the halo is
/// options.halo_spacings times `point_spacing` (the cloud's median spacing, or an estimate of
/// it). Deterministic.
/// Throws OptionError for invalid options.
RegionPlan plan_regions(const Points& sample, std::uint64_t total_points, const BoundingBox& bbox, double point_spacing,
                        const RegionOptions& options = {});

/// One region's points: its own first, then the halo (its neighbours' points within the halo).
struct RegionCloud {
  PointCloud points;
  std::size_t own = 0;  ///< rows [0, own) are the region's own points
  /// Per row, 1 for a point left out: an outlier (mark_outliers()) or a repeat of an earlier
  /// row's position (mark_repeated_positions()); empty: none marked.
  std::vector<std::uint8_t> outliers;
};

/// What a region measures of its own points for the cloud's scale (combine_surveys()).
struct RegionSurvey {
  std::uint64_t points = 0;    ///< own points
  double median_spacing = 0;   ///< median distance to the nearest other point (PointSpacing::median)
  double median_spread = 0;    ///< median mean distance to the outlier test's k neighbours
  double noise_sigma = 0;      ///< estimate_noise() of its points without their outliers
  BoundingBox bbox;            ///< of its own points without their outliers
  std::uint64_t outliers = 0;  ///< own points its own outlier test flags
};

/// The survey of one region of a cloud of `cloud_points` points (its halo serves as the
/// neighbourhood of its own points). Measures what `options` use: no spreads without
/// remove_outliers, no noise unless the threshold is Auto. The noise is measured at the scale
/// the whole cloud's estimate reaches (estimate_noise()'s cloud_points), whatever the region's size.
RegionSurvey survey_region(const RegionCloud& region, std::uint64_t cloud_points, const BuildOptions& options = {});

/// The measures every region's build shares, from the surveys: each median is the median of
/// the regions' medians weighted by their points (the median itself for one region); the box
/// is the union. The spacing and the noise differ from a survey of the whole cloud only where
/// regions differ in density or noise.
struct CloudScale {
  std::uint64_t points = 0;
  double point_spacing = 0;
  double median_spread = 0;
  double noise_sigma = 0;
  BoundingBox bbox;
};
CloudScale combine_surveys(std::span<const RegionSurvey> surveys);

/// Marks the region's outliers (find_outliers() over all its rows, judged against the cloud's
/// median spread), then its repeated positions (mark_repeated_positions()): what its build
/// leaves out and its tile's trim ignores.
void mark_outliers(RegionCloud& region, const CloudScale& scale, const OutlierOptions& options = {});

/// Marks each unmarked row whose position an earlier unmarked row holds exactly
/// (first_of_each_position(); `coincident` as there): one point per position, as
/// build_cluster_tree() clusters. Marks nothing where no position repeats.
void mark_repeated_positions(RegionCloud& region, std::span<const std::uint8_t> coincident = {});

/// The subtree of one region's own points at the cloud's scale: its marked outliers left out
/// (mark_outliers(); a region whose own points are all marked keeps them), its support checks over its own and halo
/// points, and its proxies oriented (orient_tree() over the region's rows: by normals, scanners, or propagation within
/// the region; merge_region_trees() makes regions agree). The point-leaf table covers the region's own rows (with
/// BuildOptions::keep_point_leaves), and input_points counts them. An empty region gives an empty tree. Deterministic.
ClusterTree build_region_tree(const RegionCloud& region, const RegionPlan& plan, std::int32_t region_index,
                              const CloudScale& scale, const BuildOptions& options = {},
                              OrientationReport* orientation = nullptr, const ProgressCallback& progress = {});

/// One tree from the regions' subtrees (one per region, in plan order; empty for an empty
/// region): the plan's cells above them (proxies fitted to the centres of the leaves below,
/// weighted by their points), each region's subtree under its cell, empty cells left out.
/// Regions are flipped to agree with their neighbours where their leaves' supports overlap;
/// `propagated`: the regions were oriented by propagation (build_region_tree()'s report), so
/// each group of agreeing regions is then turned to face +x at its leaf reaching farthest in +x
/// (orient_tree()'s rule, which a region's piece of the surface cannot apply alone). The point-leaf table, when every
/// region kept one, is the regions' tables concatenated in region order. Throws OptionError when the trees do not match
/// the plan, were built with different options or scales, or are all empty.
ClusterTree merge_region_trees(const RegionPlan& plan, std::vector<ClusterTree> regions, bool propagated = false);

/// What a tile needs of the merged tree besides its neighbours' region trees, so that no task
/// after the merge holds the whole tree: the merged box (the lattice's anchor), its leaves, and
/// per region whether the merge flipped its proxies and how far its leaves' supports reach.
struct RegionMerge {
  BoundingBox bbox;
  double point_spacing = 0;  ///< the merged tree's (ClusterTree::point_spacing)
  std::size_t leaves = 0;
  std::vector<std::uint8_t> flipped;  ///< per region: 1 where the merge flipped every proxy
  std::vector<double> reach;          ///< per region: its leaves' largest support radius (0: empty)
  /// The automatic lattice cell of the merged tree, coarsened where clumped points would give
  /// too many cells (auto_cell_size(), set by the tiled runs, which mesh); 0: not measured.
  double auto_cell = 0;
};

/// merge_region_trees(), and how it merged (`record`).
ClusterTree merge_region_trees(const RegionPlan& plan, std::vector<ClusterTree> regions, bool propagated,
                               RegionMerge& record);

/// The tree a tile is meshed from: the given region trees (those of tile_regions(), the
/// others empty) flipped as the merge flipped them and placed under the plan's cells, with the
/// merged tree's box. Where mesh_tile() of that region evaluates f, it equals the merged
/// tree's f to the bit (the same leaves, summed in the same order), so the tile is the same.
/// Throws OptionError when the trees do not match the plan or the record.
ClusterTree tile_tree(const RegionPlan& plan, std::vector<ClusterTree> regions, const RegionMerge& merge);

}  // namespace clustersurf
