// The colors that tell nodes and distances apart, shared by the meshes and the pictures.

#include <clustersurf/surface/palette.hpp>

#include <algorithm>
#include <cmath>

namespace clustersurf {

Eigen::Matrix<std::uint8_t, 3, 1> node_color(std::int32_t index) {
  // Golden-ratio hue walk with alternating saturation/value: distinct, reproducible colors.
  const double hue = std::fmod(static_cast<double>(index) * 0.618033988749895, 1.0) * 6.0;
  const double s = index % 2 == 0 ? 0.65 : 0.45, v = index % 3 == 0 ? 0.95 : 0.8;
  const int sector = static_cast<int>(hue);
  const double f = hue - sector;
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (sector % 6) {
    case 0:
      r = v, g = t, b = p;
      break;
    case 1:
      r = q, g = v, b = p;
      break;
    case 2:
      r = p, g = v, b = t;
      break;
    case 3:
      r = p, g = q, b = v;
      break;
    case 4:
      r = t, g = p, b = v;
      break;
    default:
      r = v, g = p, b = q;
      break;
  }
  return {static_cast<std::uint8_t>(std::lround(255 * r)), static_cast<std::uint8_t>(std::lround(255 * g)),
          static_cast<std::uint8_t>(std::lround(255 * b))};
}

Eigen::Matrix<std::uint8_t, 3, 1> distance_color(double fraction) {
  const double t = std::clamp(std::isfinite(fraction) ? fraction : 1.0, 0.0, 1.0);
  // green (0, 200, 0) → yellow (230, 220, 0) → red (220, 0, 0)
  const double red = t < 0.5 ? 460 * t : 230 - 20 * (t - 0.5);
  const double green = t < 0.5 ? 200 + 40 * t : 440 * (1 - t);
  return {static_cast<std::uint8_t>(std::lround(std::clamp(red, 0.0, 255.0))),
          static_cast<std::uint8_t>(std::lround(std::clamp(green, 0.0, 255.0))), 0};
}

}  // namespace clustersurf
