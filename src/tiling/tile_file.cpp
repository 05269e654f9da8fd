// A tiled run's mesh tiles: one region's mesh, its grid and merge reports and its vertices' votes, in a
// small binary file (little-endian, checked whole on reading).

#include <clustersurf/core/errors.hpp>

#include "io/atomic_file.hpp"
#include "tiling/tiled_run_files.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

namespace clustersurf::detail {

namespace {

constexpr char kTileMagic[8] = {'C', 'S', 'T', 'I', 'L', 'E', '3', '\n'};
/// The flags of a tile's header.
constexpr std::int64_t kTileColors = 1, kTileZUp = 2;

}  // namespace

void write_tile(const std::filesystem::path& file, const MeshTile& tile) {
  const TriangleMesh& m = tile.mesh;
  io::AtomicFile out(file);
  out.write(kTileMagic, sizeof kTileMagic);
  const bool colors = m.colors.rows() == m.vertices.rows() && m.vertices.rows() > 0;
  const std::int64_t header[8] = {tile.region,
                                  static_cast<std::int64_t>(m.vertices.rows()),
                                  static_cast<std::int64_t>(m.triangles.rows()),
                                  static_cast<std::int64_t>(tile.grid.surface_cells),
                                  static_cast<std::int64_t>(tile.grid.evaluated_corners),
                                  (colors ? kTileColors : 0) | (m.up == UpAxis::Z ? kTileZUp : 0),
                                  static_cast<std::int64_t>(tile.coarsening.triangles_before),
                                  static_cast<std::int64_t>(tile.coarsening.merged_blocks)};
  out.write(header, sizeof header);
  out.write(&tile.grid.voxel_size, sizeof(double));
  out.write(&tile.coarsening.tolerance, sizeof(double));
  out.write(m.origin.data(), 3 * sizeof(double));
  out.write(m.vertices.data(), static_cast<std::size_t>(m.vertices.size()) * sizeof(double));
  out.write(m.normals.data(), static_cast<std::size_t>(m.normals.size()) * sizeof(double));
  out.write(m.attributes.at(0).values.data(), static_cast<std::size_t>(m.vertices.rows()) * sizeof(float));
  if (colors) out.write(m.colors.data(), static_cast<std::size_t>(m.colors.size()));
  out.write(m.triangles.data(), static_cast<std::size_t>(m.triangles.size()) * sizeof(std::int32_t));
  out.commit();
}

MeshTile read_tile(const std::filesystem::path& file) {
  const std::string bytes = read_text(file);
  std::size_t at = 0;
  const auto take = [&](void* out, std::size_t n, const char* what) {
    if (n > bytes.size() - at)
      throw InputError(file, FileLocation{std::nullopt, at},
                       std::string("file ends inside ") + what + " (not a whole mesh tile)");
    if (n > 0) std::memcpy(out, bytes.data() + at, n);  // an empty matrix has no storage
    at += n;
  };
  char magic[sizeof kTileMagic];
  take(magic, sizeof magic, "the signature");
  if (std::memcmp(magic, kTileMagic, sizeof magic) != 0)
    throw InputError(file, FileLocation{std::nullopt, 0}, "not a clustersurf mesh tile");
  std::int64_t header[8];
  take(header, sizeof header, "the header");
  const std::int64_t nv = header[1], nt = header[2];
  const std::uint64_t per_vertex = 6 * sizeof(double) + sizeof(float), per_triangle = 3 * sizeof(std::int32_t);
  if (header[0] < 0 || header[0] > std::numeric_limits<std::int32_t>::max() || header[3] < 0 || header[4] < 0 ||
      header[6] < 0 || header[7] < 0)
    throw InputError(file, FileLocation{std::nullopt, sizeof kTileMagic}, "region, cell or merge counts out of range");
  if ((header[5] & ~(kTileColors | kTileZUp)) != 0)
    throw InputError(file, FileLocation{std::nullopt, sizeof kTileMagic + 5 * sizeof(std::int64_t)},
                     "unknown tile flags");
  if (nv < 0 || nt < 0 || static_cast<std::uint64_t>(nv) > bytes.size() / per_vertex ||
      static_cast<std::uint64_t>(nt) > bytes.size() / per_triangle)
    throw InputError(file, FileLocation{std::nullopt, sizeof kTileMagic + 8},
                     "vertex or triangle count out of range for the file's size");
  MeshTile tile;
  tile.region = static_cast<std::int32_t>(header[0]);
  tile.grid.surface_cells = static_cast<std::size_t>(header[3]);
  tile.grid.evaluated_corners = static_cast<std::size_t>(header[4]);
  tile.coarsening.triangles_before = static_cast<std::size_t>(header[6]);
  tile.coarsening.triangles_after = static_cast<std::size_t>(nt);
  tile.coarsening.merged_blocks = static_cast<std::size_t>(header[7]);
  const std::size_t voxel_at = at;
  take(&tile.grid.voxel_size, sizeof(double), "the header");
  if (!(tile.grid.voxel_size > 0) || !std::isfinite(tile.grid.voxel_size))
    throw InputError(file, FileLocation{std::nullopt, voxel_at}, "the cell size must be a positive number");
  const std::size_t tolerance_at = at;
  take(&tile.coarsening.tolerance, sizeof(double), "the header");
  if (!(tile.coarsening.tolerance >= 0) || !std::isfinite(tile.coarsening.tolerance))
    throw InputError(file, FileLocation{std::nullopt, tolerance_at}, "the merge tolerance must be a number >= 0");
  TriangleMesh& m = tile.mesh;
  const std::size_t origin_at = at;
  take(m.origin.data(), 3 * sizeof(double), "the origin");
  if (!m.origin.allFinite()) throw InputError(file, FileLocation{std::nullopt, origin_at}, "the origin is not finite");
  m.vertices.resize(nv, 3);
  m.normals.resize(nv, 3);
  Eigen::VectorXf votes(nv);
  m.triangles.resize(nt, 3);
  take(m.vertices.data(), static_cast<std::size_t>(nv) * 3 * sizeof(double), "the vertices");
  take(m.normals.data(), static_cast<std::size_t>(nv) * 3 * sizeof(double), "the normals");
  take(votes.data(), static_cast<std::size_t>(nv) * sizeof(float), "the votes");
  if ((header[5] & kTileColors) != 0) {
    m.colors.resize(nv, 3);
    take(m.colors.data(), static_cast<std::size_t>(nv) * 3, "the colors");
  }
  m.up = (header[5] & kTileZUp) != 0 ? UpAxis::Z : UpAxis::Y;
  const std::size_t triangles_at = at;
  take(m.triangles.data(), static_cast<std::size_t>(nt) * 3 * sizeof(std::int32_t), "the triangles");
  if (at != bytes.size())
    throw InputError(file, FileLocation{std::nullopt, at}, "unexpected bytes after the triangles");
  if (!m.vertices.allFinite() || !m.normals.allFinite() || !votes.allFinite() || (nv > 0 && votes.minCoeff() < 0))
    throw InputError(file, FileLocation{std::nullopt, sizeof kTileMagic},
                     "a vertex, normal or vote is not a finite number (votes >= 0)");
  for (Eigen::Index t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      if (m.triangles(t, k) < 0 || m.triangles(t, k) >= nv)
        throw InputError(
            file, FileLocation{std::nullopt, triangles_at + static_cast<std::size_t>(3 * t + k) * sizeof(std::int32_t)},
            "triangle " + std::to_string(t) + " names vertex " + std::to_string(m.triangles(t, k)) + " of " +
                std::to_string(nv));
  m.attributes.push_back({"votes", std::move(votes)});
  return tile;
}

}  // namespace clustersurf::detail
