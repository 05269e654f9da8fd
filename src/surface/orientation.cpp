// Orientation of the proxies: by input normals, or by minimum-spanning-tree propagation.

#include <clustersurf/kd_tree.hpp>
#include <clustersurf/orientation.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

namespace clustersurf {

namespace {

/// Union-find over leaf positions, for Kruskal's algorithm.
struct DisjointSets {
  std::vector<std::size_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  bool unite(std::size_t a, std::size_t b) {
    a = find(a), b = find(b);
    if (a == b) return false;
    parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

void flip_if(ClusterNode& n, bool condition, std::size_t& flipped) {
  if (!condition) return;
  n.proxy.flip();
  ++flipped;
}

/// Internal nodes follow the point-weighted sum of their leaves' (oriented) normals.
void orient_internal_nodes(ClusterTree& tree, std::size_t& flipped) {
  std::vector<Eigen::Vector3d> sum(tree.nodes.size(), Eigen::Vector3d::Zero());
  for (std::size_t i = tree.nodes.size(); i-- > 0;) {
    ClusterNode& n = tree.nodes[i];
    if (n.is_leaf()) {
      sum[i] = n.proxy.normal() * static_cast<double>(n.point_count);
    } else {
      sum[i] = sum[static_cast<std::size_t>(n.left)] + sum[static_cast<std::size_t>(n.right)];
      flip_if(n, n.proxy.normal().dot(sum[i]) < 0, flipped);
    }
  }
}

OrientationReport orient_by_normals(ClusterTree& tree, const PointCloud& cloud) {
  OrientationReport report;
  report.used_normals = true;
  std::vector<Eigen::Vector3d> sum(tree.nodes.size(), Eigen::Vector3d::Zero());
  for (std::size_t p = 0; p < tree.point_leaf.size(); ++p)
    sum[static_cast<std::size_t>(tree.point_leaf[p])] += cloud.normals.row(static_cast<Eigen::Index>(p)).transpose();
  for (std::size_t i = tree.nodes.size(); i-- > 0;) {
    ClusterNode& n = tree.nodes[i];
    if (!n.is_leaf()) sum[i] = sum[static_cast<std::size_t>(n.left)] + sum[static_cast<std::size_t>(n.right)];
    flip_if(n, n.proxy.normal().dot(sum[i]) < 0, report.flipped);
  }
  return report;
}

OrientationReport orient_by_propagation(ClusterTree& tree) {
  OrientationReport report;
  const std::vector<std::int32_t> leaves = tree.leaves();
  const std::size_t m = leaves.size();
  std::vector<Eigen::Vector3d> normal(m);
  Points centers(static_cast<Eigen::Index>(m), 3);
  double max_radius = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const ClusterNode& n = tree.nodes[static_cast<std::size_t>(leaves[k])];
    normal[k] = n.proxy.normal();
    centers.row(static_cast<Eigen::Index>(k)) = n.support.center.transpose();
    max_radius = std::max(max_radius, n.support.radius);
  }
  // Candidate edges: leaves whose support spheres overlap.
  struct Edge {
    double weight;
    std::uint32_t a, b;
    bool operator<(const Edge& o) const { return weight < o.weight || (weight == o.weight && (a < o.a || (a == o.a && b < o.b))); }
  };
  std::vector<Edge> edges;
  const KdTree index(centers);
  for (std::size_t k = 0; k < m; ++k) {
    const ClusterNode& nk = tree.nodes[static_cast<std::size_t>(leaves[k])];
    for (const Neighbor& nb : index.radius(nk.support.center, nk.support.radius + max_radius)) {
      if (nb.index <= k) continue;
      const ClusterNode& nj = tree.nodes[static_cast<std::size_t>(leaves[nb.index])];
      const double d = std::sqrt(nb.distance_squared);
      if (d >= nk.support.radius + nj.support.radius) continue;
      const Eigen::Vector3d dir = d > 0 ? Eigen::Vector3d((nj.support.center - nk.support.center) / d) : Eigen::Vector3d::Zero();
      const double w = 1 - std::abs(normal[k].dot(normal[nb.index])) +
                       0.5 * (std::abs(dir.dot(normal[k])) + std::abs(dir.dot(normal[nb.index])));
      edges.push_back({w, static_cast<std::uint32_t>(k), nb.index});
    }
  }
  std::sort(edges.begin(), edges.end());
  DisjointSets sets(m);
  std::vector<std::vector<std::uint32_t>> adjacency(m);
  for (const Edge& e : edges)
    if (sets.unite(e.a, e.b)) adjacency[e.a].push_back(e.b), adjacency[e.b].push_back(e.a);

  // Seed each component at its leaf of largest center.x + radius·|n.x| proxy: the outward
  // normal there has a positive x component (the component's extreme point in +x).
  std::vector<std::uint8_t> seen(m, 0);
  std::vector<std::size_t> order(m);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::vector<std::size_t> seed_of_root(m, m);
  for (std::size_t k : order) {
    const std::size_t r = sets.find(k);
    const auto extreme = [&](std::size_t i) { return centers(static_cast<Eigen::Index>(i), 0); };
    if (seed_of_root[r] == m || extreme(k) > extreme(seed_of_root[r])) seed_of_root[r] = k;
  }
  for (std::size_t r = 0; r < m; ++r) {
    const std::size_t seed = seed_of_root[r];
    if (seed == m) continue;
    ++report.components;
    ClusterNode& sn = tree.nodes[static_cast<std::size_t>(leaves[seed])];
    flip_if(sn, normal[seed].x() < 0, report.flipped);
    normal[seed] = sn.proxy.normal();
    std::queue<std::size_t> queue;
    queue.push(seed);
    seen[seed] = 1;
    while (!queue.empty()) {
      const std::size_t k = queue.front();
      queue.pop();
      for (std::uint32_t j : adjacency[k]) {
        if (seen[j]) continue;
        seen[j] = 1;
        ClusterNode& nj = tree.nodes[static_cast<std::size_t>(leaves[j])];
        flip_if(nj, normal[j].dot(normal[k]) < 0, report.flipped);
        normal[j] = nj.proxy.normal();
        queue.push(j);
      }
    }
  }
  orient_internal_nodes(tree, report.flipped);
  return report;
}

}  // namespace

OrientationReport orient_tree(ClusterTree& tree, const PointCloud& cloud) {
  const bool normals = cloud.has_normals() && !tree.point_leaf.empty() &&
                       static_cast<std::uint64_t>(cloud.size()) == tree.point_leaf.size();
  return normals ? orient_by_normals(tree, cloud) : orient_by_propagation(tree);
}

}  // namespace clustersurf
