#pragma once
// The test of one block of coarsen_mesh(): whether its vertices may become one, and the checks
// that the merges of neighbouring blocks must pass together.

#include <clustersurf/core/point_cloud.hpp>

#include "mesh/vertex_triangles.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace clustersurf::detail {

using Index = std::uint32_t;
inline constexpr Index kNone = std::numeric_limits<Index>::max();
using Triangle = std::array<Index, 3>;
inline constexpr std::uint64_t kNoCell = std::numeric_limits<std::uint64_t>::max();

/// The smallest cosine between a triangle's normal and its corners' normals a merge may leave
/// (60 degrees).
inline constexpr double kMinNormalCosine = 0.5;

/// A mesh as coarsen_mesh() reads it, in place: its positions, unit normals (the mesh's, or its
/// triangles' area-weighted mean where it has none), triangles, each vertex's triangles, the
/// lattice, and the vertices no merge may take (`fixed` positive; empty: none).
class MeshView {
 public:
  MeshView(const TriangleMesh& mesh, const Eigen::Vector3d& origin, double cell, double tolerance,
           std::span<const float> fixed = {});

  Index vertices() const { return static_cast<Index>(mesh_.vertices.rows()); }
  std::size_t triangle_count() const { return static_cast<std::size_t>(mesh_.triangles.rows()); }
  Triangle triangle(Index t) const {
    return {static_cast<Index>(mesh_.triangles(t, 0)), static_cast<Index>(mesh_.triangles(t, 1)),
            static_cast<Index>(mesh_.triangles(t, 2))};
  }
  const VertexTriangles& around() const { return around_; }
  Eigen::Vector3d position(Index v) const { return mesh_.vertices.row(v).transpose(); }
  Eigen::Vector3d normal(Index v) const {
    const Eigen::Vector3d n = normals_.empty() ? Eigen::Vector3d(mesh_.normals.row(v).transpose()) : normals_[v];
    const double length = n.norm();
    return length > 0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
  }
  /// The lattice cell that holds vertex v as a Morton code (its coordinates' bits interleaved),
  /// kNoCell outside the range of 2^21 cells the code holds: the block of 2^l cells that holds
  /// it is code >> (3 l), and the vertices of a block are contiguous in the codes' order.
  std::uint64_t cell_code(Index v) const { return cells_[v]; }
  /// Whether vertices a and b carry the same value of every attribute.
  bool same_attributes(Index a, Index b) const;
  /// Whether vertex v must stay as it is: no block that holds it merges.
  bool fixed(Index v) const { return !fixed_.empty() && fixed_[v] > 0; }
  double cell() const { return cell_; }
  double tolerance() const { return tolerance_; }

 private:
  const TriangleMesh& mesh_;
  Eigen::Vector3d origin_;
  double cell_, tolerance_;
  VertexTriangles around_;
  std::vector<Eigen::Vector3d> normals_;  ///< where the mesh has none
  std::vector<std::uint64_t> cells_;
  std::span<const float> fixed_;
};

/// Tests blocks one at a time, with scratch space of its own (one per thread).
class BlockMerge {
 public:
  explicit BlockMerge(const MeshView& mesh) : mesh_(&mesh) {}
  /// The vertex of `block` (every vertex in one block, in increasing order) that they may merge
  /// into, or kNone: none of them is fixed, they carry the same attributes, their triangles
  /// form one disk off the mesh's boundary, and the fan from the vertex nearest their centroid
  /// (ties: the lowest position) to its rim keeps every triangle within kMinNormalCosine of its
  /// corners' normals and each of them within the tolerance.
  Index kept_vertex(std::span<const Index> block);

 private:
  struct Edge {
    Index lo, hi, from, to;
  };
  /// The vertex of `block` nearest its centroid (ties: the lowest position).
  Index central_vertex(std::span<const Index> block) const;
  /// Whether the fan from `keep` over the rim of the block's triangles_ (their edges that face
  /// one corner in the block; the fan kept in fan_) is upright and within the tolerance of the
  /// block.
  bool fan_holds(std::span<const Index> block, Index keep);
  /// Whether triangles_ form one disk whose interior vertices are the block's and whose
  /// boundary is fan_'s rim, one simple cycle.
  bool one_disk(std::span<const Index> block);

  const MeshView* mesh_;
  std::vector<Index> triangles_, vertices_;
  std::vector<Edge> edges_;
  std::vector<Triangle> fan_;
  std::vector<std::pair<Index, Index>> rim_;
  std::vector<Index> parent_;
};

/// Whether `star`, the triangles around vertex v, form one fan: a cycle, or a path where v is
/// on the boundary, each edge from v in at most two of them. `link` is scratch.
bool one_fan(Index v, std::span<const Triangle> star, std::vector<std::pair<Index, Index>>& link);

/// Whether every triangle of `star` has an area and a normal within kMinNormalCosine of its
/// corners' normals.
bool unturned(const MeshView& mesh, std::span<const Triangle> star);

/// Whether each of `members` (merged into `keep`) lies within the tolerance of one of `fan`, the
/// triangles around `keep`.
bool within_tolerance(std::span<const Index> members, Index keep, const MeshView& mesh, std::span<const Triangle> fan);

}  // namespace clustersurf::detail
