#pragma once
// A triangle mesh's vertex rings, and the averages and areas over them that the vertex refit
// weighs its moves with.

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf::detail {

/// Each vertex's neighbours along the triangles' edges, in compressed rows.
struct VertexRings {
  std::vector<std::uint32_t> begin, neighbors;
};

/// The rings of `mesh`, each in the order of its vertices' positions (not of their numbers): a
/// tile of the same surface, numbered otherwise, sums the same values in the same order.
VertexRings edge_neighbors(const TriangleMesh& mesh);

/// `values` averaged over each vertex and its edge neighbours, `rounds` times.
std::vector<double> ring_mean(const VertexRings& rings, std::vector<double> values, std::uint32_t rounds);

/// The number of vertices that `rounds` rounds of ring_mean() average over, as (Σk)² / Σk² of
/// its kernel k on the regular triangulation (valence 6).
double kernel_vertices(std::uint32_t rounds);

/// Each vertex's share of the mesh's area, (√3 / 2) times the mean square of its edges (exact
/// on the regular triangulation), summed in its ring's order: the same bits in any tile.
std::vector<double> vertex_areas(const TriangleMesh& mesh, const VertexRings& rings);

}  // namespace clustersurf::detail
