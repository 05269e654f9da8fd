// coarsen_mesh(): each block's merge tested on the mesh around it, from the smallest block up;
// then the merges checked together around every vertex they change, and the last in priority
// around each vertex that fails undone (its blocks of the size below merging instead), until
// none fails (block_merge.hpp holds the tests).

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_coarsening.hpp>

#include "mesh/block_merge.hpp"
#include "mesh/mesh_subset.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace clustersurf {

namespace {

using detail::BlockMerge;
using detail::Index;
using detail::kNoCell;
using detail::kNone;
using detail::MeshView;
using detail::Triangle;

/// Rounds of the joint check in which a failing merge gives way to its smaller blocks; after
/// them a failing merge is only undone.
constexpr int kJointRounds = 8;

/// The start of each run of `order` (vertices in the order of their cell codes) that one block
/// of 2^l cells holds, and the end last.
std::vector<std::size_t> block_runs(const MeshView& mesh, std::span<const Index> order, std::uint32_t l) {
  std::vector<std::size_t> begin{0};
  for (std::size_t i = 1; i <= order.size(); ++i)
    if (i == order.size() || mesh.cell_code(order[i]) >> (3 * l) != mesh.cell_code(order[i - 1]) >> (3 * l))
      begin.push_back(i);
  return begin;
}

/// `vertices` in the order of their cell codes (ties: by number), those outside the codes'
/// range left out.
std::vector<Index> in_cell_order(const MeshView& mesh, std::span<const Index> vertices) {
  std::vector<std::pair<std::uint64_t, Index>> keyed;
  keyed.reserve(vertices.size());
  for (const Index v : vertices)
    if (mesh.cell_code(v) != kNoCell) keyed.emplace_back(mesh.cell_code(v), v);
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<Index> order(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

/// The merges: each block's level (1: 2 cells, 2: 4, …), kept vertex and members, in the order
/// they were planned, which is their priority (larger blocks first, then in the cells' order;
/// blocks that replace an undone one last).
class Merges {
 public:
  /// Each block's own test from the smallest up (own_tests()), each vertex in the largest that
  /// passed.
  Merges(const MeshView& mesh, std::uint32_t levels)
      : mesh_(mesh), rep_(mesh.vertices(), kNone), block_of_(mesh.vertices(), kNone) {
    std::vector<Index> all(mesh.vertices());
    for (Index v = 0; v < mesh.vertices(); ++v) all[v] = v;
    const std::vector<Index> order = in_cell_order(mesh, all);
    own_tests(order, levels);
    for (std::uint32_t l = static_cast<std::uint32_t>(kept_.size()); l >= 1; --l) {
      std::vector<Index> at_level;
      for (const Index v : order)
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
  /// Triangle t of the mesh on the coarse mesh's vertices, or nothing where it collapses.
  std::optional<Triangle> image_of_triangle(Index t) const {
    const Triangle f = mesh_.triangle(t);
    const Triangle c{image(f[0]), image(f[1]), image(f[2])};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) return std::nullopt;
    return c;
  }
  /// The live block whose kept vertex v is, or kNone.
  Index block_kept_at(Index v) const { return block_of_[v]; }

  /// The triangles around vertex v of the coarse mesh (none for a merged vertex that is not
  /// kept), in `star`; `scratch` holds the original triangles they come from.
  void star(Index v, std::vector<Triangle>& star, std::vector<Index>& scratch) const {
    star.clear();
    scratch.clear();
    if (rep_[v] != kNone && rep_[v] != v) return;
    const auto add = [&](Index u) {
      for (const Index t : mesh_.around().of(u)) scratch.push_back(t);
    };
    if (block_of_[v] != kNone) {
      for (const Index m : members(block_of_[v])) add(m);
      std::sort(scratch.begin(), scratch.end());
      scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
    } else {
      add(v);
    }
    for (const Index t : scratch)
      if (const std::optional<Triangle> c = image_of_triangle(t)) star.push_back(*c);
  }

  /// Undoes block b; with `fall_back`, its members merge in the blocks of the size below
  /// instead (each of which passed its own test).
  void undo(std::size_t b, bool fall_back) {
    undone_[b] = 1;
    block_of_[keep_[b]] = kNone;
    const std::vector<Index> m(members(b).begin(), members(b).end());
    for (const Index v : m) rep_[v] = kNone;
    if (fall_back && level_of_[b] > 1) plan(in_cell_order(mesh_, m), level_of_[b] - 1u);
  }

 private:
  /// level_[v]: the largest block around v whose own test passed (0: none), where a block of 2
  /// cells passes its test (one vertex alone passes) and a larger one passes when each of its
  /// vertices passed at the size below and its own test passes; kept_[l − 1][v]: the vertex
  /// v's block of level l keeps. `order`: the vertices in their cells' order.
  void own_tests(std::span<const Index> order, std::uint32_t levels) {
    const Index n = mesh_.vertices();
    level_.assign(n, 0);
    tbb::enumerable_thread_specific<BlockMerge> tests([&] { return BlockMerge(mesh_); });
    for (std::uint32_t l = 1; l <= levels; ++l) {
      const std::vector<std::size_t> runs = block_runs(mesh_, order, l);
      std::vector<Index>& keep = kept_.emplace_back(n, kNone);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, runs.size() - 1, 64), [&](const auto& r) {
        BlockMerge& test = tests.local();
        std::vector<Index> block;
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
          block.assign(order.begin() + static_cast<std::ptrdiff_t>(runs[b]),
                       order.begin() + static_cast<std::ptrdiff_t>(runs[b + 1]));
          if (std::any_of(block.begin(), block.end(), [&](Index v) { return level_[v] + 1u != l; })) continue;
          std::sort(block.begin(), block.end());
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

  /// Plans the blocks of level l that hold `order` (vertices in their cells' order, each of
  /// which passed its test at that level), one per run; blocks of one vertex change nothing.
  void plan(std::span<const Index> order, std::uint32_t l) {
    const std::vector<std::size_t> runs = block_runs(mesh_, order, l);
    for (std::size_t b = 0; b + 1 < runs.size(); ++b) {
      if (runs[b + 1] - runs[b] < 2) continue;
      const Index k = kept_[l - 1][order[runs[b]]];
      block_of_[k] = static_cast<Index>(keep_.size());
      keep_.push_back(k);
      std::vector<Index> block(order.begin() + static_cast<std::ptrdiff_t>(runs[b]),
                               order.begin() + static_cast<std::ptrdiff_t>(runs[b + 1]));
      std::sort(block.begin(), block.end());
      for (const Index v : block) {
        members_.push_back(v);
        rep_[v] = k;
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
  std::vector<Index> rep_, block_of_;
};

/// The live blocks whose merge fails on the coarse mesh, looked for where the blocks `changed`
/// (merged or undone since the last look) changed it: around each vertex of a triangle they
/// changed whose triangles are not one fan (a vertex or an edge not manifold, a triangle twice)
/// or where one is turned against its corners' normals, the last in priority of the blocks kept
/// there; and each block kept at such a vertex with a merged vertex farther than the tolerance
/// from its kept vertex's triangles. Each vertex's coarse triangles are gathered once for both.
std::vector<std::uint8_t> failed_blocks(const MeshView& mesh, const Merges& merges,
                                        std::span<const std::size_t> blocks) {
  std::vector<std::uint8_t> marked(mesh.vertices(), 0);
  for (const std::size_t b : blocks)
    for (const Index m : merges.members(b))
      for (const Index t : mesh.around().of(m))
        for (const Index u : mesh.triangle(t)) marked[merges.image(u)] = 1;
  std::vector<Index> changed;
  for (Index v = 0; v < mesh.vertices(); ++v)
    if (marked[v]) changed.push_back(v);
  // Per changed vertex: the block last in priority around it where its triangles fail, and its
  // own block where a merged vertex is beyond the tolerance.
  std::vector<Index> last(changed.size(), kNone), far(changed.size(), kNone);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, changed.size(), 256), [&](const auto& r) {
    std::vector<Triangle> star;
    std::vector<Index> scratch;
    std::vector<std::pair<Index, Index>> link;
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const Index v = changed[i];
      merges.star(v, star, scratch);
      const Index own = merges.block_kept_at(v);
      if (own != kNone && !detail::within_tolerance(merges.members(own), v, mesh, star)) far[i] = own;
      if (detail::one_fan(v, star, link) && detail::unturned(mesh, star)) continue;
      for (const Triangle& f : star)
        for (const Index u : f) {
          const Index b = merges.block_kept_at(u);
          if (b != kNone && (last[i] == kNone || b > last[i])) last[i] = b;
        }
    }
  });
  std::vector<std::uint8_t> failed(merges.blocks(), 0);
  for (std::size_t i = 0; i < changed.size(); ++i)
    for (const Index b : {last[i], far[i]})
      if (b != kNone) failed[b] = 1;
  return failed;
}

/// The triangles of `mesh` with each vertex replaced by its image, the degenerate ones dropped.
Triangles coarse_triangles(const MeshView& mesh, const Merges& merges) {
  std::vector<Triangle> kept;
  kept.reserve(mesh.triangle_count());
  for (Index t = 0; t < mesh.triangle_count(); ++t)
    if (const std::optional<Triangle> c = merges.image_of_triangle(t)) kept.push_back(*c);
  Triangles out(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t t = 0; t < kept.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k)
      out(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(k)) = static_cast<std::int32_t>(kept[t][k]);
  return out;
}

}  // namespace

double coarsening_scale(const ClusterTree& tree) {
  return tree.noise_sigma > 0 ? tree.noise_sigma : tree.error_threshold;
}

TriangleMesh coarsen_mesh(const TriangleMesh& mesh, const Eigen::Vector3d& origin, double cell, double scale,
                          const CoarseningOptions& options, CoarseningReport* report, std::span<const float> fixed) {
  if (!(options.noise_share >= 0) || !std::isfinite(options.noise_share))
    throw OptionError("the coarsening's noise share (coarsen) must be a finite number >= 0");
  if (options.levels < 1 || options.levels > kMaxCoarseningLevels)
    throw OptionError("the coarsening's block sizes (coarsen_levels) must number 1 to " +
                      std::to_string(kMaxCoarseningLevels));
  if (!(cell > 0) || !std::isfinite(cell)) throw OptionError("the coarsening's lattice cell must be positive");
  if (!origin.allFinite()) throw OptionError("the coarsening's lattice origin must be finite");
  if (!(scale >= 0) || !std::isfinite(scale))
    throw OptionError("the coarsening's error scale must be a finite distance >= 0");
  check_triangle_indices(mesh);
  if (!fixed.empty() && fixed.size() != static_cast<std::size_t>(mesh.vertices.rows()))
    throw OptionError("the coarsening's fixed vertices must be given one value per vertex");
  CoarseningReport done;
  done.vertices_before = done.vertices_after = static_cast<std::size_t>(mesh.vertices.rows());
  done.triangles_before = done.triangles_after = static_cast<std::size_t>(mesh.triangles.rows());
  done.tolerance = options.noise_share * scale;
  if (done.tolerance == 0 || mesh.triangles.rows() == 0) {
    if (report != nullptr) *report = done;
    return mesh;
  }
  Triangles coarse;
  {
    const MeshView view(mesh, origin, cell, done.tolerance, fixed);
    Merges merges(view, options.levels);
    // Each round looks where the last one changed the mesh: first every block.
    std::vector<std::size_t> changed(merges.blocks());
    for (std::size_t b = 0; b < changed.size(); ++b) changed[b] = b;
    for (int round = 0; !changed.empty(); ++round) {
      const std::vector<std::uint8_t> failed = failed_blocks(view, merges, changed);
      // From round kJointRounds on, a failing merge goes without smaller blocks in its place:
      // merges only go then, so the rounds end, and only where a merge failed.
      const bool fall_back = round < kJointRounds;
      const std::size_t planned = merges.blocks();
      changed.clear();
      for (std::size_t b = 0; b < planned; ++b)
        if (merges.live(b) && failed[b] != 0) {
          merges.undo(b, fall_back);
          changed.push_back(b);
        }
      for (std::size_t b = planned; b < merges.blocks(); ++b) changed.push_back(b);
    }

    coarse = coarse_triangles(view, merges);
    for (std::size_t b = 0; b < merges.blocks(); ++b) done.merged_blocks += merges.live(b);
  }
  TriangleMesh out = detail::with_new_triangles(mesh, coarse);
  done.vertices_after = static_cast<std::size_t>(out.vertices.rows());
  done.triangles_after = static_cast<std::size_t>(out.triangles.rows());
  if (report != nullptr) *report = done;
  return out;
}

}  // namespace clustersurf
