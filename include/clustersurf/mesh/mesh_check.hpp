#pragma once
// Is a mesh ready to print? Closed and edge-manifold, consistently oriented, enclosing a positive
// volume, and free of self-intersections; with its components, Euler characteristic and genus.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clustersurf {

/// Options of check_mesh() and find_self_intersections().
struct MeshCheckOptions {
  /// Relative tolerance of the triangle–triangle test: a vertex closer to the other triangle's
  /// plane than this times the longer of the two triangles' longest edges counts as lying in it,
  /// features closer than that count as touching (and touching triangles as intersecting), and
  /// triangles thinner than this times their longest edge are not tested (no plane is defined).
  double tolerance = 1e-8;
  /// Intersecting pairs listed in MeshCheck::intersecting_pairs (the first ones in (i, j) order);
  /// all are counted whatever this says.
  std::size_t max_pairs = 100;
};

/// Triangle pairs that intersect other than where the mesh connects them.
struct SelfIntersections {
  std::size_t count = 0;                           ///< intersecting pairs
  std::vector<std::array<std::int32_t, 2>> pairs;  ///< the first max_pairs of them, i < j, sorted
};

/// What check_mesh() found.
struct MeshCheck {
  MeshTopology topology;  ///< counts, boundary / non-manifold / inconsistent edges, χ, components
  /// Total genus: Σ over components of (2 − χᵢ)/2 = (2·components − χ)/2, defined when the mesh
  /// is watertight and consistently oriented (every component a closed orientable surface): 0
  /// for one sphere, 1 for one torus, 2 for two tori. −1 when it is not defined: open, with
  /// non-manifold or inconsistently oriented edges, or when 2·components − χ is odd or negative
  /// (components pinched together at a vertex).
  long genus = -1;
  /// The signed volume the triangles enclose (divergence theorem, input units cubed; positive
  /// when they face outward), when the mesh is watertight; NaN otherwise (an open surface
  /// encloses nothing). Components inside others and self-intersections are counted with their
  /// winding: a shell facing inward subtracts.
  double volume = 0;
  /// Pairs of triangles that intersect other than at the vertices and edges they share (see
  /// find_self_intersections()).
  std::size_t self_intersections = 0;
  std::vector<std::array<std::int32_t, 2>> intersecting_pairs;  ///< the first MeshCheckOptions::max_pairs
  bool watertight = false;                                      ///< is_watertight(topology): closed and edge-manifold
  bool consistently_oriented = false;  ///< no interior edge traversed twice in the same direction
  /// watertight && consistently_oriented && no self-intersections && volume > 0.
  bool printable = false;
};

/// Why the mesh is not printable, one phrase each ("12 boundary edges", "negative volume (the
/// triangles face inward)", ...), as both front ends report it; empty when it is.
std::vector<std::string> printing_problems(const MeshCheck& check);

/// The report of `topology` as one JSON object, the same for every front end: vertices,
/// triangles, edges, boundary_edges, non_manifold_edges, inconsistent_edges, components,
/// small_components, euler_characteristic, area, boundary_length, boundary_per_sqrt_area,
/// signed_volume, watertight.
std::string mesh_topology_json(const MeshTopology& topology);
/// The report of `check` as one JSON object: mesh_topology_json()'s fields, then genus (null
/// when not defined), volume (null when not closed), self_intersections, intersecting_pairs (the
/// first ones, [i, j]), watertight, consistently_oriented, printable and problems
/// (printing_problems()).
std::string mesh_check_json(const MeshCheck& check);

/// Topology (mesh_topology()), genus, volume and self-intersections of `mesh`. Deterministic,
/// and the same whatever the number of threads.
MeshCheck check_mesh(const TriangleMesh& mesh, const MeshCheckOptions& options = {});
/// The same with the mesh's self-intersections already found (find_self_intersections()), so
/// that a caller that has just searched for them does not search again.
MeshCheck check_mesh(const TriangleMesh& mesh, SelfIntersections intersections);

/// The pairs of triangles of `mesh` that intersect other than where they are connected. Vertices
/// at the same position count as one vertex, so a mesh stored as a triangle soup gives the same
/// answer as its welded version. Triangles that share no vertex intersect when they touch at
/// all; sharing one vertex, when they meet anywhere else; sharing an edge, when they are folded
/// flat onto each other (coplanar, on the same side of the edge); sharing three (a duplicated
/// face), always. Candidates come from Embree's BVH collision (rtcCollide), the test of each
/// candidate is computed in double precision with MeshCheckOptions::tolerance. Triangles with
/// a non-finite coordinate are skipped. Deterministic; the count does not depend on threads.
SelfIntersections find_self_intersections(const TriangleMesh& mesh, const MeshCheckOptions& options = {});
/// The same restricted to the pairs of which at least one triangle t is a suspect (suspect[t]
/// set; one mark per triangle): the pairs find_self_intersections() finds among those, at the
/// cost of a search over the suspects and the triangles their boxes meet.
SelfIntersections find_self_intersections(const TriangleMesh& mesh, const std::vector<std::uint8_t>& suspect,
                                          const MeshCheckOptions& options = {});

/// The test find_self_intersections() applies to a pair of triangles given by their corners
/// (corners at equal positions are shared). Symmetric in `a` and `b`.
bool triangles_intersect(const std::array<Eigen::Vector3d, 3>& a, const std::array<Eigen::Vector3d, 3>& b,
                         double tolerance = MeshCheckOptions{}.tolerance);

}  // namespace clustersurf
