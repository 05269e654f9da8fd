// Lights, Lambert shading and color ramps.

#include "render/shading.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace clustersurf::render {

Lighting camera_lighting(const Camera& camera) {
  Lighting l;
  l.key = (-camera.forward + 0.9 * camera.up - 0.6 * camera.right).normalized();
  l.fill = (-camera.forward + 0.8 * camera.right - 0.2 * camera.up).normalized();
  return l;
}

Color shade(const Lighting& lights, Eigen::Vector3d normal, const Eigen::Vector3d& ray_direction, const Color& base,
            double occlusion) {
  if (normal.dot(ray_direction) > 0) normal = -normal;
  const double key = std::max(0.0, normal.dot(lights.key));
  const double fill = std::max(0.0, normal.dot(lights.fill));
  const double head = std::max(0.0, -normal.dot(ray_direction));
  const double light = occlusion * (0.22 + 0.18 * fill + 0.15 * head) + 0.6 * key;
  return (base * light).cwiseMin(1.0);
}

Color to_color(const Eigen::Matrix<std::uint8_t, 3, 1>& c) { return c.cast<double>() / 255.0; }

Color rank_color(double fraction) {
  const double t = std::clamp(fraction, 0.0, 1.0);
  const Color red(0.9, 0.15, 0.1), green(0.2, 0.8, 0.2), blue(0.15, 0.3, 0.95);
  return t < 0.5 ? Color(red + 2 * t * (green - red)) : Color(green + (2 * t - 1) * (blue - green));
}

Rgba8 to_pixel(const Color& c, double alpha) {
  const auto byte = [](double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); };
  return {byte(c.x()), byte(c.y()), byte(c.z()), byte(alpha)};
}

double unit_interval(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

Eigen::Vector3d cosine_direction(const Eigen::Vector3d& normal, double u1, double u2) {
  const Eigen::Vector3d a = std::abs(normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d t = normal.cross(a).normalized();
  const Eigen::Vector3d b = normal.cross(t);
  const double r = std::sqrt(u1), phi = 2 * std::numbers::pi * u2;
  return (r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1 - u1)) * normal).normalized();
}

}  // namespace clustersurf::render
