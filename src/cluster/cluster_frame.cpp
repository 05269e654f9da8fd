// A cluster's local frame from its positions or its input normals.

#include "cluster/cluster_frame.hpp"

#include <Eigen/Geometry>

#include <algorithm>

namespace clustersurf::detail {

ClusterFrame cluster_frame(const Points& points, std::span<const std::uint32_t> range, const Points* normals,
                           std::span<const std::uint32_t> ids, double noise) {
  ClusterFrame out{pca_frame(points, range)};
  Frame& f = out.frame;
  if (!(noise > 0) || range.empty()) return out;
  double across = 0;  // Σ squared distance along the frame's second axis (the plane's narrower spread)
  for (auto row : range) {
    const double d = (points.row(row).transpose() - f.origin).dot(f.axes.col(1));
    across += d * d;
  }
  const double n = static_cast<double>(range.size());
  out.determined = normals != nullptr || across >= kDeterminedSpread * noise * noise * n;
  if (normals == nullptr || range.size() < 3) return out;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (auto row : range) sum += normals->row(ids[row]).transpose();
  const double length = sum.norm() / n;
  if (!(length > 0) || !(across > 0)) return out;  // no usable normals (or a NaN among them), or a line
  const double tilt_principal = noise * noise / (across / n * n);
  const double tilt_normals = 2 * std::max(0.0, 1 - length) / n;
  if (!(tilt_normals < tilt_principal)) return out;
  const Eigen::Vector3d z = sum / sum.norm();
  Eigen::Vector3d x = f.axes.col(0) - f.axes.col(0).dot(z) * z;
  if (!(x.norm() > 1e-6)) x = z.unitOrthogonal();
  x.normalize();
  f.axes.col(0) = x;
  f.axes.col(1) = z.cross(x);
  f.axes.col(2) = z;
  out.determined = true;
  return out;
}

}  // namespace clustersurf::detail
