#pragma once
// The polygonization step of mesh extraction: OpenVDB's VolumeToMesh over the cells the
// surface walk found. Kept apart from the walk so that OpenVDB (slow to compile) is confined to
// this file and walk_grid.cpp, which sanitizer builds leave uninstrumented like the OpenVDB
// library.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace clustersurf::detail {

/// The offsets of a cell's 8 corners from its lowest one, in the order its values are kept.
inline constexpr int kCellCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                          {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};

/// One grid cell crossed by the surface: its integer corner (i, j, k) and the values of f at
/// its 8 corners, in the kCellCorner order. Shared corners of neighbouring cells carry the same
/// value.
struct SurfaceCell {
  std::array<std::int32_t, 3> corner;
  std::array<float, 8> values;
};

/// Polygons of the zero level set inside the given cells. Vertices are in grid units (cell
/// size 1, relative to the grid origin); quads and triangles index them and are oriented so that
/// their normals point towards positive values.
struct CellPolygons {
  std::vector<std::array<float, 3>> vertices;
  std::vector<std::array<std::uint32_t, 4>> quads;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// Polygonizes f = 0 in `cells` (OpenVDB's VolumeToMesh, restricted to the cells by a surface
/// mask). `outside` is the value of grid points no cell sets (positive: outside). Thread-parallel;
/// the result does not depend on the thread count.
CellPolygons polygonize_cells(std::span<const SurfaceCell> cells, float outside);

}  // namespace clustersurf::detail
