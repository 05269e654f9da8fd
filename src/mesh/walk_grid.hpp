#pragma once
// The state of mesh extraction's walk over grid cells: the corners queued or evaluated with
// their values, and the cells visited, in OpenVDB sparse grids. Kept apart from the walk, as
// the polygonizer is, so that OpenVDB's templates stay in files that sanitizer builds leave
// uninstrumented like the OpenVDB library.

#include "mesh/cell_polygonizer.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

namespace clustersurf::detail {

/// Integer grid coordinates (i, j, k) of a corner or of a cell (its lowest corner).
using GridIndex = std::array<std::int32_t, 3>;

/// Corners and cells of a walk: each corner queued gets the next id, its value is kept by id.
/// Lookups of neighbouring coordinates are cheap (the grids' accessors cache the last leaf).
/// Not thread-safe, but for values(), which reads in parallel.
class WalkGrid {
 public:
  WalkGrid();
  ~WalkGrid();
  WalkGrid(const WalkGrid&) = delete;
  WalkGrid& operator=(const WalkGrid&) = delete;

  /// Queues `corner` for evaluation: true the first time, false when it was queued before.
  bool queue(const GridIndex& corner);
  /// The values of f (NaN where f is undefined) at the corners queued since the last call, in
  /// the order they were queued. Throws std::logic_error when the counts differ.
  void set_values(std::span<const float> values);
  /// Fills each cell's values with the values set at its 8 corners (SurfaceCell's order), the
  /// cells read in parallel. Throws std::logic_error for a corner never queued.
  void values(std::span<SurfaceCell> cells) const;
  /// Marks `cell` visited: true the first time, false when it was visited before.
  bool visit(const GridIndex& cell);
  /// How many corners were queued.
  std::size_t queued() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clustersurf::detail
