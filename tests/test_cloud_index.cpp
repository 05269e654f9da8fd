// CloudIndex: one k-d tree, one spacing and one clustered subset per cloud, the same answers
// as computing each alone, and a tree built through it is the tree built from the cloud.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/cloud_index.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>
#include <clustersurf/spatial/outliers.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// A torus with 1 % of its points moved far off (the builder leaves them out as outliers).
PointCloud torus_with_strays() {
  PointCloud c = test::sample_torus(6000);
  for (Eigen::Index i = 0; i < c.positions.rows(); i += 100) c.positions.row(i) *= 3.0;
  return c;
}

}  // namespace

TEST(CloudIndex, SpacingIsComputeStatsMedian) {
  const PointCloud c = test::sample_torus(4000);
  const CloudIndex index(c);
  EXPECT_EQ(index.median_spacing(), compute_stats(c).median_spacing);
  EXPECT_EQ(&index.points(), &index.points());        // built once
  EXPECT_EQ(&index.points().points(), &c.positions);  // adapts the cloud, no copy
}

TEST(CloudIndex, SpacingFromTheOutlierPassIsTheQueriedOne) {
  // Duplicates (spacing 0) and strays included; the outlier test runs first and the spacing is
  // taken from its neighbour pass instead of queried.
  PointCloud c = torus_with_strays();
  for (Eigen::Index i = 1; i < c.positions.rows(); i += 37) c.positions.row(i) = c.positions.row(i - 1);
  const CloudIndex index(c);
  const OutlierReport report = index.outliers(OutlierOptions{});
  ASSERT_EQ(report.nearest.size(), static_cast<std::size_t>(c.size()));
  EXPECT_EQ(index.median_spacing(), compute_stats(c).median_spacing);
  // And with a stride: the same samples as the k-d tree's queries.
  for (const std::size_t samples : {std::size_t{500}, std::size_t{1001}}) {
    const PointSpacing queried = point_spacing(index.points(), samples);
    const PointSpacing measured = point_spacing(report.nearest, samples);
    EXPECT_EQ(queried.median, measured.median);
    EXPECT_EQ(queried.mean, measured.mean);
  }
  // A region's own first rows, their neighbours among all the points (its halo after them).
  for (const std::size_t rows : {std::size_t{1}, std::size_t{777}}) {
    const PointSpacing queried = point_spacing(index.points(), 500, rows);
    const PointSpacing measured = point_spacing(std::span<const double>(report.nearest).first(rows), 500);
    EXPECT_EQ(queried.median, measured.median);
    EXPECT_EQ(queried.mean, measured.mean);
  }
}

TEST(CloudIndex, TreeThroughTheIndexIsTheTreeFromTheCloud) {
  const PointCloud c = torus_with_strays();
  const CloudIndex index(c);
  const ClusterTree a = build_cluster_tree(index);
  const ClusterTree b = build_cluster_tree(c);
  ASSERT_GT(a.outliers(), 0u);
  EXPECT_EQ(serialize_tree(a), serialize_tree(b));
  EXPECT_EQ(a.point_spacing, index.median_spacing());
}

TEST(CloudIndex, ClusteredRowsAreTheTreesRows) {
  const PointCloud c = torus_with_strays();
  const CloudIndex index(c);
  const ClusterTree tree = build_cluster_tree(index);
  const CloudIndex::Subset rows = clustered_subset(index, tree);
  EXPECT_EQ(rows.positions, clustered_points(tree, c.positions));
  EXPECT_EQ(rows.index.size(), static_cast<std::size_t>(c.size()) - tree.outliers());
  // The builder's subset is the one kept: asking again builds nothing new.
  EXPECT_EQ(&clustered_subset(index, tree).index, &rows.index);
}

TEST(CloudIndex, AnotherCloudIsRefused) {
  const PointCloud c = test::sample_torus(3000);
  const ClusterTree tree = build_cluster_tree(c);
  const PointCloud other = test::sample_sphere(500);
  const CloudIndex index(other);
  try {
    clustered_subset(index, tree);
    ADD_FAILURE() << "accepted";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("are not the tree's input"), std::string::npos) << e.what();
  }
}

TEST(CloudIndex, KeptSpreadsAreThoseOfTheKeptPointsAlone) {
  // Strays and duplicates: points beside a stray have it among their nearest in the whole
  // cloud, and other neighbours among the kept points.
  PointCloud c = torus_with_strays();
  for (Eigen::Index i = 1; i < c.positions.rows(); i += 37) c.positions.row(i) = c.positions.row(i - 1);
  for (Eigen::Index i = 50; i < c.positions.rows(); i += 100)  // a stray just off the surface
    c.positions.row(i) += 0.25 * c.positions.row(i).normalized();
  const CloudIndex index(c);
  const OutlierReport report = index.outliers(OutlierOptions{});
  ASSERT_GE(report.outliers.size(), 100u);
  ASSERT_EQ(report.kept_spread.size(), report.kept.size());
  const Points kept = c.positions(report.kept, Eigen::all);
  const KdTree alone(kept);
  std::vector<Neighbor> nb;
  std::size_t beside_a_stray = 0;
  for (std::size_t j = 0; j < report.kept.size(); ++j) {
    alone.neighbors_of(static_cast<Eigen::Index>(j), OutlierOptions{}.neighbors, nb);
    double sum = 0;
    for (const Neighbor& q : nb) sum += std::sqrt(q.distance_squared);
    ASSERT_EQ(report.kept_spread[j], sum / static_cast<double>(nb.size())) << "kept point " << j;
    index.points().neighbors_of(report.kept[j], OutlierOptions{}.neighbors, nb);
    double all = 0;
    for (const Neighbor& q : nb) all += std::sqrt(q.distance_squared);
    beside_a_stray += all != sum;
  }
  EXPECT_GT(beside_a_stray, 0u);  // the case where the whole cloud's spread is not the answer
  // A tree built through the index leaves the repeated positions out too: its clustered
  // subset is not the kept rows, whose spreads count the repeats, so it carries none.
  const ClusterTree repeats_out = build_cluster_tree(index);
  EXPECT_TRUE(clustered_subset(index, repeats_out).spread.empty());
  // Without repeats, the clustered subset of a tree built through the index carries them.
  PointCloud strays = torus_with_strays();
  for (Eigen::Index i = 50; i < strays.positions.rows(); i += 100)
    strays.positions.row(i) += 0.25 * strays.positions.row(i).normalized();
  const CloudIndex strays_index(strays);
  const OutlierReport strays_report = strays_index.outliers(OutlierOptions{});
  const ClusterTree tree = build_cluster_tree(strays_index);
  const CloudIndex::Subset rows = clustered_subset(strays_index, tree);
  ASSERT_EQ(rows.spread.size(), rows.index.size());
  EXPECT_EQ(rows.spread_neighbors, OutlierOptions{}.neighbors);
  EXPECT_TRUE(std::equal(rows.spread.begin(), rows.spread.end(), strays_report.kept_spread.begin()));
  // Another subset has none.
  std::vector<std::uint32_t> some(100);
  std::iota(some.begin(), some.end(), 0u);
  EXPECT_TRUE(index.rows(some).spread.empty());
}
