#pragma once
// Fewer vertices where the mesh is flat: the vertices of each block of the mesh's lattice that
// a nearly flat disk of triangles covers, merged into one of them (vertex clustering on an octree
// of blocks, each merge checked against a distance bound and for manifold topology).

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/point_cloud.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

namespace clustersurf {

/// coarsen_mesh()'s default tolerance, as a share of the error scale (coarsening_scale()): the
/// merges move the surface by at most a twentieth of the input's estimated noise.
inline constexpr double kCoarseningNoiseShare = 0.05;

/// The most block sizes coarsen_mesh() tries (blocks up to 256 cells).
inline constexpr std::uint32_t kMaxCoarseningLevels = 8;

/// Options of coarsen_mesh().
struct CoarseningOptions {
  /// The farthest a merged vertex may lie from the coarse mesh, as a share of the error scale
  /// (coarsening_scale() of the tree); 0: no merging.
  double noise_share = kCoarseningNoiseShare;
  /// The block sizes tried: blocks of 2, 4, …, 2^levels lattice cells along each side (1 to
  /// kMaxCoarseningLevels).
  std::uint32_t levels = 3;
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<CoarseningOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("noise_share", o.noise_share);
  f("levels", o.levels);
}

/// What coarsen_mesh() did.
struct CoarseningReport {
  double tolerance = 0;           ///< the distance bound, in input units
  std::size_t merged_blocks = 0;  ///< blocks whose vertices became one
  std::size_t vertices_before = 0, vertices_after = 0;
  std::size_t triangles_before = 0, triangles_after = 0;
};

/// The error scale of `tree` that coarsen_mesh()'s tolerance is a share of: its estimated noise
/// (ClusterTree::noise_sigma, which on a clean input is what its leaves' quadratics miss the
/// points by, and falls with the density as the mesh's own error does), or, for a tree without
/// an estimate, its leaves' error threshold.
double coarsening_scale(const ClusterTree& tree);

/// `mesh` with the vertices of flat blocks merged, each within options.noise_share × `scale`
/// (the tolerance; coarsening_scale() of the mesh's tree) of the coarse mesh. The blocks are
/// cubes of 2, 4, …, 2^options.levels cells of the lattice whose corner is `origin` and whose
/// cell is `cell` (each the union of eight of the size below); every vertex goes to the largest block
/// around it that merges, or stays. A block's vertices merge into the one nearest their
/// centroid when the triangles around them form one disk that does not touch the mesh's
/// boundary, and the fan from that vertex to the disk's rim holds every merged vertex within
/// the tolerance and turns no triangle more than 60 degrees from its corners' normals; a
/// larger block merges only where each of its eight would. The merges are then checked
/// together: where one fails beside the others (a vertex whose triangles are not one fan, a
/// turned triangle, a vertex beyond the tolerance), the last of them in priority (larger
/// blocks first) gives way to its blocks of the size below, until none fails (after 8 rounds,
/// a failing merge is undone without them, so the rounds end and a conflict that lasts undoes
/// only the merges around it). So the coarse mesh keeps the rims, the topology and the orientation,
/// and its vertices are a subset of the mesh's, in place with their normals, colors and
/// attributes, in their order (blocks whose vertices differ in an attribute stay). Whether a
/// block merges depends on the mesh around it and, through the joint check, around its
/// neighbours' merges, never on the vertices' numbering or the thread count. A block holding a
/// vertex whose `fixed` value is positive does not merge (empty: none fixed). Throws
/// OptionError for a noise share or scale that is negative or not finite, levels outside 1 to
/// kMaxCoarseningLevels, a cell that is not positive, or `fixed` not empty nor one per vertex.
TriangleMesh coarsen_mesh(const TriangleMesh& mesh, const Eigen::Vector3d& origin, double cell, double scale,
                          const CoarseningOptions& options = {}, CoarseningReport* report = nullptr,
                          std::span<const float> fixed = {});

}  // namespace clustersurf
