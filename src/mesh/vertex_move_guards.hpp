#pragma once
// Vertex moves that fold a mesh or push it through itself, undone.

#include <clustersurf/core/point_cloud.hpp>

#include <vector>

namespace clustersurf::detail {

/// Puts back where they were (`before`) the corners of each triangle that the moves turned by
/// more than 60 degrees, round after round until none is (each round undoes at least one move):
/// a move that folds the mesh (a vertex pushed past its neighbours where the surface bends
/// within a few cells) is not taken. `moves` holds each vertex's move (0: not moved); the moves
/// undone are zeroed. Deterministic.
void undo_folds(TriangleMesh& mesh, const Points& before, std::vector<double>& moves);

/// Puts back where they were (`before`) the corners of each triangle that has a corner moved
/// more than `least` and intersects another triangle (find_self_intersections()), round after
/// round until none does: a move that pushes the surface through another part of it (the far
/// side of a thin part) is not taken. Intersections the moves did not make stay. `moves` as for
/// undo_folds(). Deterministic.
void undo_crossings(TriangleMesh& mesh, const Points& before, std::vector<double>& moves, double least);

}  // namespace clustersurf::detail
