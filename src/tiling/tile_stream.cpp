// The tiles of a tiled mesh joined straight into a PLY file, one tile in memory at a time.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>
#include <clustersurf/tiling/tiling.hpp>

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

}  // namespace

JoinedMesh join_tiles_to_ply(const std::function<MeshTile(std::int32_t)>& tile_of, const RegionPlan& plan,
                             const TrimOptions& trim, const std::filesystem::path& file,
                             const ImplicitSurface* colors) {
  const auto n = static_cast<std::int32_t>(plan.regions());
  const auto get = [&](std::int32_t k) {
    MeshTile t = tile_of(k);
    const TriangleMesh& m = t.mesh;
    if (t.region != k || m.attributes.size() != 1 || m.attributes[0].values.size() != m.vertices.rows() ||
        m.normals.rows() != m.vertices.rows())
      throw OptionError("tile " + std::to_string(k) + " is not region " + std::to_string(k) +
                        "'s tile with normals and votes");
    return t;
  };
  // Pass 1: numbers, votes, components (union-find), which vertices have triangles.
  Numbering numbering(plan);
  std::vector<std::uint32_t> parent, id;
  std::vector<float> votes;
  std::vector<std::uint8_t> flags, created;  // flags: 1 has a triangle, 2 used by a kept triangle
  const auto root = [&](std::uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  UpAxis up = UpAxis::Y;
  bool tile_colors = false;  // a tile carries its points' colors
  for (std::int32_t k = 0; k < n; ++k) {
    const MeshTile t = get(k);
    if (k == 0) origin = t.mesh.origin, up = t.mesh.up;
    tile_colors = tile_colors || t.mesh.colors.rows() > 0;
    if (t.mesh.origin != origin) throw OptionError("the mesh tiles are not of one tree (their origins differ)");
    numbering.number(t, id, created);
    parent.resize(numbering.count());
    votes.resize(numbering.count(), 0.0f);
    flags.resize(numbering.count(), 0);
    for (std::size_t v = 0; v < id.size(); ++v) {
      if (created[v]) parent[id[v]] = id[v];
      votes[id[v]] += t.mesh.attributes[0].values(static_cast<Eigen::Index>(v));
    }
    for (Eigen::Index f = 0; f < t.mesh.triangles.rows(); ++f) {
      const std::uint32_t a = id[static_cast<std::size_t>(t.mesh.triangles(f, 0))];
      flags[a] |= 1;
      for (int c = 1; c < 3; ++c) {
        const std::uint32_t ra = root(a), rb = root(id[static_cast<std::size_t>(t.mesh.triangles(f, c))]);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
      }
    }
  }
  // Each component's votes, at its root; the fragment test as join_tiles() decides it.
  const std::uint32_t total = numbering.count();
  std::vector<float> support(total, 0.0f);
  for (std::uint32_t v = 0; v < total; ++v) support[root(v)] += votes[v];
  votes = {};
  float best = 0;
  for (std::uint32_t v = 0; v < total; ++v)
    if (flags[v] & 1) best = std::max(best, support[root(v)]);
  const double needed = trim.min_component_points > 0
                            ? std::min(static_cast<double>(trim.min_component_points), static_cast<double>(best))
                            : 0;
  // Pass 2: the kept triangles and the vertices they use.
  JoinedMesh out;
  numbering.restart();
  for (std::int32_t k = 0; k < n; ++k) {
    const MeshTile t = get(k);
    numbering.number(t, id, created);
    for (Eigen::Index f = 0; f < t.mesh.triangles.rows(); ++f) {
      const std::uint32_t a = id[static_cast<std::size_t>(t.mesh.triangles(f, 0))];
      if (!(support[root(a)] >= needed)) continue;
      ++out.triangles;
      for (int c = 0; c < 3; ++c) flags[id[static_cast<std::size_t>(t.mesh.triangles(f, c))]] |= 2;
    }
  }
  // Output numbers: the used vertices in global order.
  {
    std::vector<std::uint8_t> dropped_root(total, 0);
    for (std::uint32_t v = 0; v < total; ++v)
      if ((flags[v] & 1) && !(support[root(v)] >= needed)) dropped_root[root(v)] = 1;
    for (std::uint32_t v = 0; v < total; ++v) out.removed_components += dropped_root[v];
  }
  std::vector<std::uint32_t>& index = parent;  // the union-find is done with: its storage numbers the output
  std::uint32_t next = 0;
  for (std::uint32_t v = 0; v < total; ++v) index[v] = (flags[v] & 2) ? next++ : 0;
  out.vertices = next;
  support = {};

  // Passes 3 and 4: the used vertices as they are created, then the kept triangles.
  const bool with_colors = colors != nullptr || tile_colors;
  io::PlyMeshStream ply(file, out.vertices, out.triangles, true, with_colors, origin, up);
  numbering.restart();
  for (std::int32_t k = 0; k < n; ++k) {
    const MeshTile t = get(k);
    numbering.number(t, id, created);
    std::vector<Eigen::Index> rows;
    for (std::size_t v = 0; v < id.size(); ++v)
      if (created[v] && (flags[id[v]] & 2)) rows.push_back(static_cast<Eigen::Index>(v));
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
  numbering.restart();
  for (std::int32_t k = 0; k < n; ++k) {
    const MeshTile t = get(k);
    numbering.number(t, id, created);
    Triangles kept(t.mesh.triangles.rows(), 3);
    Eigen::Index count = 0;
    for (Eigen::Index f = 0; f < t.mesh.triangles.rows(); ++f) {
      const std::uint32_t a = id[static_cast<std::size_t>(t.mesh.triangles(f, 0))];
      if (!(flags[a] & 2)) continue;  // kept with its component, whose vertices are then all used
      for (int c = 0; c < 3; ++c)
        kept(count, c) = static_cast<std::int32_t>(index[id[static_cast<std::size_t>(t.mesh.triangles(f, c))]]);
      ++count;
    }
    kept.conservativeResize(count, 3);
    ply.add_triangles(kept);
  }
  ply.commit();
  return out;
}

}  // namespace clustersurf
