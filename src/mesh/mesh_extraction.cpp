// Surface-following sparse grid walk (its state in walk_grid: OpenVDB), then polygonization
// (cell_polygonizer: OpenVDB) and projection of the vertices onto f = 0.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/surface/box_walk.hpp>

#include "core/progress_reporter.hpp"
#include "core/system_memory.hpp"
#include "mesh/cell_polygonizer.hpp"
#include "mesh/clipped_extraction.hpp"
#include "mesh/mesh_subset.hpp"
#include "mesh/position_ids.hpp"
#include "mesh/walk_grid.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <tuple>
#include <vector>

namespace clustersurf {

namespace {

using Key = std::uint64_t;
constexpr std::int64_t kBias = std::int64_t{1} << 20;  // grid coordinates in [-2^20, 2^20)

Key pack(std::int64_t i, std::int64_t j, std::int64_t k) {
  return static_cast<Key>(i + kBias) | (static_cast<Key>(j + kBias) << 21) | (static_cast<Key>(k + kBias) << 42);
}
std::array<std::int64_t, 3> unpack(Key key) {
  const Key mask = (Key{1} << 21) - 1;
  return {static_cast<std::int64_t>(key & mask) - kBias, static_cast<std::int64_t>((key >> 21) & mask) - kBias,
          static_cast<std::int64_t>((key >> 42) & mask) - kBias};
}

/// The grid coordinates of a key (within [-2^20, 2^20) on each axis).
detail::GridIndex grid_index(Key key) {
  const auto [i, j, k] = unpack(key);
  return {static_cast<std::int32_t>(i), static_cast<std::int32_t>(j), static_cast<std::int32_t>(k)};
}

/// Corners and vertices are evaluated in blocks of 2^kBlockShift cells a side, one
/// ImplicitSurface::BoxWalk per block.
constexpr int kBlockShift = 3;

/// Items grouped by block: block b holds order[begin[b] .. begin[b + 1]), in item order.
struct Blocks {
  std::vector<std::uint32_t> order;
  std::vector<std::size_t> begin;
  std::size_t count() const { return begin.size() - 1; }
  std::span<const std::uint32_t> block(std::size_t b) const {
    return std::span(order).subspan(begin[b], begin[b + 1] - begin[b]);
  }
};

/// Items 0 … n − 1 grouped by the block of their grid cell `cell(t)`.
template <class Cell>
Blocks group_by_block(std::size_t n, Cell&& cell) {
  std::vector<std::pair<Key, std::uint32_t>> keyed(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto [i, j, k] = cell(t);
    keyed[t] = {pack(i >> kBlockShift, j >> kBlockShift, k >> kBlockShift), static_cast<std::uint32_t>(t)};
  }
  std::sort(keyed.begin(), keyed.end());
  Blocks blocks;
  blocks.order.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    if (t == 0 || keyed[t].first != keyed[t - 1].first) blocks.begin.push_back(t);
    blocks.order[t] = keyed[t].second;
  }
  blocks.begin.push_back(n);
  return blocks;
}

// For each face direction (−x, +x, −y, +y, −z, +z): the 4 corners on that face, and the step.
constexpr int kFaceCorners[6][4] = {{0, 2, 4, 6}, {1, 3, 5, 7}, {0, 1, 4, 5}, {2, 3, 6, 7}, {0, 1, 2, 3}, {4, 5, 6, 7}};
constexpr int kFaceStep[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

/// Newton steps of a vertex's second projection, where its first one did not settle.
constexpr int kRetrySteps = 8;

/// Newton steps x ← x − f ∇f / |∇f|² towards f = 0 of `s`, its supports found through `near`
/// (null: from the root); returns false if f is undefined or the point wanders farther than
/// `max_move`.
bool project(const ImplicitSurface& s, const ImplicitSurface::BoxWalk* near, Eigen::Vector3d& x, int steps,
             double max_move, double tolerance) {
  const Eigen::Vector3d start = x;
  for (int k = 0; k < steps; ++k) {
    const SurfaceSample q = near != nullptr ? s.sample(x, *near) : s.sample(x);
    if (!q.defined) return false;
    if (std::abs(q.value) <= tolerance) return true;
    const double g2 = q.gradient.squaredNorm();
    if (!(g2 > 0)) return false;
    x -= (q.value / g2) * q.gradient;
    if ((x - start).norm() > max_move) return false;
  }
  const auto v = near != nullptr ? s.value(x, 0, *near) : s.value(x);
  return v && std::abs(*v) <= 10 * tolerance;
}

/// A unit vector orthogonal to n.
Eigen::Vector3d any_tangent(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a = std::abs(n.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(a).normalized();
}

/// The lattice of one walk: cells `h` wide from the tree box's lower corner (`origin`), only
/// those meeting the clip box when there is one.
struct Lattice {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double h = 0;
  const detail::MeshClip* clip = nullptr;
  Eigen::Array3d clip_lo = Eigen::Array3d::Constant(-static_cast<double>(kBias)), clip_hi = -clip_lo;

  Lattice(const Eigen::Vector3d& lower, double cell, const detail::MeshClip* clipped)
      : origin(lower), h(cell), clip(clipped) {
    if (clip == nullptr) return;
    clip_lo = ((clip->box.min - origin) / h).array().floor();
    clip_hi = ((clip->box.max - origin) / h).array().floor();
  }
  Eigen::Vector3d corner(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return Eigen::Vector3d(origin +
                           h * Eigen::Vector3d(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)));
  }
  /// A polygonizer vertex (in cell units) in the surface's coordinates.
  Eigen::Vector3d at(const std::array<float, 3>& p) const {
    return Eigen::Vector3d(origin + h * Eigen::Vector3d(p[0], p[1], p[2]));
  }
  Key cell_of(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d c = ((x - origin) / h).array().floor();
    return pack(static_cast<std::int64_t>(c.x()), static_cast<std::int64_t>(c.y()), static_cast<std::int64_t>(c.z()));
  }
  bool allowed(Key cell) const {
    const auto [i, j, k] = unpack(cell);
    const Eigen::Array3d c(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
    return (c >= clip_lo).all() && (c <= clip_hi).all();
  }
  bool meets(const Sphere& s) const { return clip == nullptr || detail::sphere_meets_box(s, clip->box); }
};

/// What a walk evaluates: f of `surface`, or F of `closed` when given; where f is undefined and
/// `fill`, the same blend with supports `fill_cells` cells wider (`wide`).
struct Field {
  const ImplicitSurface& surface;
  const ClosedSurface* closed;
  ImplicitSurface wide;
  bool fill;
  double min_weight;
};

/// The cell size options ask for, checked, and the walk's memory estimate against the limit:
/// a walk the machine cannot hold is refused before any cell is visited.
double checked_cell_size(const ImplicitSurface& surface, const detail::MeshClip* clip, const MeshOptions& options) {
  const double longest = surface.tree().bbox.extent().maxCoeff();
  const double h =
      options.voxel_size ? *options.voxel_size : (options.resolution > 0 ? longest / options.resolution : 0.0);
  if (!(longest > 0) && !options.voxel_size)
    throw OptionError("the surface has no extent (all input points coincide): there is nothing to mesh");
  if (!(h > 0) || !std::isfinite(h))
    throw OptionError("the mesh cell size must be positive (MeshOptions::voxel_size, or resolution)");
  if (!(options.min_weight >= 0) || !std::isfinite(options.min_weight))
    throw OptionError("mesh min_weight must be >= 0");
  if (longest / h > 500000) throw OptionError("mesh grid too fine: more than 500000 cells along the bounding box");
  if (!(options.fill_cells >= 0) || !std::isfinite(options.fill_cells))
    throw OptionError("mesh fill_cells must be >= 0");
  const MeshEstimate cost = detail::estimate_mesh_within(surface, h, clip != nullptr ? &clip->box : nullptr);
  const std::uint64_t limit = options.memory_limit > 0 ? options.memory_limit : detail::available_memory();
  if (limit > 0 && cost.bytes > static_cast<double>(limit))
    throw OptionError(
        fmt::format("the mesh grid of cell size {:.4g} would cross about {:.3g} million surface cells and take about "
                    "{:.1f} GiB, more than {} ({:.1f} GiB): use a coarser voxel_size or resolution",
                    h, cost.surface_cells / 1e6, cost.bytes / double(1ull << 30),
                    options.memory_limit > 0 ? "the memory limit" : "the machine has free",
                    static_cast<double>(limit) / double(1ull << 30)));
  return h;
}

/// The points a proxy's seed is projected from, in steps of r/3 along its two tangents: the
/// centre first.
constexpr std::array<std::array<int, 2>, 9> kSeedSteps = {
    {{0, 0}, {-1, -1}, {-1, 0}, {-1, 1}, {0, -1}, {0, 1}, {1, -1}, {1, 0}, {1, 1}}};

/// The cells the walk starts from, sorted: around a point of every blended proxy projected onto
/// f = 0 (its centre, or where that projection fails, one of the points at ±r/3 along two
/// tangents), and the clip's seed points' cells.
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
  const detail::MeshClip* clip = lattice.clip;
  if (clip != nullptr && clip->seeds != nullptr)
    for (Eigen::Index p = 0; p < clip->seeds->rows(); ++p)
      frontier.push_back(lattice.cell_of(clip->seeds->row(p).transpose()));
  std::sort(frontier.begin(), frontier.end());
  frontier.erase(std::unique(frontier.begin(), frontier.end()), frontier.end());
  if (clip != nullptr) std::erase_if(frontier, [&](Key cell) { return !lattice.allowed(cell); });
  return frontier;
}

/// The field at `corners` (NaN where undefined), evaluated block by block, each block's walk of
/// the tree done once.
std::vector<float> corner_values(const Field& field, const Lattice& lattice,
                                 const std::vector<detail::GridIndex>& corners) {
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

/// What the walk found: the cells the surface crosses (with their corners' values), in key
/// order (by k, then j, then i), and how many corners it evaluated.
struct Walk {
  std::vector<detail::SurfaceCell> cells;
  std::uint64_t corners = 0;
};

/// Breadth-first walk from `frontier` over the cells whose corners' values change sign, into
/// each neighbour across a face that does.
Walk walk_surface(const Field& field, const Lattice& lattice, std::vector<Key> frontier,
                  detail::ProgressReporter& reporter) {
  detail::WalkGrid grid;  // corners queued (with f, NaN where undefined) and cells visited
  for (Key cell : frontier) grid.visit(grid_index(cell));
  Walk out;
  std::vector<detail::GridIndex> todo;  // corners to evaluate
  std::uint64_t reported = 0;
  while (!frontier.empty()) {
    reporter.check();
    todo.clear();
    for (Key cell : frontier) {
      const detail::GridIndex g = grid_index(cell);
      for (const auto& c : detail::kCellCorner) {
        const detail::GridIndex corner = {g[0] + c[0], g[1] + c[1], g[2] + c[2]};
        if (grid.queue(corner)) todo.push_back(corner);
      }
    }
    const std::vector<float> values = corner_values(field, lattice, todo);
    for (std::size_t t = 0; t < todo.size(); ++t) grid.set_value(todo[t], values[t]);

    std::vector<Key> next;
    for (Key cell : frontier) {
      const auto [i, j, k] = unpack(cell);
      detail::SurfaceCell here{grid_index(cell), {}};
      grid.values(here);
      const auto& v = here.values;
      bool defined = true, any_neg = false, any_pos = false;
      for (const float value : v) {
        defined = defined && !std::isnan(value);
        (value < 0 ? any_neg : any_pos) = true;
      }
      if (!defined || !any_neg || !any_pos) continue;
      out.cells.push_back(here);
      for (int f = 0; f < 6; ++f) {
        bool neg = false, pos = false;
        for (int c : kFaceCorners[f]) (v[static_cast<std::size_t>(c)] < 0 ? neg : pos) = true;
        if (!(neg && pos)) continue;
        const Key nb = pack(i + kFaceStep[f][0], j + kFaceStep[f][1], k + kFaceStep[f][2]);
        if ((lattice.clip == nullptr || lattice.allowed(nb)) && grid.visit(grid_index(nb))) next.push_back(nb);
      }
    }
    std::sort(next.begin(), next.end());
    frontier = std::move(next);
    // The walk's length is unknown in advance: report the share of cells already settled.
    const double done =
        static_cast<double>(out.cells.size()) / static_cast<double>(out.cells.size() + frontier.size() + 1);
    const auto permille = static_cast<std::uint64_t>(900 * done);
    if (permille > reported) reporter.advance(permille - reported), reported = permille;
  }
  std::sort(out.cells.begin(), out.cells.end(), [](const detail::SurfaceCell& a, const detail::SurfaceCell& b) {
    return std::tie(a.corner[2], a.corner[1], a.corner[0]) < std::tie(b.corner[2], b.corner[1], b.corner[0]);
  });
  out.corners = grid.queued();
  return out;
}

/// The polygons' vertices projected onto f = 0 (kept where the projection fails; a closed
/// surface's filled vertices stay where F's cells put them), with normals from the gradient.
TriangleMesh placed_vertices(const detail::CellPolygons& polygons, const Field& field, const Lattice& lattice,
                             const MeshOptions& options) {
  const double h = lattice.h;
  TriangleMesh mesh;
  const auto nv = static_cast<Eigen::Index>(polygons.vertices.size());
  mesh.vertices.resize(nv, 3);
  mesh.normals.resize(nv, 3);
  const Blocks blocks = group_by_block(polygons.vertices.size(), [&](std::size_t v) {
    const auto& p = polygons.vertices[v];
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(p[0])),
                                       static_cast<std::int64_t>(std::floor(p[1])),
                                       static_cast<std::int64_t>(std::floor(p[2]))};
  });
  const ImplicitSurface& surface = field.surface;
  const ClosedSurface* closed = field.closed;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.count()), [&](const auto& r) {
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      // The block's vertices and as far as their projections may move.
      BoundingBox box;
      for (const std::uint32_t v : blocks.block(b)) box.extend(lattice.at(polygons.vertices[v]));
      box.min.array() -= h, box.max.array() += h;
      const ImplicitSurface::BoxWalk near(surface, box);
      std::optional<ImplicitSurface::BoxWalk> wide_near;  // built when a vertex needs the fill
      const auto wide_walk = [&]() -> const ImplicitSurface::BoxWalk& {
        return wide_near ? *wide_near : wide_near.emplace(field.wide, box);
      };
      for (const std::uint32_t v : blocks.block(b)) {
        Eigen::Vector3d x = lattice.at(polygons.vertices[v]);
        Eigen::Vector3d y = x;
        // A closed surface's filled vertex (where F is the fill, or fades into it) stays where
        // F's cells put it: projecting it onto f = 0 would leave F's zero set.
        const bool filled = closed != nullptr && closed->filled(x);
        if (options.newton_steps > 0 && !filled) {
          // Where those steps do not settle (beside a crease, where the blended gradient leans
          // between the faces), again with more; the block's walk covers a move of a cell.
          if (project(surface, &near, y, options.newton_steps, h, 1e-6 * h) ||
              project(surface, &near, y = x, std::max(options.newton_steps, kRetrySteps), h, 1e-6 * h)) {
            if (closed == nullptr || !closed->filled(y)) x = y;  // onto f = 0, unless F is not f there
          } else if (field.fill && project(field.wide, &wide_walk(), y = x, options.newton_steps, h, 1e-6 * h)) {
            x = y;
          }
        }
        SurfaceSample s = surface.sample(x, near);
        if (!s.defined && field.fill) s = field.wide.sample(x, wide_walk());
        if (filled || (!s.defined && closed != nullptr)) {
          // F's gradient by central differences over half a cell.
          const double d = h / 2;
          for (int a = 0; a < 3; ++a) {
            const Eigen::Vector3d e = d * Eigen::Vector3d::Unit(a);
            s.gradient(a) = (closed->value(x + e) - closed->value(x - e)) / (2 * d);
          }
        }
        mesh.vertices.row(v) = x.transpose();
        const double g = s.gradient.norm();
        mesh.normals.row(v) = (g > 0 ? Eigen::Vector3d(s.gradient / g) : Eigen::Vector3d::UnitZ()).transpose();
      }
    }
  });
  return mesh;
}

/// The polygons' triangles on `mesh`'s vertices, then its unreferenced vertices dropped (order
/// kept): quads split along the shorter diagonal, degenerate triangles dropped. The polygons
/// face positive f (outside), as ours. Vertices the projection put at the same place (two cell
/// edges' crossings projected onto a crease's edge line) are one vertex: the triangle between
/// them collapses with its edge, where dropping it alone would leave a hole.
TriangleMesh with_triangles(TriangleMesh mesh, const detail::CellPolygons& polygons, double h) {
  const std::vector<std::int32_t> same = detail::position_ids(mesh.vertices);
  std::vector<std::array<std::int32_t, 3>> tris;
  auto add = [&](std::int32_t a, std::int32_t b, std::int32_t c) {
    a = same[static_cast<std::size_t>(a)], b = same[static_cast<std::size_t>(b)], c = same[static_cast<std::size_t>(c)];
    if (a == b || b == c || a == c) return;
    const Eigen::Vector3d pa = mesh.vertices.row(a).transpose(), pb = mesh.vertices.row(b).transpose(),
                          pc = mesh.vertices.row(c).transpose();
    if ((pb - pa).cross(pc - pa).norm() <= 1e-12 * h * h) return;
    tris.push_back({a, b, c});
  };
  for (const auto& quad : polygons.quads) {
    const auto a = static_cast<std::int32_t>(quad[0]), b = static_cast<std::int32_t>(quad[1]),
               c = static_cast<std::int32_t>(quad[2]), d = static_cast<std::int32_t>(quad[3]);
    const double ac = (mesh.vertices.row(a) - mesh.vertices.row(c)).squaredNorm();
    const double bd = (mesh.vertices.row(b) - mesh.vertices.row(d)).squaredNorm();
    if (ac <= bd)
      add(a, b, c), add(a, c, d);
    else
      add(a, b, d), add(b, c, d);
  }
  for (const auto& tri : polygons.triangles)
    add(static_cast<std::int32_t>(tri[0]), static_cast<std::int32_t>(tri[1]), static_cast<std::int32_t>(tri[2]));
  mesh.triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) mesh.triangles(static_cast<Eigen::Index>(t), k) = tris[t][static_cast<std::size_t>(k)];
  return detail::without_unused_vertices(mesh);
}

/// extract_mesh() of `surface`, or of `closed` (whose surface() it is) when given: then F is
/// defined everywhere and the walk follows its zero set across the holes. The stages: the cell
/// size and the memory guard, the seeds, the walk, the polygons, the vertices, the triangles.
TriangleMesh extract(const ImplicitSurface& surface, const ClosedSurface* closed, const detail::MeshClip* clip,
                     const MeshOptions& options, MeshReport* report, const ProgressCallback& progress) {
  const double h = checked_cell_size(surface, clip, options);
  const Lattice lattice(surface.tree().bbox.min, h, clip);
  const Field field{surface, closed, surface.with_margin(surface.margin() + options.fill_cells * h),
                    options.fill_cells > 0 && closed == nullptr, options.min_weight};
  detail::ProgressReporter reporter(progress, "meshing", 1000);
  const Walk walk = walk_surface(field, lattice, seed_cells(surface, lattice), reporter);
  // The grid is relative to the lattice's origin: the polygonizer's float vertices keep full
  // precision for models far from the world origin (coordinates near 1e8 would keep only ~8 units).
  const detail::CellPolygons polygons = detail::polygonize_cells(walk.cells, static_cast<float>(3 * h));
  TriangleMesh mesh = with_triangles(placed_vertices(polygons, field, lattice, options), polygons, h);
  reporter.finish();
  if (report != nullptr) {
    report->voxel_size = h;
    report->evaluated_corners = walk.corners;
    report->surface_cells = walk.cells.size();
  }
  return mesh;
}

}  // namespace

TriangleMesh extract_mesh(const ImplicitSurface& surface, const MeshOptions& options, MeshReport* report,
                          const ProgressCallback& progress) {
  return extract(surface, nullptr, nullptr, options, report, progress);
}

TriangleMesh extract_mesh(const ClosedSurface& closed, const MeshOptions& options, MeshReport* report,
                          const ProgressCallback& progress) {
  return extract(closed.surface(), &closed, nullptr, options, report, progress);
}

TriangleMesh detail::extract_clipped(const ImplicitSurface& surface, const MeshClip& clip, const MeshOptions& options,
                                     MeshReport* report, const ProgressCallback& progress) {
  if (clip.box.empty()) throw OptionError("the mesh clip box is empty");
  return extract(surface, nullptr, &clip, options, report, progress);
}

}  // namespace clustersurf
