#pragma once
// The interactive viewer: one self-contained HTML file (three.js bundled in, data embedded as
// base64 binary) showing the input points colored by cluster at any tree level, the mesh, the
// proxies as patches and the support spheres, next to a collapsible tree panel
// (`clustersurf view`, web/viewer/).

#include <clustersurf/cluster_tree.hpp>
#include <clustersurf/point_cloud.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

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

/// What write_viewer_html() wrote.
struct ViewerStats {
  std::size_t points = 0;        ///< points embedded
  std::size_t nodes = 0;         ///< tree nodes embedded
  std::size_t triangles = 0;     ///< mesh triangles embedded
  std::uintmax_t bytes = 0;      ///< size of the HTML file
};

/// Writes the viewer page for `tree` atomically (temporary file, then rename).
///
/// `cloud` (may be null: then only the tree's proxies and spheres are shown) must be the tree's
/// input, with exactly tree.input_points points, and the tree must hold its point→leaf table;
/// otherwise OptionError is thrown. `mesh` may be null. Positions are stored as float32
/// relative to the center of the tree's bounding box; node figures (errors, support spheres)
/// as float64. Each proxy patch covers the extent of its cluster's points (all of them, not
/// only the embedded ones) in the proxy's frame: poly proxies their height field, planes a
/// flat rectangle, quadrics their zero set along the frame's normal where it lies within the
/// support radius. Deterministic: the same inputs give the same bytes. Throws IoError.
ViewerStats write_viewer_html(const std::filesystem::path& file, const ClusterTree& tree, const PointCloud* cloud,
                              const TriangleMesh* mesh, const ViewerOptions& options = {});

}  // namespace clustersurf
