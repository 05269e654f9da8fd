// Pictures of a cluster tree: the surface and the views of its clusters, supports, proxies and
// error, traced through the hierarchy of support spheres.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/render.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/surface/palette.hpp>

#include <Eigen/Geometry>

#include "render/color_legend.hpp"
#include "render/pixel_loop.hpp"
#include "render/ray_support.hpp"
#include "render/surface_intersection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <utility>

namespace clustersurf {

namespace {

using render::Color;
using render::SampleResult;
using render::SupportSpan;
using render::SurfaceHit;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

const Color kGrey(0.72, 0.72, 0.72);
const Color kRed(0.90, 0.12, 0.10);

/// Everything a tile's tracer reads, computed once per picture.
struct Scene {
  const ClusterTree& tree;
  const RenderOptions& options;
  render::SupportIndex index;
  render::SupportSearch search;
  render::MarchSettings march;
  render::Lighting lights;
  double diagonal = 1;
  std::vector<double> radius_rank;  // Spheres: per node, rank of its radius among the cut in [0, 1]
  std::unique_ptr<KdTree> points;   // Error
  double error_scale = 0;
};

/// The node's ancestor at `depth` (the node itself when it is shallower).
std::int32_t ancestor_at(const ClusterTree& tree, std::int32_t node, std::uint32_t depth) {
  while (node > 0 && tree.nodes[static_cast<std::size_t>(node)].depth > depth)
    node = tree.nodes[static_cast<std::size_t>(node)].parent;
  return node;
}

bool in_subtree(const ClusterTree& tree, std::int32_t node, std::int32_t root) {
  while (node >= 0 && node != root) node = tree.nodes[static_cast<std::size_t>(node)].parent;
  return node == root;
}

/// The nearest hit of `node`'s proxy clipped to its patch sphere, with the proxy's normal.
std::optional<SurfaceHit> proxy_patch_hit(const Scene& scene, std::int32_t node, const Ray& ray) {
  const ClusterNode& n = scene.tree.nodes[static_cast<std::size_t>(node)];
  const auto clip = render::ray_sphere(ray, Sphere{n.support.center, std::min(n.support.radius, 0.5 * n.extent)});
  if (!clip || clip->second <= 0) return std::nullopt;
  const auto t = n.proxy.intersect(ray, std::max(clip->first, 0.0), clip->second);
  if (!t) return std::nullopt;
  SurfaceHit hit;
  hit.t = *t;
  hit.position = ray.origin + *t * ray.direction;
  const Eigen::Vector3d g = n.proxy.gradient(hit.position);
  hit.normal = g.norm() > 0 ? Eigen::Vector3d(g.normalized()) : Eigen::Vector3d(-ray.direction);
  hit.dominant = node;
  return hit;
}

/// The cone of the rays through pixels [x0, x1) × [y0, y1): its axis through the rectangle's
/// center, its half-angle that of the farthest corner (the angle to the axis is largest at a
/// corner of a convex region of the image plane): the smallest cosine, and the sine of the same
/// corner from a cross product (exact for small angles, where 1 − cos² cancels).
render::RayCone pixel_cone(const Camera& camera, int x0, int y0, int x1, int y1) {
  const double focal = camera.focal_pixels();
  render::RayCone cone;
  cone.apex = camera.eye;
  cone.axis = camera.ray(0.5 * (x0 + x1), 0.5 * (y0 + y1), focal).direction;
  for (const auto& [x, y] : {std::pair{x0, y0}, std::pair{x1, y0}, std::pair{x0, y1}, std::pair{x1, y1}}) {
    const Eigen::Vector3d d = camera.ray(x, y, focal).direction;
    const double c = std::clamp(d.dot(cone.axis), -1.0, 1.0);
    if (c < cone.cos_half) cone.cos_half = c, cone.sin_half = d.cross(cone.axis).norm();
  }
  return cone;
}

/// Traces one tile's rays; owns the tile's scratch memory.
class TreeTracer {
 public:
  /// The tracer of the pixels [x0, x1) × [y0, y1): the supports its rays may cross are found
  /// once, through the hierarchy, from the cone of the tile's rays (brute force: all of them).
  TreeTracer(const Scene& scene, const Camera& camera, int x0, int y0, int x1, int y1) : s_(scene), camera_(camera) {
    if (s_.search == render::SupportSearch::BruteForce) {
      s_.index.gather(s_.index.cut(), tile_supports_);
      return;
    }
    const render::RayCone cone = pixel_cone(camera, x0, y0, x1, y1);
    s_.index.collect_in_cone(cone.apex, cone.axis, cone.half_angle(), tile_nodes_);
    s_.index.gather(tile_nodes_, tile_supports_);
  }

  /// Narrows the tile's supports to those the rays of the patch [x0, x1) × [y0, y1) may cross.
  void enter_patch(int x0, int y0, int x1, int y1) {
    if (s_.search == render::SupportSearch::BruteForce) return;
    const render::RayCone cone = pixel_cone(camera_, x0, y0, x1, y1);
    render::cull_to_cone(tile_supports_, cone, patch_supports_);
    render::order_along(cone, patch_supports_);
  }

  /// Narrows the patch's supports to those the rays of the block [x0, x1) × [y0, y1) may cross;
  /// returns whether a ray of the block may see anything (a highlighted proxy always may).
  bool enter_block(int x0, int y0, int x1, int y1) {
    if (s_.search == render::SupportSearch::BruteForce) return true;
    render::cull_to_cone(patch_supports_, pixel_cone(camera_, x0, y0, x1, y1), block_supports_);
    supports_ = &block_supports_;
    return !block_supports_.nodes.empty() || s_.options.highlight.has_value();
  }

  SampleResult operator()(const Ray& ray, std::uint64_t seed) {
    s_.index.collect_from(ray, 0, kInfinity, *supports_, spans_);
    switch (s_.options.show) {
      case ShowMode::Spheres:
        return spheres(ray);
      case ShowMode::Proxies:
        return proxies(ray);
      default:
        return surface(ray, seed);
    }
  }

 private:
  std::optional<SurfaceHit> surface_hit(const Ray& ray, std::vector<SupportSpan>& spans, double t_min, double t_max) {
    if (s_.options.mode == IntersectMode::HitBlend)
      return render::blended_hit(s_.tree, spans, ray, t_min, t_max, s_.march.min_weight);
    return render::first_zero(s_.tree, spans, ray, t_min, t_max, s_.march);
  }

  /// Fraction of short rays from the hit that escape (1: open).
  double openness(const SurfaceHit& hit, const Ray& ray, std::uint64_t seed) {
    Eigen::Vector3d n = hit.normal;
    if (n.dot(ray.direction) > 0) n = -n;
    const double reach = render::kOcclusionReach * s_.diagonal;
    return render::ambient_occlusion(n, seed, [&](const Eigen::Vector3d& d) {
      const Ray r{hit.position + render::kOcclusionOffset * s_.diagonal * n, d};
      s_.index.collect(r, 0, reach, s_.search, ao_spans_);
      return surface_hit(r, ao_spans_, 0, reach).has_value();
    });
  }

  SampleResult surface(const Ray& ray, std::uint64_t seed) {
    const auto hit = surface_hit(ray, spans_, 0, kInfinity);
    std::optional<SurfaceHit> patch;
    if (s_.options.highlight) patch = proxy_patch_hit(s_, *s_.options.highlight, ray);
    SampleResult out;
    if (hit) {
      Color base = render::kSurfaceColor;
      switch (s_.options.show) {
        case ShowMode::Clusters: {
          std::int32_t node = hit->dominant;
          if (s_.options.level && node >= 0) node = ancestor_at(s_.tree, node, *s_.options.level);
          base = node >= 0 ? render::to_color(node_color(node)) : kGrey;
          break;
        }
        case ShowMode::Error: {
          const auto nb = s_.points->knn(hit->position, 1);
          base =
              render::to_color(distance_color(nb.empty() ? 1.0 : std::sqrt(nb[0].distance_squared) / s_.error_scale));
          break;
        }
        default:
          break;
      }
      if (s_.options.highlight)
        base = hit->dominant >= 0 && in_subtree(s_.tree, hit->dominant, *s_.options.highlight) ? kRed : kGrey;
      const double occlusion = s_.options.ambient_occlusion ? openness(*hit, ray, seed) : 1.0;
      out = {render::shade(s_.lights, hit->normal, ray.direction, base, occlusion), 1.0};
    }
    if (patch && (!hit || patch->t < hit->t + 0.002 * s_.diagonal)) {
      // The highlighted node's proxy, translucent over what is behind it.
      const Color red = render::shade(s_.lights, patch->normal, ray.direction, Color(0.75, 0.05, 0.05));
      constexpr double kPatchAlpha = 0.55;
      const double alpha = kPatchAlpha + (1 - kPatchAlpha) * out.alpha;
      out.rgb = (kPatchAlpha * red + (1 - kPatchAlpha) * out.alpha * out.rgb) / alpha;
      out.alpha = alpha;
    }
    return out;
  }

  SampleResult spheres(const Ray& ray) const {
    const SupportSpan* best = nullptr;
    for (const SupportSpan& sp : spans_)  // sorted by entry: the first one entered from outside
      if (sp.t_enter > 0) {
        best = &sp;
        break;
      }
    if (best == nullptr) return {};
    const ClusterNode& n = s_.tree.nodes[static_cast<std::size_t>(best->node)];
    const Eigen::Vector3d x = ray.origin + best->t_enter * ray.direction;
    const Color base = render::rank_color(s_.radius_rank[static_cast<std::size_t>(best->node)]);
    return {render::shade(s_.lights, (x - n.support.center).normalized(), ray.direction, base), 1.0};
  }

  SampleResult proxies(const Ray& ray) const {
    std::optional<SurfaceHit> best;
    for (const SupportSpan& sp : spans_) {
      if (best && sp.t_enter > best->t) break;  // later supports cannot hold a nearer patch
      const auto hit = proxy_patch_hit(s_, sp.node, ray);
      if (hit && (!best || hit->t < best->t || (hit->t == best->t && hit->dominant < best->dominant))) best = hit;
    }
    if (!best) return {};
    return {render::shade(s_.lights, best->normal, ray.direction, render::to_color(node_color(best->dominant))), 1.0};
  }

  const Scene& s_;
  const Camera& camera_;
  std::vector<std::int32_t> tile_nodes_;
  render::SupportSet tile_supports_;   // their supports, side by side
  render::SupportSet patch_supports_;  // those of the current patch
  render::SupportSet block_supports_;  // those of the current block
  const render::SupportSet* supports_ = &tile_supports_;
  std::vector<SupportSpan> spans_;
  std::vector<SupportSpan> ao_spans_;
};

}  // namespace

std::optional<RayHit> intersect_surface(const ClusterTree& tree, const Ray& ray, const RenderOptions& options) {
  const render::SupportIndex index(tree, options.lod);
  const auto search =
      options.mode == IntersectMode::BruteForce ? render::SupportSearch::BruteForce : render::SupportSearch::Hierarchy;
  std::vector<SupportSpan> spans;
  index.collect(ray, 0, kInfinity, search, spans);
  render::MarchSettings march;
  march.min_weight = options.min_weight;
  march.tolerance = 1e-6 * (tree.bbox.diagonal() > 0 ? tree.bbox.diagonal() : 1.0);
  const auto hit = options.mode == IntersectMode::HitBlend
                       ? render::blended_hit(tree, spans, ray, 0, kInfinity, options.min_weight)
                       : render::first_zero(tree, spans, ray, 0, kInfinity, march);
  if (!hit) return std::nullopt;
  return RayHit{hit->t, hit->position, hit->normal, hit->dominant};
}

Image render_tree(const ClusterTree& tree, const RenderOptions& options, RenderStats* stats,
                  const ProgressCallback& progress) {
  render::check_common_options(options);
  if (tree.nodes.empty()) throw OptionError("cannot render an empty tree");
  if (options.highlight &&
      (*options.highlight < 0 || static_cast<std::size_t>(*options.highlight) >= tree.nodes.size()))
    throw OptionError("highlight: node " + std::to_string(*options.highlight) + " does not exist (the tree has " +
                      std::to_string(tree.nodes.size()) + " nodes)");
  if (options.show == ShowMode::Error && (options.reference_points == nullptr || options.reference_points->rows() == 0))
    throw OptionError("show error needs the input points (points)");

  const Camera camera = render::scene_camera(options, tree.bbox, tree.origin, tree.up);
  Scene scene{
      tree,
      options,
      render::SupportIndex(tree, options.lod),
      options.mode == IntersectMode::BruteForce ? render::SupportSearch::BruteForce : render::SupportSearch::Hierarchy,
      {},
      render::camera_lighting(camera),
      {},
      {},
      {},
      {}};
  scene.diagonal = tree.bbox.diagonal() > 0 ? tree.bbox.diagonal() : 1.0;
  scene.march.min_weight = options.min_weight;
  scene.march.tolerance = 1e-6 * scene.diagonal;
  if (options.show == ShowMode::Spheres) {
    std::vector<std::int32_t> order = scene.index.cut();
    std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
      return tree.nodes[static_cast<std::size_t>(a)].support.radius <
             tree.nodes[static_cast<std::size_t>(b)].support.radius;
    });
    scene.radius_rank.assign(tree.nodes.size(), 0.0);
    for (std::size_t k = 0; k < order.size(); ++k)
      scene.radius_rank[static_cast<std::size_t>(order[k])] =
          order.size() > 1 ? static_cast<double>(k) / static_cast<double>(order.size() - 1) : 0.5;
  }
  if (options.show == ShowMode::Error) {
    scene.points = std::make_unique<KdTree>(*options.reference_points);
    scene.error_scale = options.error_scale.value_or(0.005 * scene.diagonal);
  }

  Image image = render::trace_image(
      camera, options, [&](int x0, int y0, int x1, int y1) { return TreeTracer(scene, camera, x0, y0, x1, y1); }, stats,
      progress);
  if (options.show == ShowMode::Error) {
    render::draw_color_legend(image, scene.error_scale, "distance to input");
    if (stats != nullptr) stats->error_scale = scene.error_scale;
  }
  return image;
}

}  // namespace clustersurf
