// Dropping the triangles that reach beyond the input points, and the fragments they do not support.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_trim.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include "mesh/data_reach.hpp"
#include "mesh/mesh_components.hpp"
#include "mesh/mesh_subset.hpp"
#include "mesh/pinhole_fill.hpp"
#include "spatial/spatial_order.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace clustersurf {

namespace {

/// A pinhole's loop lies within this many data spreads of its centroid: the centroid's
/// nearness to the data decides whether the data covers the hole; this bound keeps a fan from
/// spanning a long slit or border (16 closed more and cost more accuracy on the ogre, 4 fewer).
constexpr double kMaxPinholeSpreads = 8;

/// The most vertices nearest_kept() looks through in the index of all vertices before it asks
/// the index of the kept ones alone (where the trim took most of the mesh around a point).
constexpr std::size_t kMaxKeptSearch = 64;

/// The row of the vertex nearest to `x` (ties by row) among those `component` gives a component,
/// from `index` over all the mesh's vertices or, past kMaxKeptSearch of them, from `kept` (an
/// index of those vertices alone, rows `kept_rows` ascending, built once on first use); -1 when
/// none has one.
std::int64_t nearest_kept(const KdTree& index, const std::vector<std::int32_t>& component, const Eigen::Vector3d& x,
                          const std::function<const KdTree&()>& kept, std::span<const Eigen::Index> kept_rows,
                          std::vector<Neighbor>& nb) {
  for (std::size_t k = 1; k <= kMaxKeptSearch; k *= 4) {
    index.knn(x, k, nb);
    for (const Neighbor& n : nb)
      if (component[n.index] >= 0) return n.index;
    if (nb.size() < k) return -1;
  }
  kept().knn(x, 1, nb);
  return nb.empty() ? -1 : kept_rows[nb[0].index];
}

/// Clears keep[t] for the triangles of every component (triangles sharing a vertex) on which
/// fewer than `min_points` input points have their nearest vertex; the best-supported
/// component always stays. `vertex_index`, over all of the mesh's vertices, or null to build
/// it. Returns how many components went.
std::size_t drop_unsupported_components(const TriangleMesh& mesh, const Points& points, std::size_t min_points,
                                        std::vector<std::uint8_t>& keep, const KdTree* vertex_index) {
  const std::vector<std::int32_t> component = detail::vertex_components(mesh, &keep);
  std::vector<Eigen::Index> rows;  // the vertices the kept triangles use
  std::size_t components = 0;
  for (std::size_t v = 0; v < component.size(); ++v) {
    if (component[v] < 0) continue;
    rows.push_back(static_cast<Eigen::Index>(v));
    components += component[v] == static_cast<std::int32_t>(v);
  }
  if (components < 2) return 0;  // the best-supported component always stays

  // Each input point votes for the component of its nearest kept vertex.
  std::vector<std::int32_t> voted(static_cast<std::size_t>(points.rows()));
  const std::vector<std::uint32_t> order = detail::spatial_order(points);  // queries in spatial order
  std::optional<KdTree> own;
  const KdTree& index = vertex_index != nullptr ? *vertex_index : own.emplace(mesh.vertices);
  Points kept_vertices;
  std::optional<KdTree> kept_index;
  std::once_flag kept_once;
  const auto kept = [&]() -> const KdTree& {
    std::call_once(kept_once, [&] {
      kept_vertices = mesh.vertices(rows, Eigen::all);
      kept_index.emplace(kept_vertices);
    });
    return *kept_index;
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 1024), [&](const auto& r) {
    std::vector<Neighbor> nb;
    for (std::size_t o = r.begin(); o != r.end(); ++o) {
      const std::int64_t v = nearest_kept(index, component, points.row(order[o]).transpose(), kept, rows, nb);
      voted[order[o]] = component[static_cast<std::size_t>(v)];
    }
  });
  std::vector<std::size_t> votes(component.size(), 0);
  for (const auto c : voted) ++votes[static_cast<std::size_t>(c)];
  std::size_t best = 0;
  for (const auto v : rows)
    if (component[static_cast<std::size_t>(v)] == v) best = std::max(best, votes[static_cast<std::size_t>(v)]);
  const std::size_t needed = std::min(min_points, best);
  std::size_t dropped = 0;
  for (const auto v : rows)
    dropped += component[static_cast<std::size_t>(v)] == v && votes[static_cast<std::size_t>(v)] < needed;
  if (dropped == 0) return 0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    if (keep[static_cast<std::size_t>(t)] &&
        votes[static_cast<std::size_t>(component[static_cast<std::size_t>(mesh.triangles(t, 0))])] < needed)
      keep[static_cast<std::size_t>(t)] = 0;
  return dropped;
}

}  // namespace

double typical_spread(const ClusterTree& tree) {
  std::vector<std::pair<double, double>> leaves;  // spread, area weight
  double total = 0;
  for (const ClusterNode& node : tree.nodes)
    if (node.is_leaf() && node.point_count >= 2 && node.extent > 0) {
      leaves.emplace_back(node.extent / std::sqrt(2.0 * node.point_count), node.extent * node.extent);
      total += leaves.back().second;
    }
  std::sort(leaves.begin(), leaves.end());
  double below = 0, median = 0;
  for (const auto& [spacing, weight] : leaves) {
    median = spacing;
    if ((below += weight) >= total / 2) break;
  }
  return median;
}

TriangleMesh trim_to_points(const TriangleMesh& mesh, const Points& points, const TrimOptions& options,
                            TrimReport* report) {
  return trim_to_points(mesh, KdTree(points), options, report);
}

TriangleMesh trim_to_points(const TriangleMesh& mesh, const KdTree& data, const TrimOptions& options,
                            TrimReport* report, std::span<const double> spread) {
  const Points& points = data.points();
  if (!(options.spread_factor >= 0) || !std::isfinite(options.spread_factor))
    throw OptionError("mesh trim: the spread factor must be finite and >= 0 (0 keeps every triangle)");
  if (options.neighbors < 1) throw OptionError("mesh trim: neighbors must be at least 1");
  if (!(options.max_reach_spreads >= 0) || !std::isfinite(options.max_reach_spreads))
    throw OptionError("mesh trim: max_reach_spreads must be finite and >= 0 (0: no bound)");
  if (!(options.typical_spread >= 0) || !std::isfinite(options.typical_spread))
    throw OptionError("mesh trim: the typical spread must be finite and >= 0 (0: measured at the vertices)");
  if (report != nullptr) *report = {};
  const Eigen::Index nv = mesh.vertices.rows();
  std::vector<std::uint8_t> keep(static_cast<std::size_t>(mesh.triangles.rows()), 1);
  const bool enough_points = points.rows() > static_cast<Eigen::Index>(options.neighbors);
  const bool use_index = enough_points && !keep.empty();
  const bool vote = options.min_component_points > 0 && points.rows() > 0 && !keep.empty();
  std::optional<KdTree> vertex_index;  // for the vote, built while the trim measures where a mesh has pieces
  if (options.spread_factor > 0 && use_index) {
    std::vector<std::uint8_t> near;
    tbb::parallel_invoke([&] { near = detail::vertices_near_data(mesh, data, options, spread); },
                         [&] {
                           if (vote && detail::component_count(mesh) > 1) vertex_index.emplace(mesh.vertices);
                         });
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
      const auto tri = mesh.triangles.row(t);
      keep[static_cast<std::size_t>(t)] = near[static_cast<std::size_t>(tri(0))] &&
                                          near[static_cast<std::size_t>(tri(1))] &&
                                          near[static_cast<std::size_t>(tri(2))];
    }
  }
  std::size_t dropped_components = 0;
  if (vote)
    dropped_components = drop_unsupported_components(mesh, points, options.min_component_points, keep,
                                                     vertex_index ? &*vertex_index : nullptr);
  // An if, not ?: between the const lvalue and the call: GCC 12 with ASan leaked that prvalue.
  TriangleMesh out;
  if (std::find(keep.begin(), keep.end(), 0) == keep.end())
    out = mesh;
  else
    out = detail::with_triangles(mesh, keep);
  if (report != nullptr) {
    report->removed_triangles = static_cast<std::size_t>(mesh.triangles.rows() - out.triangles.rows());
    report->removed_vertices = static_cast<std::size_t>(nv - out.vertices.rows());
    report->removed_components = dropped_components;
  }
  if (options.close_pinholes && use_index) {
    // Pinholes are closed within the trim's reach of the data (or 2 spreads with the trim off).
    const double reach = options.spread_factor > 0 ? options.spread_factor : TrimOptions{}.spread_factor;
    const std::size_t closed = detail::close_pinholes(out, data, reach, options.neighbors, kMaxPinholeSpreads);
    if (report != nullptr) report->closed_pinholes = closed;
  }
  return out;
}

}  // namespace clustersurf
