// Names and validation of the render options.

#include <clustersurf/errors.hpp>
#include <clustersurf/render.hpp>

#include "render/pixel_loop.hpp"

#include <cmath>

namespace clustersurf {

const char* to_string(IntersectMode mode) {
  switch (mode) {
    case IntersectMode::Implicit: return "implicit";
    case IntersectMode::HitBlend: return "hit-blend";
    case IntersectMode::BruteForce: return "brute-force";
  }
  return "unknown";
}

const char* to_string(ShowMode mode) {
  switch (mode) {
    case ShowMode::Surface: return "surface";
    case ShowMode::Clusters: return "clusters";
    case ShowMode::Spheres: return "spheres";
    case ShowMode::Proxies: return "proxies";
    case ShowMode::Error: return "error";
  }
  return "unknown";
}

namespace render {

void check_common_options(const RenderOptions& options) {
  if (options.width <= 0 || options.height <= 0 || options.width > 32768 || options.height > 32768)
    throw OptionError("picture width and height must be in [1, 32768]");
  if (options.samples < 1 || options.samples > 1024) throw OptionError("samples per pixel must be in [1, 1024]");
  if (!(options.min_weight >= 0) || !std::isfinite(options.min_weight)) throw OptionError("min_weight must be >= 0");
  if (options.error_scale && !(*options.error_scale > 0)) throw OptionError("the error scale must be positive");
  if (!(options.point_radius >= 0) || !std::isfinite(options.point_radius)) throw OptionError("point radius must be >= 0");
}

}  // namespace render

}  // namespace clustersurf
