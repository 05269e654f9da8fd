// The built nodes as the tree's pre-order array, and the bounding spheres that enclose them.

#include "cluster/build_state.hpp"

#include <algorithm>

namespace clustersurf::detail {

void WorkingSet::apply(std::uint32_t begin, std::span<std::uint32_t> order) {
  const auto m = static_cast<Eigen::Index>(order.size());
  Points rows(m, 3);
  std::vector<std::uint32_t> moved(order.size());
  for (Eigen::Index k = 0; k < m; ++k) {
    const auto j = order[static_cast<std::size_t>(k)];
    rows.row(k) = positions.row(j);
    moved[static_cast<std::size_t>(k)] = ids[j];
  }
  positions.middleRows(begin, m) = rows;
  std::copy(moved.begin(), moved.end(), ids.begin() + begin);
  std::iota(order.begin(), order.end(), begin);
}

Sphere enclose(const Sphere& a, const Sphere& b) {
  const Eigen::Vector3d d = b.center - a.center;
  const double dist = d.norm();
  if (dist + b.radius <= a.radius) return a;
  if (dist + a.radius <= b.radius) return b;
  const double r = 0.5 * (dist + a.radius + b.radius);
  // Pad by a relative epsilon so rounding never leaves a child's sphere sticking out.
  return Sphere{a.center + d * ((r - a.radius) / dist), r * (1 + 1e-12)};
}

void flatten(BuildNode& root, ClusterTree& tree, std::vector<std::uint32_t>* leaf_begin) {
  struct Item {
    BuildNode* node;
    std::int32_t parent;
    bool is_left;
  };
  std::vector<Item> stack{{&root, -1, false}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    const auto index = static_cast<std::int32_t>(tree.nodes.size());
    ClusterNode n = it.node->node;
    n.parent = it.parent;
    n.left = n.right = -1;
    tree.nodes.push_back(n);
    if (leaf_begin != nullptr) leaf_begin->push_back(it.node->begin);
    if (it.parent >= 0) {
      ClusterNode& p = tree.nodes[static_cast<std::size_t>(it.parent)];
      (it.is_left ? p.left : p.right) = index;
    }
    if (it.node->left) {
      stack.push_back({it.node->right.get(), index, false});
      stack.push_back({it.node->left.get(), index, true});
    }
  }
}

}  // namespace clustersurf::detail
