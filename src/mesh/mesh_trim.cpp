// Dropping the triangles that reach beyond the input points, and the fragments they do not support.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_trim.hpp>
#include <clustersurf/proxy/moments.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include "mesh/data_reach.hpp"
#include "mesh/mesh_components.hpp"
#include "mesh/mesh_subset.hpp"
#include "mesh/pinhole_fill.hpp"
#include "spatial/spatial_order.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <numbers>
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
/// A vertex beyond the reach but within this many times it is kept when data surrounds it: the
/// vertices over the largest gaps of random samples lie within it (Igea's 100 k samples: up to
/// 2.6 spreads from the nearest point). A real hole or slit this narrow is closed too.
constexpr double kSurroundedReach = 1.5;
/// Surrounding is judged on at least this many nearest points (and twice TrimOptions::neighbors).
constexpr std::size_t kSurroundingNeighbors = 16;
/// The neighbours lie on one sheet when their least variance is at most this share of the
/// next: between two layers (a slot, two scans apart) they spread most across the gap, and
/// the two least variances are alike.
constexpr double kMaxSheetVarianceRatio = 0.25;
/// Data surrounds a point when no half-plane through it, in the data's plane, holds all its
/// neighbours: no angle between consecutive neighbours around it reaches π. Past the data's
/// edge they all lie to one side; over a gap between samples they lie all around.
constexpr double kMaxSurroundingGap = std::numbers::pi;
/// A vertex within the reach but farther than this share of its nearest point's spread from it
/// is tested against the data's sheet: nearer, it lies on the data.
constexpr double kOnDataSpreads = 0.5;
/// Where the surrounding neighbours wrap around a thin part, this many nearest of them (the
/// near side's) are judged as a sheet instead...
constexpr std::size_t kThinSheetNeighbors = 8;
/// ...when they lie within this share of a spread of their plane (RMS): one side of the part.
constexpr double kThinSheetSpreads = 0.5;

/// The moments of the points `near`, taken relative to `x`.
PlaneMoments moments_of(const Eigen::Vector3d& x, const Points& points, std::span<const Neighbor> near) {
  PlaneMoments moments(x);
  for (const auto& nb : near) moments.add(points.row(nb.index).transpose());
  return moments;
}

/// The least-squares plane of the points `around` when they lie on one sheet
/// (kMaxSheetVarianceRatio), else none.
std::optional<PlaneProxy> data_sheet(const Eigen::Vector3d& x, const Points& points, std::span<const Neighbor> around) {
  if (around.size() < 3) return std::nullopt;
  const PlaneMoments moments = moments_of(x, points, around);
  const Eigen::Vector3d variances = moments.spreads();                                // ascending
  if (!(variances(0) <= kMaxSheetVarianceRatio * variances(1))) return std::nullopt;  // not one sheet
  return moments.fit();
}

/// Whether `x` lies farther than `spread` from `plane`.
bool off_plane(const PlaneProxy& plane, const Eigen::Vector3d& x, double spread) {
  return std::abs((x - plane.point).dot(plane.normal)) > spread;
}

/// The least-squares plane of the points `near` when they lie within kThinSheetSpreads ×
/// `spread` of it (RMS), else none.
std::optional<PlaneProxy> thin_sheet(const Eigen::Vector3d& x, const Points& points, std::span<const Neighbor> near,
                                     double spread) {
  if (near.size() < 3) return std::nullopt;
  const PlaneMoments moments = moments_of(x, points, near);
  if (!(moments.rms_error() <= kThinSheetSpreads * spread)) return std::nullopt;
  return moments.fit();
}

/// Whether the points `around` `x` (nearest first) lie on one sheet and x lies farther than
/// `spread` from its plane: surface near the data that is not the data's surface. Where they
/// are not one sheet (they wrap around a thin part), the kThinSheetNeighbors nearest decide
/// when they are one thin sheet (thin_sheet()); else (an edge, a corner) nothing is decided: false.
bool off_sheet(const Eigen::Vector3d& x, const Points& points, std::span<const Neighbor> around, double spread) {
  std::optional<PlaneProxy> plane = data_sheet(x, points, around);
  if (!plane) plane = thin_sheet(x, points, around.first(std::min(around.size(), kThinSheetNeighbors)), spread);
  return plane && off_plane(*plane, x, spread);
}

/// Whether the points `around` `x` lie on one sheet (kMaxSheetVarianceRatio), `x` lies within
/// `spread` of their least-squares plane, and they leave no angular gap of kMaxSurroundingGap
/// or more around it in that plane. `angles` is scratch space.
bool surrounded(const Eigen::Vector3d& x, const Points& points, std::span<const Neighbor> around, double spread,
                std::vector<double>& angles) {
  const std::optional<PlaneProxy> sheet = data_sheet(x, points, around);
  if (!sheet || off_plane(*sheet, x, spread)) return false;  // not one sheet, or off the data's surface
  const PlaneProxy& plane = *sheet;
  const Eigen::Vector3d u = plane.normal.unitOrthogonal(), w = plane.normal.cross(u);
  angles.clear();
  for (const auto& nb : around) {
    const Eigen::Vector3d d = points.row(nb.index).transpose() - x;
    const double a = d.dot(u), b = d.dot(w);
    if (a != 0 || b != 0) angles.push_back(std::atan2(b, a));
  }
  if (angles.size() < 3) return false;
  std::sort(angles.begin(), angles.end());
  double gap = angles.front() + 2 * std::numbers::pi - angles.back();
  for (std::size_t k = 1; k < angles.size(); ++k) gap = std::max(gap, angles[k] - angles[k - 1]);
  return gap < kMaxSurroundingGap;
}

/// The spread (mean distance to its `k` nearest points) of every point of `index` that is some
/// vertex's `nearest`, once per point; -1 for the others.
std::vector<double> spreads_of_nearest(const KdTree& index, std::span<const Neighbor> nearest, std::size_t k) {
  std::vector<double> spread(index.size(), -1);
  std::vector<std::uint32_t> used;
  for (const auto& n : nearest)
    if (spread[n.index] < 0) spread[n.index] = 0, used.push_back(n.index);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, used.size(), 256), [&](const auto& r) {
    std::vector<Neighbor> around;
    for (std::size_t u = r.begin(); u != r.end(); ++u) {
      index.neighbors_of(used[u], k, around);
      double sum = 0;
      for (const auto& q : around) sum += std::sqrt(q.distance_squared);
      spread[used[u]] = sum / static_cast<double>(around.size());
    }
  });
  return spread;
}

}  // namespace

std::vector<std::uint8_t> detail::vertices_near_data(const TriangleMesh& mesh, const KdTree& index,
                                                     const TrimOptions& options, std::span<const double> given) {
  if (!given.empty() && given.size() != index.size())
    throw OptionError("mesh trim: " + std::to_string(given.size()) + " spreads for " + std::to_string(index.size()) +
                      " points");
  // The nearest input point of every vertex, then the spread of each such point (once per
  // point: many vertices share one), unless they are given.
  const Eigen::Index nv = mesh.vertices.rows();
  std::vector<Neighbor> nearest(static_cast<std::size_t>(nv));
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, nv, 512), [&](const auto& r) {
    std::vector<Neighbor> nb;
    for (Eigen::Index v = r.begin(); v != r.end(); ++v) {
      index.knn(mesh.vertices.row(v).transpose(), 1, nb);
      nearest[static_cast<std::size_t>(v)] = nb[0];
    }
  });
  std::vector<double> measured;
  if (given.empty()) measured = spreads_of_nearest(index, nearest, options.neighbors);
  const std::span<const double> spread = given.empty() ? std::span<const double>(measured) : given;
  // The reach of a point, options.spread_factor times its spread, bounded by
  // options.max_reach_spreads typical spreads (in the surrounding test too, through the spread).
  double typical = options.typical_spread;
  if (!(typical > 0) && options.max_reach_spreads > 0) {  // the median over the mesh's vertices
    std::vector<double> at_vertices(nearest.size());
    for (std::size_t v = 0; v < nearest.size(); ++v) at_vertices[v] = spread[nearest[v].index];
    const auto middle = at_vertices.begin() + static_cast<std::ptrdiff_t>(at_vertices.size() / 2);
    std::nth_element(at_vertices.begin(), middle, at_vertices.end());
    typical = at_vertices.empty() ? 0.0 : *middle;
  }
  const double max_spread = options.max_reach_spreads > 0 && typical > 0
                                ? options.max_reach_spreads * typical / options.spread_factor
                                : std::numeric_limits<double>::infinity();
  const auto spread_of = [&](const Neighbor& n) { return std::min(max_spread, spread[n.index]); };
  std::vector<std::uint8_t> near(static_cast<std::size_t>(nv));
  std::vector<Eigen::Index> between;  // beyond the reach, within kSurroundedReach times it
  std::vector<Eigen::Index> within;   // within the reach, over half a spread from the data
  for (std::size_t v = 0; v < near.size(); ++v) {
    const double d = std::sqrt(nearest[v].distance_squared), reach = options.spread_factor * spread_of(nearest[v]);
    near[v] = d <= reach;
    if (!near[v] && d <= kSurroundedReach * reach) between.push_back(static_cast<Eigen::Index>(v));
    if (near[v] && d > kOnDataSpreads * spread_of(nearest[v])) within.push_back(static_cast<Eigen::Index>(v));
  }
  // A vertex a little beyond the reach, on the data's surface, with data all around it, sits
  // over a gap between samples, not past the data's edge (where all its data lies to one side),
  // on a bulge off the data, or on a sheet between two layers of it.
  const std::size_t surrounding = std::max(kSurroundingNeighbors, 2 * options.neighbors);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, between.size(), 64), [&](const auto& r) {
    std::vector<Neighbor> around;
    std::vector<double> angles;
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const Eigen::Index v = between[b];
      index.knn(mesh.vertices.row(v).transpose(), surrounding, around);
      near[static_cast<std::size_t>(v)] = surrounded(mesh.vertices.row(v).transpose(), index.points(), around,
                                                     spread_of(nearest[static_cast<std::size_t>(v)]), angles);
    }
  });
  // A vertex within the reach but off the sheet the data forms around it is not the data's
  // surface either: a flap the blend raises between two close parts, a bubble's wall.
  std::vector<std::uint8_t> off(static_cast<std::size_t>(nv), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, within.size(), 64), [&](const auto& r) {
    std::vector<Neighbor> around;
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const Eigen::Index v = within[b];
      const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
      index.knn(x, surrounding, around);
      off[static_cast<std::size_t>(v)] =
          off_sheet(x, index.points(), around, spread_of(nearest[static_cast<std::size_t>(v)]));
    }
  });
  // One such vertex among vertices on the data is a spike of the blend (the refit takes it
  // back), not a flap: it stays, where cutting it would leave a pinhole. It goes with a
  // neighbour off the sheet or beyond the reach.
  std::vector<std::uint8_t> joined(static_cast<std::size_t>(nv), 0);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const auto tri = mesh.triangles.row(t);
    int away = 0;
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(tri(k));
      away += off[v] || !near[v];
    }
    if (away < 2) continue;
    for (int k = 0; k < 3; ++k) joined[static_cast<std::size_t>(tri(k))] = 1;
  }
  for (std::size_t v = 0; v < near.size(); ++v)
    if (off[v] && joined[v]) near[v] = 0;
  return near;
}

namespace {

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
