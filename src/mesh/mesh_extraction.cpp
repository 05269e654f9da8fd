// Mesh extraction: the cell size and memory guard, the walk (surface_walk), polygonization
// (cell_polygonizer: OpenVDB), the vertices projected onto f = 0 and the triangles.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/surface/box_walk.hpp>

#include "core/progress_reporter.hpp"
#include "core/system_memory.hpp"
#include "mesh/cell_polygonizer.hpp"
#include "mesh/mesh_subset.hpp"
#include "mesh/surface_walk.hpp"
#include "spatial/position_ids.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace clustersurf {

namespace {

using detail::Blocks;
using detail::Field;
using detail::group_by_block;
using detail::Lattice;
using detail::project;

/// The most cells the lattice spans along the surface's box (its keys hold 21 bits per axis,
/// with room around the box for the walk).
constexpr double kMaxCellsAlong = 500000;

/// Newton steps of a vertex's second projection, where its first one did not settle.
constexpr int kRetrySteps = 8;

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
  if (longest / h > kMaxCellsAlong)
    throw OptionError(fmt::format(
        "the mesh grid of cell size {:.4g} would span {:.3g} million cells along the surface's longest side ({:.4g}), "
        "more than the lattice holds ({:.3g} million): the points reach far beyond the surface's detail (parts far "
        "apart, or stray points that are not isolated); remove the far points or use a coarser voxel_size or "
        "resolution",
        h, longest / h / 1e6, longest, kMaxCellsAlong / 1e6));
  if (!(options.fill_cells >= 0) || !std::isfinite(options.fill_cells))
    throw OptionError("mesh fill_cells must be >= 0");
  if (options.fill_cell && (!(*options.fill_cell > 0) || !std::isfinite(*options.fill_cell)))
    throw OptionError("mesh fill_cell must be positive");
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
        SurfaceSample at_y;  // f at y, where the projection settled
        bool settled = false;
        if (options.newton_steps > 0 && !filled) {
          // Where those steps do not settle (beside a crease, where the blended gradient leans
          // between the faces), again with more; the block's walk covers a move of a cell.
          if (project(surface, &near, y, options.newton_steps, h, 1e-6 * h, &at_y) ||
              project(surface, &near, y = x, std::max(options.newton_steps, kRetrySteps), h, 1e-6 * h, &at_y)) {
            // Onto f = 0, unless F is not f there.
            if (closed == nullptr || !closed->filled(y)) x = y, settled = at_y.defined;
          } else if (field.fill && project(field.wide, &wide_walk(), y = x, options.newton_steps, h, 1e-6 * h)) {
            x = y;
          }
        }
        SurfaceSample s = settled ? at_y : surface.sample(x, near);
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

/// How many triangles with_triangles() makes of `polygons`: two of each quad, then the triangles.
std::size_t triangle_slots(const detail::CellPolygons& polygons) {
  return 2 * polygons.quads.size() + polygons.triangles.size();
}

/// Triangle `slot` of `polygons` (triangle_slots()' order), each quad split along its shorter
/// diagonal between `vertices`.
std::array<std::uint32_t, 3> polygon_triangle(const detail::CellPolygons& polygons, const Points& vertices,
                                              std::size_t slot) {
  const std::size_t quads = polygons.quads.size();
  if (slot >= 2 * quads) return polygons.triangles[slot - 2 * quads];
  const auto& [a, b, c, d] = polygons.quads[slot / 2];
  if ((vertices.row(a) - vertices.row(c)).squaredNorm() <= (vertices.row(b) - vertices.row(d)).squaredNorm())
    return slot % 2 == 0 ? std::array{a, b, c} : std::array{a, c, d};
  return slot % 2 == 0 ? std::array{a, b, d} : std::array{b, c, d};
}

/// Rounds of unfold().
constexpr int kUnfoldRounds = 3;

/// Where the projection folded the mesh (a triangle, as with_triangles() will cut the polygons,
/// whose projected corners face against their normals: a vertex pushed past its neighbours,
/// where the blend bends sharply within a cell), the triangle's vertices go back where the
/// polygonizer put them, with f's normal there; until no triangle is folded, at most
/// kUnfoldRounds times. Returns how many vertices went back.
std::size_t unfold(TriangleMesh& mesh, const detail::CellPolygons& polygons, const Lattice& lattice,
                   const ImplicitSurface& surface) {
  const auto at = [&](std::uint32_t v) -> Eigen::Vector3d { return mesh.vertices.row(v).transpose(); };
  const auto normal = [&](std::uint32_t v) -> Eigen::Vector3d { return mesh.normals.row(v).transpose(); };
  std::vector<std::uint8_t> placed_back(polygons.vertices.size(), 0);
  std::size_t moved = 0;
  std::vector<std::uint8_t> turned(triangle_slots(polygons));
  for (int round = 0; round < kUnfoldRounds; ++round) {
    // Each of the triangles with_triangles() will make tested in parallel; the corners of those
    // folded, not placed back before, listed after.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, turned.size(), 4096), [&](const auto& r) {
      for (std::size_t slot = r.begin(); slot != r.end(); ++slot) {
        const auto [a, b, c] = polygon_triangle(polygons, mesh.vertices, slot);
        const Eigen::Vector3d face = (at(b) - at(a)).cross(at(c) - at(a));
        turned[slot] = face.dot(normal(a) + normal(b) + normal(c)) < 0;
      }
    });
    std::vector<std::uint32_t> folded;
    for (std::size_t slot = 0; slot < turned.size(); ++slot)
      if (turned[slot] != 0)
        for (const std::uint32_t v : polygon_triangle(polygons, mesh.vertices, slot))
          if (!placed_back[v]) folded.push_back(v);
    std::sort(folded.begin(), folded.end());
    folded.erase(std::unique(folded.begin(), folded.end()), folded.end());
    if (folded.empty()) break;
    for (const std::uint32_t v : folded) {
      const Eigen::Vector3d x = lattice.at(polygons.vertices[v]);
      const SurfaceSample s = surface.sample(x);
      mesh.vertices.row(v) = x.transpose();
      const double g = s.gradient.norm();
      if (s.defined && g > 0) mesh.normals.row(v) = (s.gradient / g).transpose();
      placed_back[v] = 1;
    }
    moved += folded.size();
  }
  return moved;
}

/// The polygons' triangles on `mesh`'s vertices, then its unreferenced vertices dropped (order
/// kept): quads split along the shorter diagonal, degenerate triangles dropped. The polygons
/// face positive f (outside), as ours. Vertices the projection put at the same place (two cell
/// edges' crossings projected onto a crease's edge line) are one vertex: the triangle between
/// them collapses with its edge, where dropping it alone would leave a hole.
TriangleMesh with_triangles(TriangleMesh mesh, const detail::CellPolygons& polygons, double h) {
  const std::vector<std::int32_t> same = detail::position_ids(mesh.vertices);
  // Each polygon's triangles in slots of their own (triangle_slots()), made in parallel; those
  // kept, in slot order.
  std::vector<std::array<std::int32_t, 3>> slots(triangle_slots(polygons));
  std::vector<std::uint8_t> kept(slots.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, slots.size(), 4096), [&](const auto& r) {
    for (std::size_t slot = r.begin(); slot != r.end(); ++slot) {
      std::array<std::int32_t, 3> t;
      const auto corners = polygon_triangle(polygons, mesh.vertices, slot);
      for (std::size_t k = 0; k < 3; ++k) t[k] = same[corners[k]];
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      const Eigen::Vector3d pa = mesh.vertices.row(t[0]).transpose(), pb = mesh.vertices.row(t[1]).transpose(),
                            pc = mesh.vertices.row(t[2]).transpose();
      if ((pb - pa).cross(pc - pa).norm() <= 1e-12 * h * h) continue;
      slots[slot] = t;
      kept[slot] = 1;
    }
  });
  mesh.triangles.resize(std::count(kept.begin(), kept.end(), std::uint8_t{1}), 3);
  Eigen::Index row = 0;
  for (std::size_t slot = 0; slot < slots.size(); ++slot)
    if (kept[slot] != 0) {
      for (int k = 0; k < 3; ++k) mesh.triangles(row, k) = slots[slot][static_cast<std::size_t>(k)];
      ++row;
    }
  return detail::without_unused_vertices(mesh);
}

/// extract_mesh() of `surface`, or of `closed` (whose surface() it is) when given: then F is
/// defined everywhere and the walk follows its zero set across the holes. The stages: the cell
/// size and the memory guard, the seeds, the walk, the polygons, the vertices, the triangles.
TriangleMesh extract(const ImplicitSurface& surface, const ClosedSurface* closed, const detail::MeshClip* clip,
                     const MeshOptions& options, MeshReport* report, const ProgressCallback& progress) {
  const double h = checked_cell_size(surface, clip, options);
  const Lattice lattice(surface.tree().bbox.min, h, clip);
  const Field field{surface, closed, surface.with_margin(surface.margin() + fill_band(options, h)),
                    options.fill_cells > 0 && closed == nullptr, options.min_weight};
  detail::ProgressReporter reporter(progress, "meshing", 1000);
  const detail::Walk walk = detail::walk_surface(field, lattice, detail::seed_cells(surface, lattice), reporter);
  // The grid is relative to the lattice's origin: the polygonizer's float vertices keep full
  // precision for models far from the world origin (coordinates near 1e8 would keep only ~8 units).
  const detail::CellPolygons polygons = detail::polygonize_cells(walk.cells, static_cast<float>(3 * h));
  TriangleMesh placed = placed_vertices(polygons, field, lattice, options);
  if (closed == nullptr && options.newton_steps > 0) unfold(placed, polygons, lattice, surface);
  TriangleMesh mesh = with_triangles(std::move(placed), polygons, h);
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
