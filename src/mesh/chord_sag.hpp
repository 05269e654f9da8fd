#pragma once
// A mesh whose vertices lie on a smooth surface, moved so that its triangles straddle the
// surface instead of cutting under its curved parts.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>

#include <span>

namespace clustersurf::detail {

/// The largest turn, in radians, of the normals along an edge over which offset_chord_sag()
/// trusts the quadratic: the turn over a cell of the finest curvature the mesh grid resolves
/// (a cell of 1 / kCellsPerCurvatureRadius of the radius).
inline constexpr double kMaxSagTurn = 1 / kCellsPerCurvatureRadius;

/// Moves each vertex of `mesh` (its vertices on a smooth surface, mesh.normals the unit normals
/// there) along its normal by the mean, weighted by its hat function over its triangles, of the
/// gap between those triangles and the quadratic surface through their corners with their
/// normals (the gap at barycentric λ is ½ Σᵢ<ⱼ λᵢλⱼ (nᵢ − nⱼ)·(xᵢ − xⱼ), exact for a quadratic):
/// the lumped L² projection of that surface onto the mesh's piecewise linear functions. A
/// chord of a convex part lies inside it: its corners go out by the mean sag, and the mesh's
/// mean distance to the surface falls (to 0.39 of it on a uniformly sampled circle, 0.22 on a
/// subdivided icosahedron). The lumped projection needs no solve and keeps each vertex's offset
/// within the range of its triangles' sags. Vertices
/// stay where an edge of theirs turns the normals by more than kMaxSagTurn (a crease, a
/// fold, a thin part's rim: no quadratic there) and where `fixed` is positive. Each vertex's
/// sum runs in an order set by the values, not by the numbering: the same bits for any
/// numbering of the vertices and triangles, and any thread count. Returns the mean |offset|.
double offset_chord_sag(TriangleMesh& mesh, std::span<const float> fixed = {});

}  // namespace clustersurf::detail
