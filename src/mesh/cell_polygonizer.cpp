// OpenVDB's VolumeToMesh over the surface cells found by mesh extraction.

#include "mesh/cell_polygonizer.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

namespace clustersurf::detail {

CellPolygons polygonize_cells(std::span<const SurfaceCell> cells, float outside) {
  openvdb::initialize();
  // The identity transform: index space is grid units.
  auto grid = openvdb::FloatGrid::create(outside);
  auto mask = openvdb::BoolGrid::create(false);
  {
    auto acc = grid->getAccessor();
    auto macc = mask->getAccessor();
    for (const SurfaceCell& cell : cells) {
      const auto [i, j, k] = cell.corner;
      macc.setValueOn(openvdb::Coord(i, j, k), true);
      for (int c = 0; c < 8; ++c)
        acc.setValueOn(openvdb::Coord(i + kCellCorner[c][0], j + kCellCorner[c][1], k + kCellCorner[c][2]),
                       cell.values[static_cast<std::size_t>(c)]);
    }
  }
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
