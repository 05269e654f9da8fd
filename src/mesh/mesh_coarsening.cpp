// coarsen_mesh(): each block's merge tested on the mesh around it, from the smallest block up;
// then the merges checked together on the coarse mesh, and the last in priority around each
// vertex that fails undone (its blocks of the size below merging instead), until none fails
// (block_merge.hpp holds the tests).

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_coarsening.hpp>

#include "mesh/block_merge.hpp"
#include "mesh/mesh_subset.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace clustersurf {

namespace {

using detail::BlockMerge;
using detail::Index;
using detail::kNone;
using detail::MeshView;
using detail::Triangle;
using detail::VertexTriangles;

/// Rounds of the joint check before every merge still in doubt is undone.
constexpr int kJointRounds = 8;

/// The vertices grouped by the block of side `size` that holds them: (key, vertex) pairs in
/// order, and where each block's run begins (with the end last).
struct Grouping {
  std::vector<std::pair<std::int64_t, Index>> keyed;
  std::vector<std::size_t> begin;
};

Grouping group_by_block(const MeshView& mesh, std::span<const Index> vertices, double size) {
  Grouping g;
  g.keyed.reserve(vertices.size());
  for (const Index v : vertices) {
    const std::int64_t key = mesh.block_key(v, size);
    if (key >= 0) g.keyed.emplace_back(key, v);
  }
  std::sort(g.keyed.begin(), g.keyed.end());
  g.begin.push_back(0);
  for (std::size_t i = 1; i <= g.keyed.size(); ++i)
    if (i == g.keyed.size() || g.keyed[i].first != g.keyed[i - 1].first) g.begin.push_back(i);
  return g;
}

/// The merges: each block's level (1: 2 cells, 2: 4, …), kept vertex and members, in the order
/// they were planned, which is their priority (larger blocks first, then by key; blocks that
/// replace an undone one last).
class Merges {
 public:
  /// Each block's own test from the smallest up (own_tests()), each vertex in the largest that
  /// passed.
  Merges(const MeshView& mesh, std::uint32_t levels) : mesh_(mesh), rep_(mesh.vertices(), kNone) {
    own_tests(levels);
    std::vector<Index> all(mesh.vertices());
    for (Index v = 0; v < mesh.vertices(); ++v) all[v] = v;
    for (std::size_t l = kept_.size(); l >= 1; --l) {
      std::vector<Index> at_level;
      for (const Index v : all)
        if (level_[v] == l) at_level.push_back(v);
      plan(at_level, l);
    }
  }

  std::size_t blocks() const { return keep_.size(); }
  bool live(std::size_t b) const { return !undone_[b]; }
  Index keep(std::size_t b) const { return keep_[b]; }
  std::span<const Index> members(std::size_t b) const {
    return {members_.data() + begin_[b], begin_[b + 1] - begin_[b]};
  }
  /// The vertex v becomes: its live block's kept vertex, or itself.
  Index image(Index v) const { return rep_[v] == kNone ? v : rep_[v]; }

  /// Undoes block b; with `fall_back`, its members merge in the blocks of the size below
  /// instead (each of which passed its own test).
  void undo(std::size_t b, bool fall_back) {
    undone_[b] = 1;
    const std::span<const Index> m = members(b);
    for (const Index v : m) rep_[v] = kNone;
    if (fall_back && level_of_[b] > 1) {
      const std::vector<Index> copy(m.begin(), m.end());
      plan(copy, level_of_[b] - 1u);
    }
  }

 private:
  /// level_[v]: the largest block around v whose own test passed (0: none), where a block of 2
  /// cells passes its test (one vertex alone passes) and a larger one passes when each of its
  /// vertices passed at the size below and its own test passes; kept_[l − 1][v]: the vertex
  /// v's block of level l keeps.
  void own_tests(std::uint32_t levels) {
    const Index n = mesh_.vertices();
    level_.assign(n, 0);
    std::vector<Index> all(n);
    for (Index v = 0; v < n; ++v) all[v] = v;
    tbb::enumerable_thread_specific<BlockMerge> tests([&] { return BlockMerge(mesh_); });
    for (std::uint32_t l = 1; l <= levels; ++l) {
      const Grouping g = group_by_block(mesh_, all, mesh_.cell() * static_cast<double>(1u << l));
      std::vector<Index>& keep = kept_.emplace_back(n, kNone);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, g.begin.size() - 1, 64), [&](const auto& r) {
        BlockMerge& test = tests.local();
        std::vector<Index> block;
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
          block.clear();
          for (std::size_t i = g.begin[b]; i < g.begin[b + 1]; ++i) block.push_back(g.keyed[i].second);
          if (std::any_of(block.begin(), block.end(), [&](Index v) { return level_[v] + 1u != l; })) continue;
          const Index k = block.size() == 1 ? block.front() : test.kept_vertex(block);
          if (k != kNone)
            for (const Index v : block) keep[v] = k;
        }
      });
      bool any = false;
      for (Index v = 0; v < n; ++v)
        if (keep[v] != kNone) level_[v] = static_cast<std::uint8_t>(l), any = true;
      if (!any) break;
    }
  }

  /// Plans the blocks of level l that hold `vertices` (each passed its test at that level),
  /// in order of key; blocks of one vertex change nothing and are left out.
  void plan(std::span<const Index> vertices, std::size_t l) {
    const Grouping g = group_by_block(mesh_, vertices, mesh_.cell() * static_cast<double>(1u << l));
    for (std::size_t b = 0; b + 1 < g.begin.size(); ++b) {
      if (g.begin[b + 1] - g.begin[b] < 2) continue;
      const Index k = kept_[l - 1][g.keyed[g.begin[b]].second];
      keep_.push_back(k);
      for (std::size_t i = g.begin[b]; i < g.begin[b + 1]; ++i) {
        members_.push_back(g.keyed[i].second);
        rep_[g.keyed[i].second] = k;
      }
      begin_.push_back(static_cast<Index>(members_.size()));
      level_of_.push_back(static_cast<std::uint8_t>(l));
      undone_.push_back(0);
    }
  }

  const MeshView& mesh_;
  std::vector<std::uint8_t> level_;
  std::vector<std::vector<Index>> kept_;
  std::vector<Index> keep_, begin_{0}, members_;
  std::vector<std::uint8_t> level_of_, undone_;
  std::vector<Index> rep_;
};

/// The triangles of `mesh` with each vertex replaced by its image, the degenerate ones dropped.
std::vector<Triangle> coarse_triangles(const MeshView& mesh, const Merges& merges) {
  std::vector<Triangle> out;
  out.reserve(mesh.triangles().size());
  for (const Triangle& t : mesh.triangles()) {
    const Triangle c{merges.image(t[0]), merges.image(t[1]), merges.image(t[2])};
    if (c[0] != c[1] && c[1] != c[2] && c[0] != c[2]) out.push_back(c);
  }
  return out;
}

/// The live blocks whose merge fails on the coarse mesh `coarse`: around each vertex of a
/// triangle a merge changed whose triangles are not one fan (a vertex or an edge not manifold, a
/// triangle twice) or where one is turned against its corners' normals, the last in priority
/// of the blocks kept there; and each block with a merged vertex farther than the tolerance
/// from its kept vertex's triangles.
std::vector<std::uint8_t> failed_blocks(const MeshView& mesh, const Merges& merges,
                                        const std::vector<Triangle>& coarse) {
  std::vector<Index> block_of(mesh.vertices(), kNone);  // per kept vertex of a live block
  for (std::size_t b = 0; b < merges.blocks(); ++b)
    if (merges.live(b)) block_of[merges.keep(b)] = static_cast<Index>(b);
  const VertexTriangles around(coarse, mesh.vertices());
  std::vector<std::uint8_t> checked(mesh.vertices(), 0);
  for (const Triangle& t : coarse)
    if (block_of[t[0]] != kNone || block_of[t[1]] != kNone || block_of[t[2]] != kNone)
      for (const Index v : t) checked[v] = 1;
  std::vector<std::uint8_t> fails(mesh.vertices(), 0);
  tbb::parallel_for(tbb::blocked_range<Index>(0, mesh.vertices(), 4096), [&](const auto& r) {
    std::vector<std::pair<Index, Index>> link;
    for (Index v = r.begin(); v != r.end(); ++v)
      if (checked[v])
        fails[v] = !detail::one_fan(v, coarse, around, link) || !detail::unturned(v, mesh, coarse, around);
  });
  std::vector<std::uint8_t> failed(merges.blocks(), 0);
  for (Index v = 0; v < mesh.vertices(); ++v) {
    if (!fails[v]) continue;
    Index last = kNone;
    for (const Index t : around.of(v))
      for (const Index u : coarse[t])
        if (block_of[u] != kNone && (last == kNone || block_of[u] > last)) last = block_of[u];
    if (last != kNone) failed[last] = 1;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, merges.blocks(), 64), [&](const auto& r) {
    for (std::size_t b = r.begin(); b != r.end(); ++b)
      if (merges.live(b) && !failed[b] &&
          !detail::within_tolerance(merges.members(b), merges.keep(b), mesh, coarse, around.of(merges.keep(b)),
                                    mesh.tolerance()))
        failed[b] = 1;
  });
  return failed;
}

}  // namespace

TriangleMesh coarsen_mesh(const TriangleMesh& mesh, const Eigen::Vector3d& origin, double cell, double leaf_error,
                          const CoarseningOptions& options, CoarseningReport* report) {
  if (!(options.error_share >= 0) || !std::isfinite(options.error_share))
    throw OptionError("the coarsening's error share (coarsen) must be a finite number >= 0");
  if (options.levels < 1 || options.levels > kMaxCoarseningLevels)
    throw OptionError("the coarsening's block sizes (coarsen_levels) must number 1 to " +
                      std::to_string(kMaxCoarseningLevels));
  if (!(cell > 0) || !std::isfinite(cell)) throw OptionError("the coarsening's lattice cell must be positive");
  if (!origin.allFinite()) throw OptionError("the coarsening's lattice origin must be finite");
  if (!(leaf_error >= 0) || !std::isfinite(leaf_error))
    throw OptionError("the coarsening's leaf error must be a finite distance >= 0");
  check_triangle_indices(mesh);
  CoarseningReport done;
  done.vertices_before = done.vertices_after = static_cast<std::size_t>(mesh.vertices.rows());
  done.triangles_before = done.triangles_after = static_cast<std::size_t>(mesh.triangles.rows());
  done.tolerance = options.error_share * leaf_error;
  if (done.tolerance == 0 || mesh.triangles.rows() == 0) {
    if (report != nullptr) *report = done;
    return mesh;
  }
  const MeshView view(mesh, origin, cell, done.tolerance);
  Merges merges(view, options.levels);
  std::vector<Triangle> coarse = coarse_triangles(view, merges);
  for (int round = 0; merges.blocks() > 0; ++round) {
    const std::vector<std::uint8_t> failed = failed_blocks(view, merges, coarse);
    if (std::none_of(failed.begin(), failed.end(), [](std::uint8_t f) { return f != 0; })) break;
    // The last round undoes every merge (the mesh as it was) rather than keep one in doubt.
    const bool last = round == kJointRounds;
    const std::size_t planned = merges.blocks();
    for (std::size_t b = 0; b < planned; ++b)
      if (merges.live(b) && (failed[b] || last)) merges.undo(b, !last);
    coarse = coarse_triangles(view, merges);
    if (last) break;
  }

  TriangleMesh out = mesh;
  out.triangles.resize(static_cast<Eigen::Index>(coarse.size()), 3);
  for (std::size_t t = 0; t < coarse.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k)
      out.triangles(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(k)) =
          static_cast<std::int32_t>(coarse[t][k]);
  out = detail::without_unused_vertices(out);
  for (std::size_t b = 0; b < merges.blocks(); ++b) done.merged_blocks += merges.live(b);
  done.vertices_after = static_cast<std::size_t>(out.vertices.rows());
  done.triangles_after = static_cast<std::size_t>(out.triangles.rows());
  if (report != nullptr) *report = done;
  return out;
}

}  // namespace clustersurf
