// Names and validation of the render options.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/render.hpp>

#include "render/pixel_loop.hpp"

#include <cmath>
#include <cstdio>

namespace clustersurf {

const char* to_string(IntersectMode mode) {
  switch (mode) {
    case IntersectMode::Implicit:
      return "implicit";
    case IntersectMode::HitBlend:
      return "hit-blend";
    case IntersectMode::BruteForce:
      return "brute-force";
  }
  return "unknown";
}

const char* to_string(ShowMode mode) {
  switch (mode) {
    case ShowMode::Surface:
      return "surface";
    case ShowMode::Clusters:
      return "clusters";
    case ShowMode::Spheres:
      return "spheres";
    case ShowMode::Proxies:
      return "proxies";
    case ShowMode::Error:
      return "error";
  }
  return "unknown";
}

IntersectMode parse_intersect_mode(const std::string& name) {
  for (IntersectMode m : {IntersectMode::Implicit, IntersectMode::HitBlend, IntersectMode::BruteForce})
    if (name == to_string(m)) return m;
  throw OptionError("mode must be implicit, hit-blend or brute-force, not \"" + name + "\"");
}

ShowMode parse_show_mode(const std::string& name) {
  for (ShowMode m : {ShowMode::Surface, ShowMode::Clusters, ShowMode::Spheres, ShowMode::Proxies, ShowMode::Error})
    if (name == to_string(m)) return m;
  throw OptionError("show must be surface, clusters, spheres, proxies or error, not \"" + name + "\"");
}

Rgba8 parse_background(const std::string& text) {
  if (text == "transparent") return {255, 255, 255, 0};
  if (text == "white") return {255, 255, 255, 255};
  if (text == "black") return {0, 0, 0, 255};
  unsigned r = 0, g = 0, b = 0;
  char tail = 0;
  if (text.size() == 7 && std::sscanf(text.c_str(), "#%2x%2x%2x%c", &r, &g, &b, &tail) == 3)
    return {static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b), 255};
  throw OptionError("background must be transparent, white, black or #rrggbb, not \"" + text + "\"");
}

namespace render {

void check_common_options(const RenderOptions& options) {
  if (options.width <= 0 || options.height <= 0 || options.width > 32768 || options.height > 32768)
    throw OptionError("picture width and height must be in [1, 32768]");
  if (options.samples < 1 || options.samples > 1024) throw OptionError("samples per pixel must be in [1, 1024]");
  if (!(options.min_weight >= 0) || !std::isfinite(options.min_weight)) throw OptionError("min_weight must be >= 0");
  if (options.error_scale && !(*options.error_scale > 0)) throw OptionError("the error scale must be positive");
  if (!(options.point_radius >= 0) || !std::isfinite(options.point_radius))
    throw OptionError("point radius must be >= 0");
}

Camera scene_camera(const RenderOptions& options, const BoundingBox& own, const Eigen::Vector3d& origin, UpAxis up) {
  BoundingBox box = own;
  if (options.framing && !options.framing->empty())
    box = BoundingBox{options.framing->min - origin, options.framing->max - origin};
  CameraOptions camera = options.camera;
  if (camera.eye) *camera.eye -= origin;
  if (camera.target) *camera.target -= origin;
  if (!camera.up) camera.up = up_vector(up);
  return make_camera(box, camera, options.width, options.height);
}

}  // namespace render

}  // namespace clustersurf
