// The regions' subtrees as one tree under the plan's cells.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/regions/regions.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include "cluster/build_state.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace clustersurf {

namespace {

/// The region trees' nodes appended under the plan's cells, in pre-order.
struct Merger {
  const RegionPlan& plan;
  std::vector<ClusterTree>& regions;
  const TreeParameters& parameters;
  ClusterTree& out;
  std::vector<std::int32_t> region_root;  // each region's root in `out` (-1: empty)
  std::vector<std::uint64_t> cell_points;
  std::vector<BoundingBox> cell_box;  // of the clustered points below each cell

  void measure(std::size_t c) {
    const RegionPlan::Cell& cell = plan.cells[c];
    if (cell.left < 0) {
      const ClusterTree& t = regions[static_cast<std::size_t>(cell.region)];
      cell_points[c] = t.nodes.empty() ? 0 : t.nodes[0].point_count;
      cell_box[c] = t.bbox;
      return;
    }
    const auto l = static_cast<std::size_t>(cell.left), r = static_cast<std::size_t>(cell.right);
    measure(l);
    measure(r);
    cell_points[c] = cell_points[l] + cell_points[r];
    cell_box[c] = cell_box[l];
    if (!cell_box[r].empty()) cell_box[c].extend(cell_box[r].min), cell_box[c].extend(cell_box[r].max);
  }

  /// Appends the nodes of cell c at `depth` under `parent`; returns its node (-1: empty).
  std::int32_t emit(std::size_t c, std::int32_t parent, std::uint32_t depth) {
    if (cell_points[c] == 0) return -1;
    const RegionPlan::Cell& cell = plan.cells[c];
    if (cell.left < 0) return append_region(static_cast<std::size_t>(cell.region), parent, depth);
    const auto l = static_cast<std::size_t>(cell.left), r = static_cast<std::size_t>(cell.right);
    if (cell_points[l] == 0) return emit(r, parent, depth);
    if (cell_points[r] == 0) return emit(l, parent, depth);
    const auto self = static_cast<std::int32_t>(out.nodes.size());
    out.nodes.emplace_back();
    const std::int32_t left = emit(l, self, depth + 1);
    const std::int32_t right = emit(r, self, depth + 1);
    ClusterNode& node = out.nodes[static_cast<std::size_t>(self)];
    node.parent = parent;
    node.left = left;
    node.right = right;
    node.depth = depth;
    node.point_count = static_cast<std::uint32_t>(cell_points[c]);
    node.extent = cell_box[c].diagonal();
    fit_inner(self);
    return self;
  }

  std::int32_t append_region(std::size_t r, std::int32_t parent, std::uint32_t depth) {
    ClusterTree& t = regions[r];
    const auto offset = static_cast<std::int32_t>(out.nodes.size());
    for (ClusterNode n : t.nodes) {
      n.parent = n.parent < 0 ? parent : n.parent + offset;
      if (!n.is_leaf()) n.left += offset, n.right += offset;
      n.depth += depth;
      out.nodes.push_back(std::move(n));
    }
    region_root[r] = offset;
    t.nodes = {};
    return offset;
  }

  /// An inner cell's node: a quadratic over the centres of the leaves below it, each weighted
  /// by its points, facing as their normals do on the whole; its support as the builder's.
  void fit_inner(std::int32_t self) {
    ClusterNode& node = out.nodes[static_cast<std::size_t>(self)];
    Points centers(0, 3);
    std::vector<double> weight;
    Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> rows;
    for (auto i = static_cast<std::size_t>(self) + 1; i < out.nodes.size(); ++i) {
      const ClusterNode& n = out.nodes[i];
      if (!n.is_leaf()) continue;
      rows.push_back(n.support.center);
      weight.push_back(n.point_count);
      normal_sum += n.proxy.normal() * static_cast<double>(n.point_count);
    }
    centers.resize(static_cast<Eigen::Index>(rows.size()), 3);
    for (std::size_t i = 0; i < rows.size(); ++i) centers.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
    std::vector<std::uint32_t> ids(rows.size());
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<std::uint32_t>(i);
    const Frame frame = pca_frame(centers, ids);
    node.proxy = parameters.proxy == ProxyKind::Poly ? Proxy(fit_poly_in_frame(frame, centers, ids, weight))
                                                     : fit_proxy(parameters.proxy, centers, ids);
    if (node.proxy.normal().dot(normal_sum) < 0) node.proxy.flip();
    const ProxyError err = proxy_error(node.proxy, centers, ids);
    node.rms_error = err.rms;
    node.max_error = err.max;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    double total = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) mean += weight[i] * rows[i], total += weight[i];
    node.support = Sphere{mean / total, parameters.alpha * node.extent};
    node.bound = detail::enclose(detail::enclose(node.support, out.nodes[static_cast<std::size_t>(node.left)].bound),
                                 out.nodes[static_cast<std::size_t>(node.right)].bound);
  }
};

/// The region of each node: the subtrees under `region_root` (-1 elsewhere).
std::vector<std::int32_t> node_regions(const ClusterTree& tree, const std::vector<std::int32_t>& region_root) {
  std::vector<std::int32_t> region_of(tree.nodes.size(), -1);
  for (std::size_t r = 0; r < region_root.size(); ++r) {
    if (region_root[r] < 0) continue;
    // A subtree's nodes are contiguous from its root: up to the next node at its depth or above.
    const auto root = static_cast<std::size_t>(region_root[r]);
    region_of[root] = static_cast<std::int32_t>(r);
    for (std::size_t i = root + 1; i < tree.nodes.size() && tree.nodes[i].depth > tree.nodes[root].depth; ++i)
      region_of[i] = static_cast<std::int32_t>(r);
  }
  return region_of;
}

/// For each pair of regions (lower first) whose leaves' supports overlap: the sum over the
/// overlapping pairs of the cosine between their proxies' gradients midway between them.
std::map<std::pair<std::int32_t, std::int32_t>, double> region_agreement(const ClusterTree& tree,
                                                                         const std::vector<std::int32_t>& leaves,
                                                                         const std::vector<std::int32_t>& region_of) {
  Points centers(static_cast<Eigen::Index>(leaves.size()), 3);
  double largest = 0;
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    const ClusterNode& n = tree.nodes[static_cast<std::size_t>(leaves[i])];
    centers.row(static_cast<Eigen::Index>(i)) = n.support.center.transpose();
    largest = std::max(largest, n.support.radius);
  }
  const KdTree index(centers);
  std::map<std::pair<std::int32_t, std::int32_t>, double> agreement;
  std::vector<Neighbor> near;
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    const ClusterNode& a = tree.nodes[static_cast<std::size_t>(leaves[i])];
    const std::int32_t ra = region_of[static_cast<std::size_t>(leaves[i])];
    index.radius_unsorted(a.support.center, a.support.radius + largest, near);
    for (const Neighbor& nb : near) {
      const ClusterNode& b = tree.nodes[static_cast<std::size_t>(leaves[nb.index])];
      const std::int32_t rb = region_of[static_cast<std::size_t>(leaves[nb.index])];
      if (rb <= ra || std::sqrt(nb.distance_squared) >= a.support.radius + b.support.radius) continue;
      const Eigen::Vector3d mid = 0.5 * (a.support.center + b.support.center);
      const Eigen::Vector3d ga = a.proxy.gradient(mid), gb = b.proxy.gradient(mid);
      const double norm = ga.norm() * gb.norm();
      if (norm > 0) agreement[{ra, rb}] += ga.dot(gb) / norm;
    }
  }
  return agreement;
}

/// The maximum spanning forest of `n` regions by |agreement| (Kruskal): each region's forest
/// neighbours, and whether the neighbour faces the other way.
std::vector<std::vector<std::pair<std::size_t, bool>>> agreement_forest(
    const std::map<std::pair<std::int32_t, std::int32_t>, double>& agreement, std::size_t n) {
  std::vector<std::pair<double, std::pair<std::int32_t, std::int32_t>>> edges;
  for (const auto& [pair, sum] : agreement) edges.push_back({std::abs(sum), pair});
  std::stable_sort(edges.begin(), edges.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  std::vector<std::size_t> group(n);
  for (std::size_t r = 0; r < n; ++r) group[r] = r;
  const auto find = [&](std::size_t r) {
    while (group[r] != r) r = group[r] = group[group[r]];
    return r;
  };
  std::vector<std::vector<std::pair<std::size_t, bool>>> adjacent(n);
  for (const auto& [weight, pair] : edges) {
    const auto a = static_cast<std::size_t>(pair.first), b = static_cast<std::size_t>(pair.second);
    const std::size_t ga = find(a), gb = find(b);
    if (ga == gb) continue;
    group[std::max(ga, gb)] = std::min(ga, gb);
    const bool opposite = agreement.at(pair) < 0;
    adjacent[a].push_back({b, opposite});
    adjacent[b].push_back({a, opposite});
  }
  return adjacent;
}

/// Flips whole regions so that regions agree where their leaves' supports overlap: the
/// proxies' gradients are compared midway between overlapping leaves of two regions, and a
/// maximum spanning tree over the regions (weighted by how much they overlap) carries the
/// orientation of the largest region of each group to the others. Returns the flipped regions.
std::vector<std::uint8_t> align_regions(ClusterTree& tree, const std::vector<std::int32_t>& region_root,
                                        bool propagated) {
  const std::vector<std::int32_t> region_of = node_regions(tree, region_root);
  const std::vector<std::int32_t> leaves = tree.leaves();
  if (leaves.empty()) return std::vector<std::uint8_t>(region_root.size(), 0);
  const std::size_t n = region_root.size();
  // Each group's orientation follows its first region along the forest's edges.
  const auto adjacent = agreement_forest(region_agreement(tree, leaves, region_of), n);
  // Orientation by propagation is certain only at the leaf reaching farthest in +x of the
  // whole group (orient_tree()'s seed), which may lie in any of its regions.
  const auto reach = [&](std::int32_t l) {
    const ClusterNode& node = tree.nodes[static_cast<std::size_t>(l)];
    return node.support.center.x() + 0.5 * node.extent;
  };
  std::vector<std::int32_t> extreme(n, -1);  // the +x-most leaf of each region
  for (const std::int32_t leaf : leaves) {
    const std::int32_t r = region_of[static_cast<std::size_t>(leaf)];
    if (r >= 0 &&
        (extreme[static_cast<std::size_t>(r)] < 0 || reach(leaf) > reach(extreme[static_cast<std::size_t>(r)])))
      extreme[static_cast<std::size_t>(r)] = leaf;
  }
  std::vector<int> flip(n, -1);
  for (std::size_t start = 0; start < n; ++start) {
    if (flip[start] >= 0) continue;
    flip[start] = 0;
    std::vector<std::size_t> stack{start}, members;
    while (!stack.empty()) {
      const std::size_t r = stack.back();
      stack.pop_back();
      members.push_back(r);
      for (const auto& [other, opposite] : adjacent[r])
        if (flip[other] < 0) flip[other] = flip[r] ^ static_cast<int>(opposite), stack.push_back(other);
    }
    if (!propagated) continue;
    std::int32_t seed = -1;
    for (const std::size_t r : members) {
      const std::int32_t e = extreme[r];
      if (e < 0) continue;
      if (seed < 0 || reach(e) > reach(seed)) seed = e;
    }
    if (seed < 0) continue;
    const bool seed_flipped = flip[static_cast<std::size_t>(region_of[static_cast<std::size_t>(seed)])] == 1;
    const double x = tree.nodes[static_cast<std::size_t>(seed)].proxy.normal().x() * (seed_flipped ? -1 : 1);
    if (x < 0)
      for (const std::size_t r : members) flip[r] ^= 1;
  }
  for (std::size_t i = 0; i < tree.nodes.size(); ++i)
    if (region_of[i] >= 0 && flip[static_cast<std::size_t>(region_of[i])] == 1) tree.nodes[i].proxy.flip();
  std::vector<std::uint8_t> flipped(n);
  for (std::size_t r = 0; r < n; ++r) flipped[r] = flip[r] == 1;
  return flipped;
}

/// The region trees under the plan's cells (no flips): the merged tree and each region's root.
struct Assembly {
  ClusterTree tree;
  std::vector<std::int32_t> region_root;
};

Assembly assemble(const RegionPlan& plan, std::vector<ClusterTree>& regions) {
  if (regions.size() != plan.regions())
    throw OptionError("the plan has " + std::to_string(plan.regions()) + " regions, not " +
                      std::to_string(regions.size()));
  const ClusterTree* first = nullptr;
  std::size_t nodes = 0;
  for (const ClusterTree& t : regions) {
    nodes += t.nodes.size();
    if (t.nodes.empty()) continue;
    if (first == nullptr) first = &t;
    if (!(t.parameters == first->parameters) || t.error_threshold != first->error_threshold ||
        t.origin != first->origin || t.up != first->up)
      throw OptionError("the region trees were not built with the same options and scale");
  }
  if (first == nullptr) throw OptionError("every region is empty: there is no surface");
  Assembly a;
  ClusterTree& out = a.tree;
  out.parameters = first->parameters;
  out.noise_sigma = first->noise_sigma;
  out.error_threshold = first->error_threshold;
  out.point_spacing = first->point_spacing;
  out.origin = first->origin;
  out.up = first->up;
  out.nodes.reserve(nodes + plan.cells.size());  // no reallocation: the regions' nodes are freed as they move
  bool point_leaves = true;
  for (const ClusterTree& t : regions) {
    out.input_points += t.input_points;
    point_leaves = point_leaves && t.point_leaf.size() == t.input_points;
  }
  Merger merger{plan,
                regions,
                out.parameters,
                out,
                std::vector<std::int32_t>(regions.size(), -1),
                std::vector<std::uint64_t>(plan.cells.size(), 0),
                std::vector<BoundingBox>(plan.cells.size())};
  merger.measure(0);
  merger.emit(0, -1, 0);
  out.bbox = merger.cell_box[0];
  // The point-leaf tables, renumbered and concatenated in region order.
  if (point_leaves) {
    for (std::size_t r = 0; r < regions.size(); ++r)
      for (const std::int32_t leaf : regions[r].point_leaf)
        out.point_leaf.push_back(leaf < 0 ? -1 : leaf + merger.region_root[r]);
  }
  a.region_root = std::move(merger.region_root);
  return a;
}

}  // namespace

ClusterTree merge_region_trees(const RegionPlan& plan, std::vector<ClusterTree> regions, bool propagated,
                               RegionMerge& record) {
  record.reach.assign(regions.size(), 0.0);
  for (std::size_t r = 0; r < regions.size(); ++r)
    for (const ClusterNode& n : regions[r].nodes)
      if (n.is_leaf()) record.reach[r] = std::max(record.reach[r], n.support.radius);
  Assembly a = assemble(plan, regions);
  record.flipped = align_regions(a.tree, a.region_root, propagated);
  record.bbox = a.tree.bbox;
  record.point_spacing = a.tree.point_spacing;
  record.leaves = static_cast<std::size_t>(
      std::count_if(a.tree.nodes.begin(), a.tree.nodes.end(), [](const ClusterNode& n) { return n.is_leaf(); }));
  return std::move(a.tree);
}

ClusterTree merge_region_trees(const RegionPlan& plan, std::vector<ClusterTree> regions, bool propagated) {
  RegionMerge record;
  return merge_region_trees(plan, std::move(regions), propagated, record);
}

ClusterTree tile_tree(const RegionPlan& plan, std::vector<ClusterTree> regions, const RegionMerge& merge) {
  if (merge.flipped.size() != plan.regions() || regions.size() != plan.regions())
    throw OptionError("the merge record does not match the plan");
  for (std::size_t r = 0; r < regions.size(); ++r)
    if (merge.flipped[r])
      for (ClusterNode& n : regions[r].nodes) n.proxy.flip();
  Assembly a = assemble(plan, regions);
  a.tree.bbox = merge.bbox;
  return std::move(a.tree);
}

}  // namespace clustersurf
