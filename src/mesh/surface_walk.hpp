#pragma once
// The surface-following walk of mesh extraction: seeds on every blended proxy, then breadth-first
// over the cells the zero set crosses (its state in walk_grid: OpenVDB).

#include "core/progress_reporter.hpp"
#include "mesh/cell_polygonizer.hpp"
#include "mesh/walk_lattice.hpp"

#include <cstdint>
#include <vector>

namespace clustersurf::detail {

/// The cells the walk starts from, sorted: around a point of every blended proxy projected onto
/// f = 0 (its centre, or where that projection fails, one of the points at ±r/3 along two
/// tangents), and the clip's seed points' cells.
std::vector<Key> seed_cells(const ImplicitSurface& surface, const Lattice& lattice);

/// What the walk found: the cells the surface crosses (with their corners' values), in key
/// order (by k, then j, then i), and how many corners it evaluated.
struct Walk {
  std::vector<SurfaceCell> cells;
  std::uint64_t corners = 0;
};

/// Breadth-first walk from `frontier` over the cells whose corners' values change sign, into
/// each neighbour across a face that does.
Walk walk_surface(const Field& field, const Lattice& lattice, std::vector<Key> frontier, ProgressReporter& reporter);

}  // namespace clustersurf::detail
