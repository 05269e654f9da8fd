// CloudIndex: one k-d tree, one spacing and one clustered subset per cloud, the same answers
// as computing each alone, and a tree built through it is the tree built from the cloud.

#include <clustersurf/cloud_index.hpp>
#include <clustersurf/cloud_stats.hpp>
#include <clustersurf/cluster_tree.hpp>
#include <clustersurf/errors.hpp>
#include <clustersurf/tree_file.hpp>

#include <gtest/gtest.h>

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
  EXPECT_EQ(&index.points(), &index.points());  // built once
  EXPECT_EQ(&index.points().points(), &c.positions);  // adapts the cloud, no copy
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
  const CloudIndex::Subset rows = index.clustered(tree);
  EXPECT_EQ(rows.positions, clustered_points(tree, c.positions));
  EXPECT_EQ(rows.index.size(), static_cast<std::size_t>(c.size()) - tree.outliers());
  // The builder's subset is the one kept: asking again builds nothing new.
  EXPECT_EQ(&index.clustered(tree).index, &rows.index);
}

TEST(CloudIndex, AnotherCloudIsRefused) {
  const PointCloud c = test::sample_torus(3000);
  const ClusterTree tree = build_cluster_tree(c);
  const PointCloud other = test::sample_sphere(500);
  const CloudIndex index(other);
  try {
    index.clustered(tree);
    ADD_FAILURE() << "accepted";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("are not the tree's input"), std::string::npos) << e.what();
  }
}
