// One block's merge test: its triangles' disk and rim, the fan that replaces them, its normals
// and distances; and the same checks on the coarse mesh around a vertex.

#include "mesh/block_merge.hpp"

#include "spatial/spatial_order.hpp"

#include <clustersurf/core/closest_point.hpp>

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace clustersurf::detail {

namespace {

/// Bits of each cell coordinate in a Morton code; coordinates are offset by half their range.
constexpr int kCodeBits = 21;
constexpr std::int64_t kCodeOffset = std::int64_t{1} << (kCodeBits - 1);

/// Whether triangle (a, b, c) has an area (against the cell's square) and a normal within
/// kMinNormalCosine of each corner's normal.
bool upright(const MeshView& mesh, Index a, Index b, Index c) {
  const Eigen::Vector3d pa = mesh.position(a);
  const Eigen::Vector3d n = (mesh.position(b) - pa).cross(mesh.position(c) - pa);
  const double length = n.norm();
  if (!(length > 1e-12 * mesh.cell() * mesh.cell())) return false;
  for (const Index v : {a, b, c})
    if (n.dot(mesh.normal(v)) < kMinNormalCosine * length) return false;
  return true;
}

/// How the directed edges `link` join: one simple cycle, one simple path, or neither. Sorts
/// `link`.
enum class Chain { Cycle, Path, Broken };
Chain chain_of(std::vector<std::pair<Index, Index>>& link) {
  std::sort(link.begin(), link.end());
  for (std::size_t i = 1; i < link.size(); ++i)
    if (link[i].first == link[i - 1].first) return Chain::Broken;
  // A path starts at a vertex that no edge ends at; a cycle has none.
  std::vector<Index> ends;
  ends.reserve(link.size());
  for (const auto& e : link) ends.push_back(e.second);
  std::sort(ends.begin(), ends.end());
  for (std::size_t i = 1; i < ends.size(); ++i)
    if (ends[i] == ends[i - 1]) return Chain::Broken;
  Index start = link.front().first;
  std::size_t starts = 0;
  for (const auto& e : link)
    if (!std::binary_search(ends.begin(), ends.end(), e.first)) start = e.first, ++starts;
  if (starts > 1) return Chain::Broken;
  std::size_t steps = 0;
  for (Index at = start;;) {
    const auto next = std::lower_bound(link.begin(), link.end(), std::pair{at, Index{0}});
    if (next == link.end() || next->first != at) break;  // the path's end
    at = next->second;
    ++steps;
    if (at == start || steps > link.size()) break;
  }
  if (steps != link.size()) return Chain::Broken;
  return starts == 0 ? Chain::Cycle : Chain::Path;
}

/// The smallest squared distance from p to the triangles `fan`.
double squared_distance(const Eigen::Vector3d& p, const MeshView& mesh, std::span<const Triangle> fan) {
  double best = std::numeric_limits<double>::infinity();
  for (const Triangle& f : fan) {
    best =
        std::min(best, (closest_point_on_triangle(p, mesh.position(f[0]), mesh.position(f[1]), mesh.position(f[2])) - p)
                           .squaredNorm());
  }
  return best;
}

}  // namespace

MeshView::MeshView(const TriangleMesh& mesh, const Eigen::Vector3d& origin, double cell, double tolerance,
                   std::span<const float> fixed)
    : mesh_(mesh),
      origin_(origin),
      cell_(cell),
      tolerance_(tolerance),
      around_(mesh.triangles, static_cast<std::size_t>(mesh.vertices.rows())),
      fixed_(fixed) {
  if (mesh.normals.rows() != mesh.vertices.rows()) {
    normals_.assign(static_cast<std::size_t>(mesh.vertices.rows()), Eigen::Vector3d::Zero());
    for (Index t = 0; t < triangle_count(); ++t) {
      const Triangle f = triangle(t);
      const Eigen::Vector3d n = (position(f[1]) - position(f[0])).cross(position(f[2]) - position(f[0]));
      for (const Index v : f) normals_[v] += n;
    }
  }
  cells_.resize(static_cast<std::size_t>(mesh.vertices.rows()));
  tbb::parallel_for(tbb::blocked_range<Index>(0, vertices(), 4096), [&](const auto& r) {
    for (Index v = r.begin(); v != r.end(); ++v) {
      const Eigen::Array3d c = ((position(v) - origin_) / cell_).array().floor();
      cells_[v] = kNoCell;
      if (!c.allFinite() || (c.abs() >= static_cast<double>(kCodeOffset)).any()) continue;
      const auto at = [&](int a) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(c[a]) + kCodeOffset); };
      cells_[v] = morton_code(at(0), at(1), at(2));
    }
  });
}

bool MeshView::same_attributes(Index a, Index b) const {
  for (const PointAttribute& attribute : mesh_.attributes)
    if (attribute.values.size() == mesh_.vertices.rows() && attribute.values(a) != attribute.values(b)) return false;
  return true;
}

Index BlockMerge::kept_vertex(std::span<const Index> block) {
  const MeshView& mesh = *mesh_;
  if (block.size() < 2) return kNone;
  for (const Index v : block)
    if (mesh.fixed(v) || !mesh.same_attributes(v, block.front())) return kNone;
  triangles_.clear();
  for (const Index v : block)
    for (const Index t : mesh.around().of(v)) triangles_.push_back(t);
  std::sort(triangles_.begin(), triangles_.end());
  triangles_.erase(std::unique(triangles_.begin(), triangles_.end()), triangles_.end());
  // The cheap tests first: the fan, from the triangles with one corner in the block, and the
  // distances to it; then the topology that makes it the block's whole replacement.
  const Index keep = central_vertex(block);
  if (!fan_holds(block, keep) || !one_disk(block)) return kNone;
  return keep;
}

Index BlockMerge::central_vertex(std::span<const Index> block) const {
  const MeshView& mesh = *mesh_;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Index v : block) centroid += mesh.position(v);
  centroid /= static_cast<double>(block.size());
  Index keep = block.front();
  double nearest = std::numeric_limits<double>::infinity();
  for (const Index v : block) {
    const Eigen::Vector3d p = mesh.position(v);
    const double d = (p - centroid).squaredNorm();
    const Eigen::Vector3d q = mesh.position(keep);
    if (d < nearest || (d == nearest && std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3))) {
      nearest = d;
      keep = v;
    }
  }
  return keep;
}

bool BlockMerge::fan_holds(std::span<const Index> block, Index keep) {
  const MeshView& mesh = *mesh_;
  const auto inside = [&](Index v) { return std::binary_search(block.begin(), block.end(), v); };
  fan_.clear();
  for (const Index t : triangles_) {
    const Triangle f = mesh.triangle(t);
    const int corners = int(inside(f[0])) + int(inside(f[1])) + int(inside(f[2]));
    if (corners != 1) continue;
    const std::size_t k = inside(f[0]) ? 0 : inside(f[1]) ? 1 : 2;
    fan_.push_back({keep, f[(k + 1) % 3], f[(k + 2) % 3]});
  }
  return unturned(mesh, fan_) && within_tolerance(block, keep, mesh, fan_);
}

bool BlockMerge::one_disk(std::span<const Index> block) {
  const MeshView& mesh = *mesh_;
  const auto inside = [&](Index v) { return std::binary_search(block.begin(), block.end(), v); };
  edges_.clear();
  vertices_.clear();
  for (const Index t : triangles_) {
    const Triangle f = mesh.triangle(t);
    for (std::size_t k = 0; k < 3; ++k) {
      const Index a = f[k], b = f[(k + 1) % 3];
      edges_.push_back({std::min(a, b), std::max(a, b), a, b});
      vertices_.push_back(a);
    }
  }
  std::sort(edges_.begin(), edges_.end(),
            [](const Edge& x, const Edge& y) { return std::tie(x.lo, x.hi) < std::tie(y.lo, y.hi); });
  std::sort(vertices_.begin(), vertices_.end());
  vertices_.erase(std::unique(vertices_.begin(), vertices_.end()), vertices_.end());
  // Each edge in one or two triangles; those in one (the rim) between vertices outside the
  // block; the block's vertices joined by edges into one piece.
  std::size_t edges = 0, rim = 0;
  parent_.resize(block.size());
  std::iota(parent_.begin(), parent_.end(), Index{0});
  const auto root = [&](Index i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  };
  const auto at = [&](Index v) {
    return static_cast<Index>(std::lower_bound(block.begin(), block.end(), v) - block.begin());
  };
  for (std::size_t i = 0, j = 0; i < edges_.size(); i = j) {
    while (j < edges_.size() && edges_[j].lo == edges_[i].lo && edges_[j].hi == edges_[i].hi) ++j;
    ++edges;
    const Edge& e = edges_[i];
    if (j - i > 2) return false;
    const bool in_lo = inside(e.lo), in_hi = inside(e.hi);
    if (j - i == 1) {
      if (in_lo || in_hi) return false;
      ++rim;
    } else if (in_lo && in_hi) {
      parent_[root(at(e.lo))] = root(at(e.hi));
    }
  }
  for (std::size_t i = 0; i < block.size(); ++i)
    if (root(static_cast<Index>(i)) != root(0)) return false;
  // The rim is the fan's (each of its edges faces one corner in the block), one simple cycle
  // through every vertex outside the block, and Euler's characteristic is 1.
  if (rim != fan_.size() || fan_.size() < 3 || vertices_.size() != block.size() + fan_.size()) return false;
  if (static_cast<long>(vertices_.size()) - static_cast<long>(edges) + static_cast<long>(triangles_.size()) != 1)
    return false;
  rim_.clear();
  for (const Triangle& f : fan_) rim_.emplace_back(f[1], f[2]);
  return chain_of(rim_) == Chain::Cycle;
}

bool one_fan(Index v, std::span<const Triangle> star, std::vector<std::pair<Index, Index>>& link) {
  link.clear();
  for (const Triangle& f : star) {
    const std::size_t k = f[0] == v ? 0 : f[1] == v ? 1 : 2;
    link.emplace_back(f[(k + 1) % 3], f[(k + 2) % 3]);
  }
  return link.empty() || chain_of(link) != Chain::Broken;
}

bool unturned(const MeshView& mesh, std::span<const Triangle> star) {
  for (const Triangle& f : star)
    if (!upright(mesh, f[0], f[1], f[2])) return false;
  return true;
}

bool within_tolerance(std::span<const Index> members, Index keep, const MeshView& mesh, std::span<const Triangle> fan) {
  const double limit = mesh.tolerance() * mesh.tolerance();
  for (const Index v : members)
    if (v != keep && !(squared_distance(mesh.position(v), mesh, fan) <= limit)) return false;
  return true;
}

}  // namespace clustersurf::detail
