#pragma once
// The pinhole camera of the renderer: automatic framing of a bounding box from an azimuth,
// elevation and field of view, or an explicit eye / target / up.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/proxy/proxy.hpp>

#include <Eigen/Core>

#include <optional>

namespace clustersurf {

/// How the camera is placed. Angles in degrees. Unset fields are derived from the framed box.
struct CameraOptions {
  /// Turn around `up`, from the front axis (+z for +y up, +x for +z up) toward up × front.
  double azimuth = 30;
  double elevation = 20;                  ///< above the horizontal plane through the target
  std::optional<double> distance;         ///< eye–target distance; default: the nearest with the whole box in view
  double fov = 35;                        ///< vertical field of view
  std::optional<Eigen::Vector3d> eye;     ///< explicit eye (overrides azimuth/elevation/distance)
  std::optional<Eigen::Vector3d> target;  ///< default: center of the box
  /// Default: the scene's up axis (ClusterTree::up, TriangleMesh::up, PointCloud::up) in the
  /// renderers, +y in make_camera().
  std::optional<Eigen::Vector3d> up;
};

/// A perspective camera for a width × height picture. Pixel (x, y) covers [x, x+1) × [y, y+1),
/// y down; ray() gives unit directions.
struct Camera {
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  Eigen::Vector3d forward = -Eigen::Vector3d::UnitZ();  ///< unit, toward the target
  Eigen::Vector3d right = Eigen::Vector3d::UnitX();     ///< unit
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();        ///< unit, orthogonal to forward and right
  double fov = 35;                                      ///< vertical, degrees
  int width = 1;
  int height = 1;

  /// Focal length in pixels: (height / 2) / tan(fov / 2).
  double focal_pixels() const;
  /// The ray from the eye through image position (x, y) (pixel units, y down).
  Ray ray(double x, double y) const;
  /// ray(x, y) given focal_pixels(), for loops over many rays of one camera.
  Ray ray(double x, double y, double focal) const;
};

/// The camera framing `box` per `options` for a width × height picture. Throws OptionError for
/// a non-positive size, a field of view outside (0, 180), a degenerate up vector or eye = target.
Camera make_camera(const BoundingBox& box, const CameraOptions& options, int width, int height);

}  // namespace clustersurf
