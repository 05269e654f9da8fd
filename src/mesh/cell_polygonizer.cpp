// OpenVDB's VolumeToMesh over the surface cells found by mesh extraction.

#include "mesh/cell_polygonizer.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace clustersurf::detail {

namespace {

/// The cells' corner values and the cells as a mask, filled by parts in parallel and merged:
/// neighbouring cells share corners with equal values, so every split gives the same grids.
struct CellGrids {
  std::span<const SurfaceCell> cells;
  openvdb::FloatGrid::Ptr values;
  openvdb::BoolGrid::Ptr mask = openvdb::BoolGrid::create(false);

  CellGrids(std::span<const SurfaceCell> all, float outside)
      : cells(all), values(openvdb::FloatGrid::create(outside)) {}
  CellGrids(CellGrids& other, tbb::split)
      : cells(other.cells), values(openvdb::FloatGrid::create(other.values->background())) {}

  void operator()(const tbb::blocked_range<std::size_t>& r) {
    auto acc = values->getAccessor();
    auto macc = mask->getAccessor();
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      const auto [i, j, k] = cells[t].corner;
      macc.setValueOn(openvdb::Coord(i, j, k), true);
      for (int c = 0; c < 8; ++c)
        acc.setValueOn(openvdb::Coord(i + kCellCorner[c][0], j + kCellCorner[c][1], k + kCellCorner[c][2]),
                       cells[t].values[static_cast<std::size_t>(c)]);
    }
  }
  void join(CellGrids& other) {
    values->tree().merge(other.values->tree());
    mask->tree().merge(other.mask->tree());
  }
};

}  // namespace

CellPolygons polygonize_cells(std::span<const SurfaceCell> cells, float outside) {
  openvdb::initialize();
  // The identity transform: index space is grid units.
  CellGrids filled(cells, outside);
  tbb::parallel_reduce(tbb::blocked_range<std::size_t>(0, cells.size(), 1 << 16), filled);
  const openvdb::FloatGrid::Ptr grid = filled.values;
  const openvdb::BoolGrid::Ptr mask = filled.mask;
  openvdb::tools::VolumeToMesh mesher(0.0, 0.0);
  mesher.setSurfaceMask(mask, false);
  mesher(*grid);

  CellPolygons out;
  const auto& points = mesher.pointList();
  out.vertices.resize(mesher.pointListSize());
  for (std::size_t v = 0; v < out.vertices.size(); ++v) out.vertices[v] = {points[v].x(), points[v].y(), points[v].z()};
  const auto& pools = mesher.polygonPoolList();
  for (std::size_t n = 0; n < mesher.polygonPoolListSize(); ++n) {
    const auto& pool = pools[n];
    for (std::size_t q = 0; q < pool.numQuads(); ++q) {
      const auto& quad = pool.quad(q);
      out.quads.push_back({quad[0], quad[1], quad[2], quad[3]});
    }
    for (std::size_t t = 0; t < pool.numTriangles(); ++t) {
      const auto& tri = pool.triangle(t);
      out.triangles.push_back({tri[0], tri[1], tri[2]});
    }
  }
  return out;
}

}  // namespace clustersurf::detail
