// Seeds and the breadth-first walk over the cells the surface crosses.

#include "mesh/surface_walk.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace clustersurf::detail {

bool project(const ImplicitSurface& s, const ImplicitSurface::BoxWalk* near, Eigen::Vector3d& x, int steps,
             double max_move, double tolerance, SurfaceSample* at_x) {
  const Eigen::Vector3d start = x;
  for (int k = 0; k < steps; ++k) {
    const SurfaceSample q = near != nullptr ? s.sample(x, *near) : s.sample(x);
    if (!q.defined) return false;
    if (std::abs(q.value) <= tolerance) {
      if (at_x != nullptr) *at_x = q;
      return true;
    }
    const double g2 = q.gradient.squaredNorm();
    if (!(g2 > 0)) return false;
    x -= (q.value / g2) * q.gradient;
    if ((x - start).norm() > max_move) return false;
  }
  const auto v = near != nullptr ? s.value(x, 0, *near) : s.value(x);
  return v && std::abs(*v) <= 10 * tolerance;
}

namespace {

/// A unit vector orthogonal to n.
Eigen::Vector3d any_tangent(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a = std::abs(n.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(a).normalized();
}

// For each face direction (−x, +x, −y, +y, −z, +z): the 4 corners on that face, and the step.
constexpr int kFaceCorners[6][4] = {{0, 2, 4, 6}, {1, 3, 5, 7}, {0, 1, 4, 5}, {2, 3, 6, 7}, {0, 1, 2, 3}, {4, 5, 6, 7}};
constexpr int kFaceStep[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

/// Which faces of a cell with corner `values` the surface crosses (bit f for face f, in
/// kFaceCorners' order) and, in bit 6, whether it crosses the cell; 0 where a value is undefined.
std::uint8_t crossings(const std::array<float, 8>& values) {
  bool any_neg = false, any_pos = false;
  for (const float value : values) {
    if (std::isnan(value)) return 0;
    (value < 0 ? any_neg : any_pos) = true;
  }
  if (!any_neg || !any_pos) return 0;
  std::uint8_t crossed = 1u << 6;
  for (int f = 0; f < 6; ++f) {
    bool neg = false, pos = false;
    for (int c : kFaceCorners[f]) (values[static_cast<std::size_t>(c)] < 0 ? neg : pos) = true;
    if (neg && pos) crossed |= static_cast<std::uint8_t>(1u << f);
  }
  return crossed;
}

/// The points a proxy's seed is projected from, in steps of r/3 along its two tangents: the
/// centre first.
constexpr std::array<std::array<int, 2>, 9> kSeedSteps = {
    {{0, 0}, {-1, -1}, {-1, 0}, {-1, 1}, {0, -1}, {0, 1}, {1, -1}, {1, 0}, {1, 1}}};

/// The field at `corners` (NaN where undefined), evaluated block by block, each block's walk of
/// the tree done once.
std::vector<float> corner_values(const Field& field, const Lattice& lattice, const std::vector<GridIndex>& corners) {
  const Blocks blocks = group_by_block(corners.size(), [&](std::size_t t) {
    return std::array<std::int64_t, 3>{corners[t][0], corners[t][1], corners[t][2]};
  });
  std::vector<float> values(corners.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.count()), [&](const auto& r) {
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const auto position = [&](std::uint32_t t) {
        return lattice.corner(corners[t][0], corners[t][1], corners[t][2]);
      };
      // A closed surface evaluates its own field: its corners keep an empty box.
      BoundingBox box;
      if (field.closed == nullptr)
        for (const std::uint32_t t : blocks.block(b)) box.extend(position(t));
      const ImplicitSurface::BoxWalk near(field.surface, box);
      std::optional<ImplicitSurface::BoxWalk> wide_near;  // built when a corner needs the fill
      for (const std::uint32_t t : blocks.block(b)) {
        const Eigen::Vector3d x = position(t);
        std::optional<double> v;
        if (field.closed != nullptr)
          v = field.closed->value(x);
        else {
          v = field.surface.value(x, field.min_weight, near);
          if (!v && field.fill)
            v = field.wide.value(x, field.min_weight, wide_near ? *wide_near : wide_near.emplace(field.wide, box));
        }
        values[t] = v ? static_cast<float>(*v) : std::numeric_limits<float>::quiet_NaN();
      }
    }
  });
  return values;
}

/// The cells of all rounds sorted by (k, j, i), which is their keys' order: one order on any
/// thread count. Keys and places are sorted, then the cells gathered, both in parallel.
std::vector<SurfaceCell> in_key_order(const std::vector<std::vector<SurfaceCell>>& rounds, std::size_t count) {
  std::vector<std::pair<Key, const SurfaceCell*>> keyed;
  keyed.reserve(count);
  for (const auto& round : rounds)
    for (const SurfaceCell& cell : round)
      keyed.emplace_back(pack(cell.corner[0], cell.corner[1], cell.corner[2]), &cell);
  tbb::parallel_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<SurfaceCell> out(keyed.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keyed.size(), 4096), [&](const auto& r) {
    for (std::size_t t = r.begin(); t != r.end(); ++t) out[t] = *keyed[t].second;
  });
  return out;
}

}  // namespace

std::vector<Key> seed_cells(const ImplicitSurface& surface, const Lattice& lattice) {
  const ClusterTree& tree = surface.tree();
  const auto& cut = surface.cut();
  std::vector<std::vector<Key>> seeds(cut.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cut.size()), [&](const auto& r) {
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      const ClusterNode& n = tree.nodes[static_cast<std::size_t>(cut[c])];
      if (!lattice.meets(n.support)) continue;
      const Eigen::Vector3d normal = n.proxy.normal();
      const Eigen::Vector3d t1 = any_tangent(normal), t2 = normal.cross(t1);
      const double step = n.support.radius / 3;
      for (std::size_t s = 0; s < kSeedSteps.size() && (s == 0 || seeds[c].empty()); ++s) {
        const auto [a, b] = kSeedSteps[s];
        Eigen::Vector3d x = n.support.center + step * (a * t1 + b * t2);
        if (project(surface, nullptr, x, 12, n.support.radius, 1e-3 * lattice.h))
          seeds[c].push_back(lattice.cell_of(x));
      }
    }
  });
  std::vector<Key> frontier;
  for (const auto& cells : seeds)
    for (Key key : cells) {
      const auto [i, j, k] = unpack(key);
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj)
          for (int dk = -1; dk <= 1; ++dk) frontier.push_back(pack(i + di, j + dj, k + dk));
    }
  const MeshClip* clip = lattice.clip;
  if (clip != nullptr && clip->seeds != nullptr)
    for (Eigen::Index p = 0; p < clip->seeds->rows(); ++p)
      frontier.push_back(lattice.cell_of(clip->seeds->row(p).transpose()));
  tbb::parallel_sort(frontier.begin(), frontier.end());
  frontier.erase(std::unique(frontier.begin(), frontier.end()), frontier.end());
  if (clip != nullptr) std::erase_if(frontier, [&](Key cell) { return !lattice.allowed(cell); });
  return frontier;
}

Walk walk_surface(const Field& field, const Lattice& lattice, std::vector<Key> frontier, ProgressReporter& reporter) {
  WalkGrid grid;  // corners queued (with f, NaN where undefined) and cells visited
  for (Key cell : frontier) grid.visit(grid_index(cell));
  std::vector<std::vector<SurfaceCell>> rounds;  // the surface cells each round found
  std::size_t settled = 0;                       // how many
  std::vector<GridIndex> todo;                   // corners to evaluate
  std::uint64_t reported = 0;
  while (!frontier.empty()) {
    reporter.check();
    todo.clear();
    for (Key cell : frontier) {
      const GridIndex g = grid_index(cell);
      for (const auto& c : kCellCorner) {
        const GridIndex corner = {g[0] + c[0], g[1] + c[1], g[2] + c[2]};
        if (grid.queue(corner)) todo.push_back(corner);
      }
    }
    grid.set_values(corner_values(field, lattice, todo));

    // The frontier's cells read in parallel: whether the surface crosses each, and which of its
    // faces it crosses (bit f for face f, bit 6 for the cell); then, in order, the cells kept
    // and their unvisited neighbours across those faces queued.
    std::vector<SurfaceCell> cells(frontier.size());
    for (std::size_t t = 0; t < frontier.size(); ++t) cells[t].corner = grid_index(frontier[t]);
    grid.values(cells);
    std::vector<std::uint8_t> crossed(frontier.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.size(), 4096), [&](const auto& r) {
      for (std::size_t t = r.begin(); t != r.end(); ++t) crossed[t] = crossings(cells[t].values);
    });
    std::vector<Key> next;
    std::vector<SurfaceCell>& kept = rounds.emplace_back();
    kept.reserve(
        static_cast<std::size_t>(std::count_if(crossed.begin(), crossed.end(), [](auto c) { return c != 0; })));
    for (std::size_t t = 0; t < frontier.size(); ++t) {
      if (crossed[t] == 0) continue;
      kept.push_back(cells[t]);
      const auto [i, j, k] = unpack(frontier[t]);
      for (int f = 0; f < 6; ++f) {
        if ((crossed[t] & (1u << f)) == 0) continue;
        const Key nb = pack(i + kFaceStep[f][0], j + kFaceStep[f][1], k + kFaceStep[f][2]);
        if ((lattice.clip == nullptr || lattice.allowed(nb)) && grid.visit(grid_index(nb))) next.push_back(nb);
      }
    }
    tbb::parallel_sort(next.begin(), next.end());  // distinct keys: one order on any thread count
    frontier = std::move(next);
    // The walk's length is unknown in advance: report the share of cells already settled.
    settled += kept.size();
    const double done = static_cast<double>(settled) / static_cast<double>(settled + frontier.size() + 1);
    const auto permille = static_cast<std::uint64_t>(900 * done);
    if (permille > reported) reporter.advance(permille - reported), reported = permille;
  }
  Walk out;
  out.cells = in_key_order(rounds, settled);
  out.corners = grid.queued();
  return out;
}

}  // namespace clustersurf::detail
