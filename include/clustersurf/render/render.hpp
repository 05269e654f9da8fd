#pragma once
// Pictures of a cluster tree's surface (thesis ch. 5–6), and of meshes and point clouds with
// the same camera: a tiled, multi-threaded ray tracer over the hierarchy of support spheres.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/progress.hpp>
#include <clustersurf/render/camera.hpp>
#include <clustersurf/render/image.hpp>
#include <clustersurf/surface/implicit_surface.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace clustersurf {

/// How a ray finds the surface of a tree.
enum class IntersectMode : std::uint8_t {
  Implicit,    ///< first zero of the blended f along the ray (supports found through the hierarchy)
  HitBlend,    ///< the thesis's method: intersect each leaf proxy, blend the hits by the weights
  BruteForce,  ///< Implicit with every leaf's support tested per ray (no hierarchy): same picture
};
/// What the picture shows.
enum class ShowMode : std::uint8_t {
  Surface,   ///< the surface, shaded
  Clusters,  ///< the surface colored by the dominant leaf (or its ancestor at `level`)
  Spheres,   ///< the leaf support spheres, colored by radius rank red → green → blue
  Proxies,   ///< each leaf proxy as a patch clipped to its cluster's extent
  Error,     ///< the surface colored green → red by distance to the nearest input point
};

const char* to_string(IntersectMode mode);
const char* to_string(ShowMode mode);
/// The mode named by to_string(); throws OptionError for any other name.
IntersectMode parse_intersect_mode(const std::string& name);
/// The view named by to_string(); throws OptionError for any other name.
ShowMode parse_show_mode(const std::string& name);
/// A background: "transparent", "white", "black" or "#rrggbb"; throws OptionError otherwise.
Rgba8 parse_background(const std::string& text);

/// Options of the renderers; the defaults make a 1280 × 960 picture of the surface.
struct RenderOptions {
  int width = 1280;
  int height = 960;
  int samples = 1;  ///< rays per pixel (jittered deterministically from the pixel index)
  IntersectMode mode = IntersectMode::Implicit;
  ShowMode show = ShowMode::Surface;
  CameraOptions camera;
  /// Frame this box instead of the input's bounding box (the same camera for several inputs).
  /// The framing and camera.eye / camera.target are in the input file's coordinates (a scene's
  /// stored coordinates plus its origin), so scenes far from zero share one camera.
  std::optional<BoundingBox> framing;
  LevelOfDetail lod;  ///< which tree nodes are blended (default: the leaves)
  /// Surface defined only where the total weight exceeds this (as MeshOptions::min_weight, so
  /// the picture matches the mesh).
  double min_weight = kMinWeight;
  std::optional<std::uint32_t> level;        ///< Clusters: color by the ancestor at this depth
  std::optional<std::int32_t> highlight;     ///< draw this node's cluster and proxy in red
  const Points* reference_points = nullptr;  ///< Error: the input points (required)
  std::optional<double> error_scale;         ///< Error: distance shown full red; default 0.005 × diagonal
  bool ambient_occlusion = false;            ///< darken creases (8 short occlusion rays per hit)
  Rgba8 background{255, 255, 255, 255};
  double point_radius = 0;  ///< point clouds: splat radius; 0: 0.75 × mean spacing
};

/// Figures of one rendering.
struct RenderStats {
  double seconds = 0;          ///< wall time of the ray tracing (without setup)
  std::uint64_t rays = 0;      ///< primary rays: samples × pixels, counting those of blocks that see nothing
  std::uint64_t hits = 0;      ///< primary rays that hit
  double rays_per_second = 0;  ///< rays / seconds
  double error_scale = 0;      ///< Error mode: distance shown full red
};

/// A surface point found along one ray.
struct RayHit {
  double t = 0;  ///< ray parameter (unit direction: distance)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, direction of ∇f (outside)
  std::int32_t node = -1;                             ///< blended node of largest weight there
};

/// The first point of `tree`'s surface along `ray` (unit direction, t ≥ 0) as render_tree()
/// finds it with options.mode, options.lod and options.min_weight. For single rays (it sets up
/// the tree cut on every call).
std::optional<RayHit> intersect_surface(const ClusterTree& tree, const Ray& ray, const RenderOptions& options = {});

/// Renders `tree` (its implicit surface or one of the ShowMode views). Deterministic: the same
/// picture for any thread count. Throws OptionError for invalid options, Cancelled when
/// `progress` says stop (as do render_mesh() and render_points()).
Image render_tree(const ClusterTree& tree, const RenderOptions& options, RenderStats* stats = nullptr,
                  const ProgressCallback& progress = {});
/// Renders a triangle mesh (vertex colors and normals used when present) with the same camera
/// conventions as render_tree(). A mesh far from zero (georeferenced coordinates) is drawn
/// moved next to it (origin_shift()), so float precision does not open gaps between triangles.
Image render_mesh(const TriangleMesh& mesh, const RenderOptions& options, RenderStats* stats = nullptr,
                  const ProgressCallback& progress = {});
/// Renders a point cloud as small discs (oriented by the normals, spheres without normals),
/// moved next to zero as render_mesh() moves a mesh.
Image render_points(const PointCloud& cloud, const RenderOptions& options, RenderStats* stats = nullptr,
                    const ProgressCallback& progress = {});

}  // namespace clustersurf
