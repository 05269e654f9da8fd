#pragma once
// Laplace's equation on the unknown nodes of a grid, for ClosedSurface's fill: conjugate
// gradients preconditioned by a geometric multigrid V-cycle.

#include "core/progress_reporter.hpp"

#include <cstdint>
#include <vector>

namespace clustersurf::detail {

/// Node values on a grid, x fastest, and which of them are fixed.
struct FillGrid {
  std::int64_t nx, ny, nz;
  std::vector<float> values;
  std::vector<std::uint8_t> known;
};

/// Solves Laplace's equation at the nodes that are not known, in place, and returns how many
/// there were. A = −Laplacian on the unknowns (7 points; at the grid's border the missing
/// neighbours drop out: no flux through it, so the fill is not pulled towards any value out
/// there), b = the sum of the known neighbours' values; every unknown region touches some known
/// node (the surface bounds it), so A is positive definite. Conjugate gradients to a residual
/// of 1e-6 of b, preconditioned by a multigrid V-cycle (damped Jacobi smoothing, trilinear
/// transfers, the coarse levels' unknowns those of every other node), starting from the same
/// problem solved on every other node and interpolated. Deterministic and independent of the
/// thread count; at most 2³¹ nodes. `reporter` (may be null) hears progress and cancellation.
std::size_t solve_fill(FillGrid& g, ProgressReporter* reporter);

}  // namespace clustersurf::detail
