// The tiles of a tiled mesh joined straight into a PLY file, one tile in memory at a time.

#include "tiling/tiles.hpp"
#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>

#include "io/ply_mesh_stream.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <unordered_map>

namespace clustersurf {

namespace {

/// A position's bits: vertices of two tiles are one when their coordinates are equal (and the
/// mesher never puts two vertices of one tile at one place).
using PositionKey = std::array<std::uint64_t, 3>;
struct PositionHash {
  std::size_t operator()(const PositionKey& k) const noexcept {
    std::uint64_t h = k[0] * 0x9E3779B97F4A7C15ULL;
    h ^= k[1] + 0x632BE59BD9B4E019ULL + (h << 6) + (h >> 2);
    h ^= k[2] + 0x85EBCA77C2B2AE63ULL + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

/// Global vertex numbers of the tiles' vertices, in tile order, a vertex shared with an earlier
/// tile taking the earlier one's (as join_tiles()' weld: the lowest index). Only vertices near
/// their region's border can be shared (a tile's vertices lie within kTileMarginCells + 2 cells of
/// its region), so only those are kept in a map.
class Numbering {
 public:
  explicit Numbering(const RegionPlan& plan) : plan_(plan) {}

  /// The global numbers of `tile`'s vertices; `created[v]` says the vertex is new here. After
  /// restart(), the tiles asked for again in the same order get the same numbers.
  void number(const MeshTile& tile, std::vector<std::uint32_t>& id, std::vector<std::uint8_t>& created) {
    const Points& v = tile.mesh.vertices;
    const BoundingBox& box = plan_.region_box(tile.region);
    const double reach = (kTileMarginCells + 2) * tile.grid.voxel_size;
    id.resize(static_cast<std::size_t>(v.rows()));
    created.resize(id.size());
    for (Eigen::Index i = 0; i < v.rows(); ++i) {
      const Eigen::Vector3d x = v.row(i).transpose();
      const double inside = std::min((x - box.min).minCoeff(), (box.max - x).minCoeff());  // < 0 outside
      std::uint32_t g = next_;
      if (inside <= reach) {
        const PositionKey key{std::bit_cast<std::uint64_t>(x.x()), std::bit_cast<std::uint64_t>(x.y()),
                              std::bit_cast<std::uint64_t>(x.z())};
        g = border_.try_emplace(key, next_).first->second;  // a replay finds every one it made
      }
      created[static_cast<std::size_t>(i)] = g == next_;
      id[static_cast<std::size_t>(i)] = g;
      if (g == next_) ++next_;
    }
  }
  void restart() { next_ = 0; }
  std::uint32_t count() const { return next_; }

 private:
  const RegionPlan& plan_;
  std::unordered_map<PositionKey, std::uint32_t, PositionHash> border_;
  std::uint32_t next_ = 0;
};

/// join_tiles_to_ply()'s passes over the tiles, each asked for again in region order: the
/// components and their votes, the kept triangles, the output numbering, the vertices, the
/// triangles.
class TileJoin {
 public:
  TileJoin(const std::function<MeshTile(std::int32_t)>& tile_of, const RegionPlan& plan)
      : tile_of_(tile_of), numbering_(plan), n_(static_cast<std::int32_t>(plan.regions())) {}

  /// Pass 1: global numbers, votes, components (union-find), the vertices with triangles;
  /// the tiles' common origin and up axis, and whether a tile carries colors.
  void join_components() {
    std::vector<float> votes;
    for (std::int32_t k = 0; k < n_; ++k) {
      const MeshTile t = tile(k);
      if (k == 0) origin_ = t.mesh.origin, up_ = t.mesh.up;
      tile_colors_ = tile_colors_ || t.mesh.colors.rows() > 0;
      if (t.mesh.origin != origin_) throw OptionError("the mesh tiles are not of one tree (their origins differ)");
      parent_.resize(numbering_.count());
      votes.resize(numbering_.count(), 0.0f);
      flags_.resize(numbering_.count(), 0);
      for (std::size_t v = 0; v < id_.size(); ++v) {
        if (created_[v]) parent_[id_[v]] = id_[v];
        votes[id_[v]] += t.mesh.attributes[0].values(static_cast<Eigen::Index>(v));
      }
      for (Eigen::Index f = 0; f < t.mesh.triangles.rows(); ++f) {
        const std::uint32_t a = id_[static_cast<std::size_t>(t.mesh.triangles(f, 0))];
        flags_[a] |= kHasTriangle;
        for (int c = 1; c < 3; ++c) {
          const std::uint32_t ra = root(a), rb = root(id_[static_cast<std::size_t>(t.mesh.triangles(f, c))]);
          if (ra != rb) parent_[std::max(ra, rb)] = std::min(ra, rb);
        }
      }
    }
    // Each component's votes, at its root; the fragment test as join_tiles() decides it.
    total_ = numbering_.count();
    support_.assign(total_, 0.0f);
    for (std::uint32_t v = 0; v < total_; ++v) support_[root(v)] += votes[v];
  }

  /// Pass 2: the triangles of the components with `min_component_points` votes (or the best
  /// component's, when fewer), the vertices they use; then the output numbers.
  void keep_supported(std::size_t min_component_points, JoinedMesh& out) {
    float best = 0;
    for (std::uint32_t v = 0; v < total_; ++v)
      if (flags_[v] & kHasTriangle) best = std::max(best, support_[root(v)]);
    const double needed =
        min_component_points > 0 ? std::min(static_cast<double>(min_component_points), static_cast<double>(best)) : 0;
    for (std::int32_t k = 0; k < n_; ++k) {
      const MeshTile t = tile(k);
      for (Eigen::Index f = 0; f < t.mesh.triangles.rows(); ++f) {
        const std::uint32_t a = id_[static_cast<std::size_t>(t.mesh.triangles(f, 0))];
        if (!(support_[root(a)] >= needed)) continue;
        ++out.triangles;
        for (int c = 0; c < 3; ++c) flags_[id_[static_cast<std::size_t>(t.mesh.triangles(f, c))]] |= kUsed;
      }
    }
    std::vector<std::uint8_t> dropped_root(total_, 0);
    for (std::uint32_t v = 0; v < total_; ++v)
      if ((flags_[v] & kHasTriangle) && !(support_[root(v)] >= needed)) dropped_root[root(v)] = 1;
    for (std::uint32_t v = 0; v < total_; ++v) out.removed_components += dropped_root[v];
    // The union-find is done with: its storage numbers the output, the used vertices in global order.
    std::vector<std::uint32_t>& index = parent_;
    std::uint32_t next = 0;
    for (std::uint32_t v = 0; v < total_; ++v) index[v] = (flags_[v] & kUsed) ? next++ : 0;
    out.vertices = next;
    support_ = {};
  }

  /// Passes 3 and 4: the used vertices as they are created (colored by `colors`' nodes when
  /// given), then the kept triangles.
  void write(const std::filesystem::path& file, const JoinedMesh& out, const ImplicitSurface* colors) {
    const bool with_colors = colors != nullptr || tile_colors_;
    io::PlyMeshStream ply(file, out.vertices, out.triangles, true, with_colors, origin_, up_);
    for (std::int32_t k = 0; k < n_; ++k) {
      const MeshTile t = tile(k);
      std::vector<Eigen::Index> rows;
      for (std::size_t v = 0; v < id_.size(); ++v)
        if (created_[v] && (flags_[id_[v]] & kUsed)) rows.push_back(static_cast<Eigen::Index>(v));
      TriangleMesh part;
      part.vertices = t.mesh.vertices(rows, Eigen::all);
      part.normals = t.mesh.normals(rows, Eigen::all);
      if (colors != nullptr)
        part.colors = colors_by_node(part, *colors);
      else if (with_colors && t.mesh.colors.rows() == t.mesh.vertices.rows())
        part.colors = t.mesh.colors(rows, Eigen::all);
      else if (with_colors)
        part.colors.setConstant(part.vertices.rows(), 3, 128);  // a tile without colors
      ply.add_vertices(part.vertices, part.normals, part.colors);
    }
    for (std::int32_t k = 0; k < n_; ++k) {
      const MeshTile t = tile(k);
      Triangles kept(t.mesh.triangles.rows(), 3);
      Eigen::Index count = 0;
      for (Eigen::Index f = 0; f < t.mesh.triangles.rows(); ++f) {
        const std::uint32_t a = id_[static_cast<std::size_t>(t.mesh.triangles(f, 0))];
        if (!(flags_[a] & kUsed)) continue;  // kept with its component, whose vertices are then all used
        for (int c = 0; c < 3; ++c)
          kept(count, c) = static_cast<std::int32_t>(parent_[id_[static_cast<std::size_t>(t.mesh.triangles(f, c))]]);
        ++count;
      }
      kept.conservativeResize(count, 3);
      ply.add_triangles(kept);
    }
    ply.commit();
  }

 private:
  static constexpr std::uint8_t kHasTriangle = 1, kUsed = 2;

  /// Tile k, checked, numbered (id_, created_); tile 0 starts a pass over the tiles again.
  MeshTile tile(std::int32_t k) {
    if (k == 0) numbering_.restart();
    MeshTile t = tile_of_(k);
    const TriangleMesh& m = t.mesh;
    if (t.region != k || m.attributes.size() != 1 || m.attributes[0].values.size() != m.vertices.rows() ||
        m.normals.rows() != m.vertices.rows())
      throw OptionError("tile " + std::to_string(k) + " is not region " + std::to_string(k) +
                        "'s tile with normals and votes");
    numbering_.number(t, id_, created_);
    return t;
  }
  std::uint32_t root(std::uint32_t a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }

  const std::function<MeshTile(std::int32_t)>& tile_of_;
  Numbering numbering_;
  std::int32_t n_;
  std::vector<std::uint32_t> parent_, id_;  ///< union-find, then the output numbers; a tile's global numbers
  std::vector<std::uint8_t> flags_, created_;
  std::vector<float> support_;  ///< votes per component root
  std::uint32_t total_ = 0;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  UpAxis up_ = UpAxis::Y;
  bool tile_colors_ = false;  ///< a tile carries its points' colors
};

}  // namespace

JoinedMesh join_tiles_to_ply(const std::function<MeshTile(std::int32_t)>& tile_of, const RegionPlan& plan,
                             const TrimOptions& trim, const std::filesystem::path& file,
                             const ImplicitSurface* colors) {
  TileJoin join(tile_of, plan);
  JoinedMesh out;
  join.join_components();
  join.keep_supported(trim.min_component_points, out);
  join.write(file, out, colors);
  return out;
}

}  // namespace clustersurf
