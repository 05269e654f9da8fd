// One tile of a tiled mesh: the lattice around a region, meshed, trimmed and cut to the region.

#include "tiling/tiles.hpp"
#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>
#include <clustersurf/mesh/vertex_refit.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include "mesh/clipped_extraction.hpp"
#include "mesh/mesh_subset.hpp"
#include "spatial/spatial_order.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace clustersurf {

namespace {

/// Which triangles of `mesh` region `region` owns: those whose centroid lies in its cell (every
/// tile computes the same centroid of the same triangle, and exactly one cell holds it).
std::vector<std::uint8_t> owned_triangles(const TriangleMesh& mesh, const RegionPlan& plan, std::int32_t region) {
  std::vector<std::uint8_t> owned(static_cast<std::size_t>(mesh.triangles.rows()));
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d c = (mesh.vertices.row(mesh.triangles(t, 0)) + mesh.vertices.row(mesh.triangles(t, 1)) +
                               mesh.vertices.row(mesh.triangles(t, 2)))
                                  .transpose() /
                              3.0;
    owned[static_cast<std::size_t>(t)] = plan.region_of(c) == region;
  }
  return owned;
}

/// The votes of the first `own` rows of `data` (the region's own points) for their nearest
/// vertex of `mesh`.
Eigen::VectorXf vertex_votes(const TriangleMesh& mesh, const Points& data, std::size_t own) {
  Eigen::VectorXf votes = Eigen::VectorXf::Zero(mesh.vertices.rows());
  if (mesh.vertices.rows() == 0 || own == 0) return votes;
  const KdTree vertices(mesh.vertices);
  std::vector<std::uint32_t> nearest(own);
  std::vector<Eigen::Index> rows(own);
  std::iota(rows.begin(), rows.end(), Eigen::Index{0});
  const std::vector<std::uint32_t> order = detail::spatial_order(data, rows);  // queries in spatial order
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, own, 1024), [&](const auto& r) {
    std::vector<Neighbor> nb;
    for (std::size_t o = r.begin(); o != r.end(); ++o) {
      vertices.knn(data.row(static_cast<Eigen::Index>(order[o])).transpose(), 1, nb);
      nearest[order[o]] = nb[0].index;
    }
  });
  for (const std::uint32_t v : nearest) votes(v) += 1;
  return votes;
}

/// The squared distance from x to box b (0 inside it).
double squared_distance(const Eigen::Vector3d& x, const BoundingBox& b) {
  return (b.min - x).cwiseMax(x - b.max).cwiseMax(0.0).squaredNorm();
}

/// How many triangles `owned` (owned_triangles()) marks.
std::size_t count_owned(const std::vector<std::uint8_t>& owned) {
  return static_cast<std::size_t>(std::count(owned.begin(), owned.end(), std::uint8_t{1}));
}

}  // namespace

Eigen::VectorXf near_other_regions(const TriangleMesh& mesh, const RegionPlan& plan, double distance) {
  // Per region, the others whose cell lies within `distance` of its cell.
  const std::size_t n = plan.regions();
  std::vector<std::vector<std::int32_t>> near(n);
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) {
      BoundingBox grown = plan.region_box(static_cast<std::int32_t>(b));
      grown.min.array() -= distance;
      grown.max.array() += distance;
      const BoundingBox& cell = plan.region_box(static_cast<std::int32_t>(a));
      if (a != b && (cell.min.array() <= grown.max.array()).all() && (grown.min.array() <= cell.max.array()).all())
        near[a].push_back(static_cast<std::int32_t>(b));
    }
  Eigen::VectorXf out = Eigen::VectorXf::Zero(mesh.vertices.rows());
  const double d2 = distance * distance;
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, mesh.vertices.rows(), 4096), [&](const auto& r) {
    for (Eigen::Index v = r.begin(); v != r.end(); ++v) {
      const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
      for (const std::int32_t other : near[static_cast<std::size_t>(plan.region_of(x))])
        if (squared_distance(x, plan.region_box(other)) < d2) {
          out(v) = 1;
          break;
        }
    }
  });
  return out;
}

MeshTile mesh_tile(const ImplicitSurface& surface, const RegionPlan& plan, std::int32_t region_index,
                   const RegionCloud& region, const MeshOptions& grid, const SurfaceMeshOptions& meshing,
                   const ProgressCallback& progress) {
  if (region_index < 0 || static_cast<std::size_t>(region_index) >= plan.regions())
    throw OptionError("region " + std::to_string(region_index) + " is not in the plan");
  if (!grid.voxel_size || !(*grid.voxel_size > 0) || !std::isfinite(*grid.voxel_size))
    throw OptionError("a tile needs the lattice's cell size (a positive voxel size)");
  if (!region.outliers.empty() && region.outliers.size() != static_cast<std::size_t>(region.points.size()))
    throw OptionError("the region's outlier marks do not match its points");
  MeshTile tile;
  tile.region = region_index;
  if (region.own == 0) return tile;
  const double h = *grid.voxel_size;
  // The region's points but its outliers: the seeds of the walk and the data of the trim.
  std::vector<Eigen::Index> rows;
  for (Eigen::Index r = 0; r < region.points.size(); ++r)
    if (region.outliers.empty() || !region.outliers[static_cast<std::size_t>(r)]) rows.push_back(r);
  const Points data = region.points.positions(rows, Eigen::all);
  std::size_t own_data = 0;  // rows of `data` that are the region's own
  while (own_data < rows.size() && rows[own_data] < static_cast<Eigen::Index>(region.own)) ++own_data;

  detail::MeshClip clip;
  clip.box = plan.region_box(region_index);
  clip.box.min.array() -= kTileMarginCells * h;
  clip.box.max.array() += kTileMarginCells * h;
  clip.seeds = &data;
  TriangleMesh mesh = detail::extract_clipped(surface, clip, grid, &tile.grid, progress);

  // The reach trim over the region's data; the fragment test waits for the whole mesh.
  const KdTree index(data);
  TrimOptions reach = meshing.trim;
  reach.min_component_points = 0;
  reach.close_pinholes = false;
  reach.typical_spread = typical_spread(surface.tree());  // as in core
  mesh = trim_to_points(mesh, index, reach);

  // Flat blocks merged as in core, but near another region's cell, where both tiles keep the
  // lattice's triangles.
  tile.coarsening.triangles_before = count_owned(owned_triangles(mesh, plan, region_index));
  const Eigen::VectorXf fixed = near_other_regions(mesh, plan, kTileFixedCells * h);
  mesh = coarsen_mesh(mesh, surface.tree().bbox.min, h, coarsening_scale(surface.tree()), meshing.coarsening,
                      &tile.coarsening, std::span<const float>(fixed.data(), static_cast<std::size_t>(fixed.size())));

  // The triangles the region owns, and the votes of its own points for their nearest vertex of
  // the coarse mesh (kept whether or not the region owns a triangle there: the neighbour that
  // does gets them when the tiles are joined).
  const std::vector<std::uint8_t> owned = owned_triangles(mesh, plan, region_index);
  tile.coarsening.triangles_after = count_owned(owned);
  tile.coarsening.vertices_before = tile.coarsening.vertices_after = 0;  // tiles share their border vertices
  const Eigen::VectorXf votes = vertex_votes(mesh, data, own_data);
  // Refitted after the votes, as the whole mesh is after its trim's fragment test.
  refit_vertices(mesh, index, surface, meshing.refit);
  // Keep the owned triangles and every voted vertex (a voted vertex no owned triangle uses
  // joins its owner's copy, or goes with its own triangles when the join drops them).
  Triangles kept(mesh.triangles.rows(), 3);
  Eigen::Index count = 0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    if (owned[static_cast<std::size_t>(t)]) kept.row(count++) = mesh.triangles.row(t);
  kept.conservativeResize(count, 3);
  std::vector<std::uint8_t> used(static_cast<std::size_t>(mesh.vertices.rows()), 0);
  for (Eigen::Index t = 0; t < kept.rows(); ++t)
    for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(kept(t, k))] = 1;
  for (Eigen::Index v = 0; v < votes.size(); ++v) used[static_cast<std::size_t>(v)] |= votes(v) > 0;
  std::vector<Eigen::Index> keep_rows, remap(static_cast<std::size_t>(mesh.vertices.rows()), -1);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    if (used[static_cast<std::size_t>(v)])
      remap[static_cast<std::size_t>(v)] = static_cast<Eigen::Index>(keep_rows.size()), keep_rows.push_back(v);
  tile.mesh.vertices = mesh.vertices(keep_rows, Eigen::all);
  if (mesh.normals.rows() == mesh.vertices.rows()) tile.mesh.normals = mesh.normals(keep_rows, Eigen::all);
  tile.mesh.triangles.resize(kept.rows(), 3);
  for (Eigen::Index t = 0; t < kept.rows(); ++t)
    for (int k = 0; k < 3; ++k)
      tile.mesh.triangles(t, k) = static_cast<std::int32_t>(remap[static_cast<std::size_t>(kept(t, k))]);
  if (meshing.coloring == MeshColoring::FromInput && region.points.has_colors())
    tile.mesh.colors = colors_from_points(tile.mesh, index, region.points.colors(rows, Eigen::all));
  tile.mesh.attributes.push_back({"votes", votes(keep_rows)});
  tile.mesh.origin = surface.tree().origin;
  tile.mesh.up = surface.tree().up;
  return tile;
}

std::vector<std::int32_t> tile_regions(const RegionPlan& plan, const RegionMerge& merge, std::int32_t region_index,
                                       const MeshOptions& grid) {
  if (region_index < 0 || static_cast<std::size_t>(region_index) >= plan.regions())
    throw OptionError("region " + std::to_string(region_index) + " is not in the plan");
  if (merge.reach.size() != plan.regions()) throw OptionError("the merge record does not match the plan");
  if (!grid.voxel_size || !(*grid.voxel_size > 0))
    throw OptionError("a tile needs the lattice's cell size (a positive voxel size)");
  const double h = *grid.voxel_size;
  // Every leaf's support centre lies in its region's cell (the centroid of its own points), so
  // its support, grown by the fill band, lies in the cell grown by the region's reach and band.
  const auto influence = [&](std::size_t r) {
    BoundingBox b = plan.region_box(static_cast<std::int32_t>(r));
    b.min.array() -= merge.reach[r] + fill_band(grid, h);
    b.max.array() += merge.reach[r] + fill_band(grid, h);
    return b;
  };
  const auto meets = [](const BoundingBox& a, const BoundingBox& b) {
    return (a.min.array() <= b.max.array()).all() && (b.min.array() <= a.max.array()).all();
  };
  // The tile's cells, their far corners and a vertex's projection (a cell more); then the
  // supports that seed the walk, whose seeds are projected within about their radius.
  BoundingBox cells = plan.region_box(region_index);
  cells.min.array() -= (kTileMarginCells + 2) * h;
  cells.max.array() += (kTileMarginCells + 2) * h;
  double seed_reach = 0;
  for (std::size_t r = 0; r < plan.regions(); ++r)
    if (merge.reach[r] > 0 && meets(influence(r), cells)) seed_reach = std::max(seed_reach, merge.reach[r]);
  BoundingBox evaluated = cells;
  evaluated.min.array() -= 3 * seed_reach;
  evaluated.max.array() += 3 * seed_reach;
  std::vector<std::int32_t> out;
  for (std::size_t r = 0; r < plan.regions(); ++r)
    if (merge.reach[r] > 0 && meets(influence(r), evaluated)) out.push_back(static_cast<std::int32_t>(r));
  return out;
}

}  // namespace clustersurf
