// Pinhole camera and automatic framing.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/camera.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace clustersurf {

namespace {

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

}  // namespace

double Camera::focal_pixels() const { return 0.5 * height / std::tan(0.5 * radians(fov)); }

Ray Camera::ray(double x, double y) const { return ray(x, y, focal_pixels()); }

Ray Camera::ray(double x, double y, double focal) const {
  const Eigen::Vector3d d = focal * forward + (x - 0.5 * width) * right - (y - 0.5 * height) * up;
  return {eye, d.normalized()};
}

Camera make_camera(const BoundingBox& box, const CameraOptions& options, int width, int height) {
  if (width <= 0 || height <= 0) throw OptionError("picture size must be positive");
  if (!(options.fov > 0 && options.fov < 180)) throw OptionError("field of view must be in (0, 180) degrees");
  const Eigen::Vector3d given_up = options.up.value_or(Eigen::Vector3d::UnitY());
  if (!(given_up.norm() > 0) || !given_up.allFinite()) throw OptionError("the up vector must be nonzero");
  if (options.distance && !(*options.distance > 0)) throw OptionError("camera distance must be positive");
  const Eigen::Vector3d up = given_up.normalized();
  const Eigen::Vector3d center = box.empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.5 * (box.min + box.max));
  const double radius = box.empty() || box.diagonal() == 0 ? 1.0 : 0.5 * box.diagonal();
  const Eigen::Vector3d target = options.target.value_or(center);

  Eigen::Vector3d eye;
  if (options.eye) {
    eye = *options.eye;
  } else {
    // Front axis: +z made orthogonal to up (+x when up is along z).
    Eigen::Vector3d front = Eigen::Vector3d::UnitZ() - up.z() * up;
    if (front.norm() < 1e-6) front = Eigen::Vector3d::UnitX() - up.x() * up;
    front.normalize();
    const Eigen::Vector3d side = up.cross(front);  // +x for up +y, front +z
    const double az = radians(options.azimuth), el = radians(options.elevation);
    const Eigen::Vector3d dir = std::cos(el) * (std::cos(az) * front + std::sin(az) * side) + std::sin(el) * up;
    // Default distance: the nearest at which every corner of the box is in view (5 % margin).
    const double tan_v = std::tan(0.5 * radians(options.fov));
    const double tan_h = tan_v * width / height;
    const Eigen::Vector3d cam_right = (-dir).cross(up).normalized(), cam_up = cam_right.cross(-dir);
    double fit = 0;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d corner(k & 1 ? box.max.x() : box.min.x(), k & 2 ? box.max.y() : box.min.y(),
                                   k & 4 ? box.max.z() : box.min.z());
      const Eigen::Vector3d p = (box.empty() ? center : corner) - target;
      fit = std::max({fit, p.dot(dir) + std::abs(p.dot(cam_right)) / (0.95 * tan_h),
                      p.dot(dir) + std::abs(p.dot(cam_up)) / (0.95 * tan_v)});
    }
    const double distance = options.distance.value_or(fit > 0 ? fit : radius / std::sin(std::atan(tan_v)));
    eye = target + distance * dir;
  }
  Camera c;
  c.eye = eye;
  c.fov = options.fov;
  c.width = width;
  c.height = height;
  const Eigen::Vector3d forward = target - eye;
  if (!(forward.norm() > 0)) throw OptionError("camera eye and target coincide");
  c.forward = forward.normalized();
  const Eigen::Vector3d right = c.forward.cross(up);
  if (right.norm() < 1e-9) throw OptionError("the up vector is parallel to the viewing direction");
  c.right = right.normalized();
  c.up = c.right.cross(c.forward);
  return c;
}

}  // namespace clustersurf
