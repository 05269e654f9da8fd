// The input points a tree clusters (its input without the outliers).

#include <clustersurf/cluster_tree.hpp>

namespace clustersurf {

Points clustered_points(const ClusterTree& tree, const Points& input) {
  if (tree.outliers() == 0 || tree.point_leaf.size() != static_cast<std::size_t>(input.rows())) return input;
  std::vector<Eigen::Index> rows;
  rows.reserve(tree.point_leaf.size());
  for (std::size_t i = 0; i < tree.point_leaf.size(); ++i)
    if (tree.point_leaf[i] >= 0) rows.push_back(static_cast<Eigen::Index>(i));
  return input(rows, Eigen::all);
}

}  // namespace clustersurf
