#pragma once
// The interactive viewer: one self-contained HTML file (three.js bundled in, data embedded as
// base64 binary) showing the input points colored by cluster at any tree level, the mesh, the
// proxies as patches and the support spheres, next to a collapsible tree panel
// (`clustersurf view`, web/viewer/). The page also opens .glb meshes the user picks or drops.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/point_cloud.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace clustersurf {

/// Options of write_viewer_html().
struct ViewerOptions {
  /// At most this many points are embedded; larger clouds keep points floor(k·n / max_points),
  /// k = 0, 1, ... (deterministic, spread over the input order). 0: no limit. The points are
  /// stored in an order whose every prefix is spread evenly over the input: the viewer draws a
  /// prefix while the camera moves.
  std::size_t max_points = 2'000'000;
  /// Grid vertices along each side of a proxy patch (≥ 2).
  std::uint32_t patch_grid = 6;
  /// Shown as the page's title (typically the tree file's name).
  std::string title = "clustersurf";
};

/// A mesh as the bytes of a glTF binary file (.glb, e.g. from write_glb()): embedded in the page
/// as they are and parsed there (three.js GLTFLoader).
struct GlbMesh {
  std::vector<std::uint8_t> bytes;
  std::filesystem::path file;  ///< where the bytes came from, for error messages (may be empty)
};

/// Reads a .glb file whole. Throws IoError; the content is checked by write_viewer_html().
GlbMesh read_glb_file(const std::filesystem::path& file);

/// What write_viewer_html() wrote.
struct ViewerStats {
  std::size_t points = 0;     ///< points embedded
  std::size_t nodes = 0;      ///< tree nodes embedded
  std::size_t triangles = 0;  ///< mesh triangles embedded
  std::uintmax_t bytes = 0;   ///< size of the HTML file
};

/// Writes the viewer page for `tree` atomically (temporary file, then rename).
///
/// `cloud` (may be null: then the page shows the leaf proxies and their support spheres by
/// default) must be the tree's input, with exactly tree.input_points points, and the tree must
/// hold its point→leaf table; otherwise OptionError is thrown. `mesh` may be null; it is placed
/// by its origin (TriangleMesh::origin) in the tree's frame. Positions are stored as float32
/// relative to the center of the tree's bounding box (itself relative to tree.origin, which the
/// page also holds); node figures (errors, support spheres) as float64. Each proxy patch covers the extent of its
/// cluster's points (all of them, not only the embedded ones) in the proxy's frame: poly proxies their height field,
/// planes a flat rectangle, quadrics their zero set along the frame's normal where it lies within the support radius.
/// Deterministic: the same inputs give the same bytes. Throws IoError.
ViewerStats write_viewer_html(const std::filesystem::path& file, const ClusterTree& tree, const PointCloud* cloud,
                              const TriangleMesh* mesh, const ViewerOptions& options = {});

/// The same page with a glTF binary mesh: its bytes are embedded as they are and the page shows
/// its scene in the tree's frame (file coordinates minus tree.origin: a root node translated by
/// the tree's origin, as write_glb() writes it, lands exactly on the tree). InputError when the
/// bytes are not a self-contained glTF 2.0 binary (bad header or JSON, external buffers or
/// images).
ViewerStats write_viewer_html(const std::filesystem::path& file, const ClusterTree& tree, const PointCloud* cloud,
                              const GlbMesh& mesh, const ViewerOptions& options = {});

}  // namespace clustersurf
