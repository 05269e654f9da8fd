// The input points a tree clusters (its input without the outliers).

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/errors.hpp>

#include <numeric>
#include <string>

namespace clustersurf {

void require_tree_input(const ClusterTree& tree, const Points& input, std::string_view what) {
  if (static_cast<std::uint64_t>(input.rows()) != tree.input_points)
    throw OptionError(std::string(what) + " (" + std::to_string(input.rows()) + ") are not the tree's input (" +
                      std::to_string(tree.input_points) + " points): pass the cloud the tree was built from");
}

std::vector<std::uint32_t> clustered_rows(const ClusterTree& tree) {
  std::vector<std::uint32_t> rows;
  if (tree.outliers() == 0 || tree.point_leaf.empty()) {
    rows.resize(static_cast<std::size_t>(tree.input_points));
    std::iota(rows.begin(), rows.end(), 0u);
    return rows;
  }
  rows.reserve(tree.point_leaf.size());
  for (std::size_t i = 0; i < tree.point_leaf.size(); ++i)
    if (tree.point_leaf[i] >= 0) rows.push_back(static_cast<std::uint32_t>(i));
  return rows;
}

Points clustered_points(const ClusterTree& tree, const Points& input) {
  require_tree_input(tree, input);
  if (tree.outliers() == 0 || tree.point_leaf.empty()) return input;
  return input(clustered_rows(tree), Eigen::all);
}

CloudIndex::Subset clustered_subset(const CloudIndex& cloud, const ClusterTree& tree) {
  require_tree_input(tree, cloud.cloud().positions);
  return cloud.rows(clustered_rows(tree));
}

}  // namespace clustersurf
