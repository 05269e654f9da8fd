// Orientation of the proxies: by input normals, by the scanners' positions, or by
// minimum-spanning-tree propagation.

#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/surface/orientation.hpp>

#include "spatial/spatial_order.hpp"

#include <tbb/parallel_for.h>

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
  // A NaN or infinite normal (the readers refuse them; a caller may not) carries no direction:
  // it is skipped rather than allowed to poison its leaf's sum.
  for (std::size_t p = 0; p < tree.point_leaf.size(); ++p) {
    const auto normal = cloud.normals.row(static_cast<Eigen::Index>(p));
    if (tree.point_leaf[p] >= 0 && normal.allFinite())
      sum[static_cast<std::size_t>(tree.point_leaf[p])] += normal.transpose();
  }
  for (std::size_t i = tree.nodes.size(); i-- > 0;) {
    ClusterNode& n = tree.nodes[i];
    if (!n.is_leaf()) sum[i] = sum[static_cast<std::size_t>(n.left)] + sum[static_cast<std::size_t>(n.right)];
    flip_if(n, n.proxy.normal().dot(sum[i]) < 0, report.flipped);
  }
  return report;
}

/// Each node follows the sum, over its points, of the unit directions towards the scanner that
/// saw them: a scanner sees the outer side of a surface.
OrientationReport orient_by_scanners(ClusterTree& tree, const PointCloud& cloud) {
  OrientationReport report;
  report.used_scanners = true;
  std::vector<Eigen::Vector3d> sum(tree.nodes.size(), Eigen::Vector3d::Zero());
  for (std::size_t p = 0; p < tree.point_leaf.size(); ++p) {
    if (tree.point_leaf[p] < 0) continue;
    const std::uint32_t scan = cloud.scanner_of_point[p];
    const Eigen::Vector3d towards =
        cloud.scanner_positions.row(scan) - cloud.positions.row(static_cast<Eigen::Index>(p));
    const double length = towards.norm();
    if (length > 0 && std::isfinite(length)) sum[static_cast<std::size_t>(tree.point_leaf[p])] += towards / length;
  }
  for (std::size_t i = tree.nodes.size(); i-- > 0;) {
    ClusterNode& n = tree.nodes[i];
    if (!n.is_leaf()) sum[i] = sum[static_cast<std::size_t>(n.left)] + sum[static_cast<std::size_t>(n.right)];
    flip_if(n, n.proxy.normal().dot(sum[i]) < 0, report.flipped);
  }
  return report;
}

/// An undirected edge between leaves i < j of the orientation graph: its MST weight and
/// whether the two proxies agree (+1) or disagree (−1) on the side they call outside.
struct Edge {
  double weight;
  std::uint32_t a, b;
  int agree;
  bool operator<(const Edge& o) const {
    return weight < o.weight || (weight == o.weight && (a < o.a || (a == o.a && b < o.b)));
  }
};

/// Edges between leaves whose clusters touch: some point of one has one of its k nearest
/// neighbours in the other. The proxies are compared where they meet (at the midpoints of such
/// point pairs), not at their centers, so strongly curved parts orient correctly.
std::vector<Edge> cluster_adjacency(const ClusterTree& tree, const KdTree& index,
                                    const std::vector<std::uint32_t>& leaf_slot) {
  constexpr std::size_t k = 8;
  constexpr double kPriorPairs = 5;
  const Points& points = index.points();
  struct Pair {
    std::uint32_t a, b;
    double dot;
  };
  const auto n = static_cast<std::size_t>(points.rows());
  std::vector<std::vector<Pair>> found(n);
  // Queried in spatial order (consecutive queries visit the same part of the k-d tree); the
  // pairs are gathered by point, so the order of the queries does not change them.
  const std::vector<std::uint32_t> order = detail::spatial_order(points);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& r) {
    std::vector<Neighbor> nb;
    for (std::size_t o = r.begin(); o != r.end(); ++o) {
      const std::size_t p = order[o];
      const Eigen::Vector3d x = points.row(static_cast<Eigen::Index>(p)).transpose();
      index.knn(x, k + 1, nb);
      const std::int32_t lp = tree.point_leaf[p];
      if (lp < 0) continue;  // an outlier
      for (const Neighbor& q : nb) {
        const std::int32_t lq = tree.point_leaf[q.index];
        if (lq <= lp) continue;  // each unordered leaf pair once per point pair direction; outliers (-1)
        const Eigen::Vector3d mid = 0.5 * (x + points.row(q.index).transpose());
        const Eigen::Vector3d ga = tree.nodes[static_cast<std::size_t>(lp)].proxy.gradient(mid);
        const Eigen::Vector3d gb = tree.nodes[static_cast<std::size_t>(lq)].proxy.gradient(mid);
        const double na = ga.norm(), nb_ = gb.norm();
        if (!(na > 0) || !(nb_ > 0)) continue;
        found[p].push_back({leaf_slot[static_cast<std::size_t>(lp)], leaf_slot[static_cast<std::size_t>(lq)],
                            ga.dot(gb) / (na * nb_)});
      }
    }
  });
  // Aggregate per leaf pair in a fixed order (independent of the thread count).
  std::vector<Pair> all;
  for (auto& f : found) all.insert(all.end(), f.begin(), f.end());
  std::sort(all.begin(), all.end(),
            [](const Pair& x, const Pair& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); });
  std::vector<Edge> edges;
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i;
    double sum = 0;
    while (j < all.size() && all[j].a == all[i].a && all[j].b == all[i].b) sum += all[j++].dot;
    // 1 − |mean dot|, with the evidence shrunk towards 0 when few point pairs support it: a
    // single pair across a thin part must not outweigh a well-attested boundary.
    const double shrunk = sum / (static_cast<double>(j - i) + kPriorPairs);
    edges.push_back(
        {1 - std::abs(shrunk), std::min(all[i].a, all[i].b), std::max(all[i].a, all[i].b), sum >= 0 ? 1 : -1});
    i = j;
  }
  return edges;
}

/// Edges between leaves whose support spheres overlap (when the tree has no point-leaf table),
/// comparing the proxies' normals at their centers, with a penalty for neighbours stacked along
/// their normals (opposite sides of a thin part).
std::vector<Edge> support_overlap(const ClusterTree& tree, const std::vector<std::int32_t>& leaves) {
  const std::size_t m = leaves.size();
  Points centers(static_cast<Eigen::Index>(m), 3);
  std::vector<Eigen::Vector3d> normal(m);
  double max_radius = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const ClusterNode& n = tree.nodes[static_cast<std::size_t>(leaves[k])];
    normal[k] = n.proxy.normal();
    centers.row(static_cast<Eigen::Index>(k)) = n.support.center.transpose();
    max_radius = std::max(max_radius, n.support.radius);
  }
  std::vector<Edge> edges;
  const KdTree index(centers);
  for (std::size_t k = 0; k < m; ++k) {
    const ClusterNode& nk = tree.nodes[static_cast<std::size_t>(leaves[k])];
    for (const Neighbor& nb : index.radius(nk.support.center, nk.support.radius + max_radius)) {
      if (nb.index <= k) continue;
      const ClusterNode& nj = tree.nodes[static_cast<std::size_t>(leaves[nb.index])];
      const double d = std::sqrt(nb.distance_squared);
      if (d >= nk.support.radius + nj.support.radius) continue;
      const Eigen::Vector3d dir =
          d > 0 ? Eigen::Vector3d((nj.support.center - nk.support.center) / d) : Eigen::Vector3d::Zero();
      const double dot = normal[k].dot(normal[nb.index]);
      const double w = 1 - std::abs(dot) + 0.5 * (std::abs(dir.dot(normal[k])) + std::abs(dir.dot(normal[nb.index])));
      edges.push_back({w, static_cast<std::uint32_t>(k), nb.index, dot >= 0 ? 1 : -1});
    }
  }
  return edges;
}

OrientationReport orient_by_propagation(ClusterTree& tree, const CloudIndex& cloud) {
  OrientationReport report;
  const std::vector<std::int32_t> leaves = tree.leaves();
  const std::size_t m = leaves.size();
  std::vector<std::uint32_t> leaf_slot(tree.nodes.size(), 0);
  for (std::size_t k = 0; k < m; ++k) leaf_slot[static_cast<std::size_t>(leaves[k])] = static_cast<std::uint32_t>(k);
  const bool have_points =
      !tree.point_leaf.empty() && static_cast<std::uint64_t>(cloud.cloud().size()) == tree.point_leaf.size();
  std::vector<Edge> edges =
      have_points ? cluster_adjacency(tree, cloud.points(), leaf_slot) : support_overlap(tree, leaves);

  // Minimum spanning forest (Kruskal).
  std::sort(edges.begin(), edges.end());
  DisjointSets sets(m);
  std::vector<std::vector<std::pair<std::uint32_t, int>>> adjacency(m);
  for (const Edge& e : edges)
    if (sets.unite(e.a, e.b)) adjacency[e.a].push_back({e.b, e.agree}), adjacency[e.b].push_back({e.a, e.agree});

  // Seed of each component: the leaf reaching farthest in +x (largest center.x + radius); the
  // outward normal there points to +x, so its proxy is made to agree with +x.
  std::vector<std::size_t> seed_of_root(m, m);
  auto reach = [&](std::size_t k) {
    const ClusterNode& n = tree.nodes[static_cast<std::size_t>(leaves[k])];
    return n.support.center.x() + 0.5 * n.extent;
  };
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t r = sets.find(k);
    if (seed_of_root[r] == m || reach(k) > reach(seed_of_root[r])) seed_of_root[r] = k;
  }
  // Breadth-first propagation of a ±1 sign per leaf, then the flips.
  std::vector<int> sign(m, 0);
  for (std::size_t r = 0; r < m; ++r) {
    const std::size_t seed = seed_of_root[r];
    if (seed == m) continue;
    ++report.components;
    sign[seed] = tree.nodes[static_cast<std::size_t>(leaves[seed])].proxy.normal().x() < 0 ? -1 : 1;
    std::queue<std::size_t> queue;
    queue.push(seed);
    while (!queue.empty()) {
      const std::size_t k = queue.front();
      queue.pop();
      for (const auto& [j, agree] : adjacency[k]) {
        if (sign[j] != 0) continue;
        sign[j] = sign[k] * agree;
        queue.push(j);
      }
    }
  }
  // Clean-up: a leaf whose neighbours, weighed by evidence over all graph edges (not only the
  // spanning tree), vote for the other sign takes it; rounds in a fixed order until stable.
  std::vector<std::vector<std::pair<std::uint32_t, double>>> votes(m);
  for (const Edge& e : edges) {
    const double strength = std::max(0.0, 1 - e.weight) * e.agree;
    votes[e.a].push_back({e.b, strength});
    votes[e.b].push_back({e.a, strength});
  }
  for (int round = 0; round < 20; ++round) {
    bool changed = false;
    for (std::size_t k = 0; k < m; ++k) {
      double v = 0;
      for (const auto& [j, strength] : votes[k]) v += strength * sign[j];
      if (v * sign[k] < 0) sign[k] = -sign[k], changed = true;
    }
    if (!changed) break;
  }
  for (std::size_t k = 0; k < m; ++k)
    flip_if(tree.nodes[static_cast<std::size_t>(leaves[k])], sign[k] < 0, report.flipped);
  orient_internal_nodes(tree, report.flipped);
  return report;
}

}  // namespace

OrientationReport orient_tree(ClusterTree& tree, const PointCloud& cloud) {
  return orient_tree(tree, CloudIndex(cloud));
}

OrientationReport orient_tree(ClusterTree& tree, const CloudIndex& index, bool use_normals) {
  const PointCloud& cloud = index.cloud();
  const bool per_point = !tree.point_leaf.empty() && static_cast<std::uint64_t>(cloud.size()) == tree.point_leaf.size();
  if (use_normals && per_point && cloud.has_normals()) return orient_by_normals(tree, cloud);
  const bool scanners = per_point && cloud.scanner_of_point.size() == tree.point_leaf.size() &&
                        std::all_of(cloud.scanner_of_point.begin(), cloud.scanner_of_point.end(),
                                    [&](std::uint32_t s) { return s < cloud.scanner_positions.rows(); });
  return scanners ? orient_by_scanners(tree, cloud) : orient_by_propagation(tree, index);
}

}  // namespace clustersurf
