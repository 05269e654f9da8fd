#pragma once
// Fewer vertices where the mesh is flat: the vertices of each block of the mesh's lattice that
// a nearly flat disk of triangles covers, merged into one of them (vertex clustering on an octree
// of blocks, each merge checked against a distance bound and for manifold topology).

#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/point_cloud.hpp>

#include <cstddef>
#include <cstdint>

namespace clustersurf {

/// coarsen_mesh()'s default tolerance, as a share of the error a leaf of the tree may keep
/// (ClusterTree::error_threshold: the noise and the tree's tolerance together): the merges move
/// the surface by at most a twentieth of what the leaves are allowed to miss the points by.
inline constexpr double kCoarseningErrorShare = 0.05;

/// The most block sizes coarsen_mesh() tries (blocks up to 256 cells).
inline constexpr std::uint32_t kMaxCoarseningLevels = 8;

/// Options of coarsen_mesh().
struct CoarseningOptions {
  /// The farthest a merged vertex may lie from the coarse mesh, as a share of the error a leaf
  /// may keep (ClusterTree::error_threshold); 0: no merging.
  double error_share = kCoarseningErrorShare;
  /// The block sizes tried: blocks of 2, 4, …, 2^levels lattice cells along each side (1 to
  /// kMaxCoarseningLevels).
  std::uint32_t levels = 3;
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<CoarseningOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("error_share", o.error_share);
  f("levels", o.levels);
}

/// What coarsen_mesh() did.
struct CoarseningReport {
  double tolerance = 0;           ///< the distance bound, in input units
  std::size_t merged_blocks = 0;  ///< blocks whose vertices became one
  std::size_t vertices_before = 0, vertices_after = 0;
  std::size_t triangles_before = 0, triangles_after = 0;
};

/// `mesh` with the vertices of flat blocks merged, each within options.error_share ×
/// `leaf_error` (the tolerance; the tree's error_threshold) of the coarse mesh. The blocks are cubes of 2, 4, …,
/// 2^options.levels cells of the lattice whose corner is `origin` and whose cell is
/// `cell` (each the union of eight of the size below); every vertex goes to the largest block
/// around it that merges, or stays. A block's vertices merge into the one nearest their
/// centroid when the triangles around them form one disk that does not touch the mesh's
/// boundary, and the fan from that vertex to the disk's rim holds every merged vertex within
/// the tolerance and turns no triangle more than 60 degrees from its corners' normals; a
/// larger block merges only where each of its eight would. The merges are then checked
/// together: where one fails beside the others (a vertex whose triangles are not one fan, a
/// turned triangle, a vertex beyond the tolerance), the last of them in priority (larger
/// blocks first) gives way to its blocks of the size below, until none fails. So the coarse
/// mesh keeps the rims, the topology and the orientation, and its vertices are a subset of the
/// mesh's, in place with their normals, colors and attributes, in their order (blocks whose
/// vertices differ in an attribute stay). Whether a block merges depends on the positions and
/// triangles near it, never on the vertices' numbering or the thread count. Throws OptionError
/// for an error share or leaf error that is negative or not finite, levels outside 1 to
/// kMaxCoarseningLevels, or a cell that is not positive.
TriangleMesh coarsen_mesh(const TriangleMesh& mesh, const Eigen::Vector3d& origin, double cell, double leaf_error,
                          const CoarseningOptions& options = {}, CoarseningReport* report = nullptr);

}  // namespace clustersurf
