// vertices_near_data(): which mesh vertices the input points reach, and which lie off the sheet
// they form.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/proxy/moments.hpp>

#include "mesh/data_reach.hpp"

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

namespace clustersurf {

namespace {

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

/// Sets near[v] for each vertex v of `between` (a little beyond the reach) over a gap between
/// samples: on the data's surface, with data all around it (surrounded() of its `surrounding`
/// nearest points), not past the data's edge (where all its data lies to one side), on a bulge
/// off the data, or on a sheet between two layers of it. `spread`: each vertex's spread.
void mark_surrounded(const TriangleMesh& mesh, const KdTree& index, std::span<const Eigen::Index> between,
                     std::size_t surrounding, std::span<const double> spread, std::vector<std::uint8_t>& near) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, between.size(), 64), [&](const auto& r) {
    std::vector<Neighbor> around;
    std::vector<double> angles;
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const Eigen::Index v = between[b];
      const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
      index.knn(x, surrounding, around);
      near[static_cast<std::size_t>(v)] =
          surrounded(x, index.points(), around, spread[static_cast<std::size_t>(v)], angles);
    }
  });
}

/// 1 for each vertex of `within` (within the reach) off the sheet the data forms around it
/// (off_sheet() of its `surrounding` nearest points): a flap the blend raises between two close
/// parts, a bubble's wall. 0 elsewhere.
std::vector<std::uint8_t> off_sheet_vertices(const TriangleMesh& mesh, const KdTree& index,
                                             std::span<const Eigen::Index> within, std::size_t surrounding,
                                             std::span<const double> spread) {
  std::vector<std::uint8_t> off(static_cast<std::size_t>(mesh.vertices.rows()), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, within.size(), 64), [&](const auto& r) {
    std::vector<Neighbor> around;
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const Eigen::Index v = within[b];
      const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
      index.knn(x, surrounding, around);
      off[static_cast<std::size_t>(v)] = off_sheet(x, index.points(), around, spread[static_cast<std::size_t>(v)]);
    }
  });
  return off;
}

/// Clears near[v] for the vertices `off` the data's sheet that share a triangle with another
/// vertex off it or beyond the reach: a flap. One such vertex among vertices on the data is a
/// spike of the blend (the refit takes it back), not a flap: it stays, where cutting it would
/// leave a pinhole.
void drop_flaps(const TriangleMesh& mesh, const std::vector<std::uint8_t>& off, std::vector<std::uint8_t>& near) {
  std::vector<std::uint8_t> joined(near.size(), 0);
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
  // Each vertex's spread: its nearest point's, bounded.
  std::vector<double> vertex_spread(nearest.size());
  for (std::size_t v = 0; v < nearest.size(); ++v) vertex_spread[v] = std::min(max_spread, spread[nearest[v].index]);
  std::vector<std::uint8_t> near(static_cast<std::size_t>(nv));
  std::vector<Eigen::Index> between;  // beyond the reach, within kSurroundedReach times it
  std::vector<Eigen::Index> within;   // within the reach, over half a spread from the data
  for (std::size_t v = 0; v < near.size(); ++v) {
    const double d = std::sqrt(nearest[v].distance_squared), reach = options.spread_factor * vertex_spread[v];
    near[v] = d <= reach;
    if (!near[v] && d <= kSurroundedReach * reach) between.push_back(static_cast<Eigen::Index>(v));
    if (near[v] && d > kOnDataSpreads * vertex_spread[v]) within.push_back(static_cast<Eigen::Index>(v));
  }
  const std::size_t surrounding = std::max(kSurroundingNeighbors, 2 * options.neighbors);
  mark_surrounded(mesh, index, between, surrounding, vertex_spread, near);
  drop_flaps(mesh, off_sheet_vertices(mesh, index, within, surrounding, vertex_spread), near);
  return near;
}

}  // namespace clustersurf
