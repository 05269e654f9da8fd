// Whole-cloud operations on the value types of point_cloud.hpp.

#include <clustersurf/core/point_cloud.hpp>

#include <clustersurf/core/errors.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace clustersurf {

void check_triangle_indices(const TriangleMesh& mesh) {
  const Eigen::Index nv = mesh.vertices.rows();
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles(t, k) < 0 || mesh.triangles(t, k) >= nv)
        throw OptionError("triangle " + std::to_string(t) + " references vertex " +
                          std::to_string(mesh.triangles(t, k)) + ", outside 0.." + std::to_string(nv - 1));
}

BoundingBox bounding_box(const Points& points) {
  BoundingBox box;
  if (points.rows() > 0) {
    box.min = points.colwise().minCoeff().transpose();
    box.max = points.colwise().maxCoeff().transpose();
  }
  return box;
}

PointCloud select(const PointCloud& cloud, const std::vector<Eigen::Index>& indices) {
  PointCloud out;
  out.positions = cloud.positions(indices, Eigen::all);
  if (cloud.has_normals()) out.normals = cloud.normals(indices, Eigen::all);
  if (cloud.has_colors()) out.colors = cloud.colors(indices, Eigen::all);
  out.origin = cloud.origin;
  out.up = cloud.up;
  for (const PointAttribute& a : cloud.attributes) out.attributes.push_back({a.name, a.values(indices)});
  out.scanner_positions = cloud.scanner_positions;
  if (cloud.has_scanners()) {
    out.scanner_of_point.reserve(indices.size());
    for (const Eigen::Index i : indices)
      out.scanner_of_point.push_back(cloud.scanner_of_point[static_cast<std::size_t>(i)]);
  }
  return out;
}

Eigen::Vector3d shift_to_origin(PointCloud& cloud) {
  const Eigen::Vector3d shift = origin_shift(bounding_box(cloud.positions));
  if (shift.isZero()) return shift;
  cloud.positions.rowwise() -= shift.transpose();
  if (cloud.scanner_positions.rows() != 0) cloud.scanner_positions.rowwise() -= shift.transpose();
  cloud.origin += shift;
  return shift;
}

Eigen::Vector3d shift_to_origin(TriangleMesh& mesh) {
  const Eigen::Vector3d shift = origin_shift(bounding_box(mesh.vertices));
  if (shift.isZero()) return shift;
  mesh.vertices.rowwise() -= shift.transpose();
  mesh.origin += shift;
  return shift;
}

std::size_t scan_count(const PointCloud& cloud) {
  std::vector<std::uint32_t> scans = cloud.scanner_of_point;
  std::sort(scans.begin(), scans.end());
  return static_cast<std::size_t>(std::unique(scans.begin(), scans.end()) - scans.begin());
}

Eigen::Vector3d origin_shift(const BoundingBox& box) {
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  if (box.empty() || !box.min.allFinite() || !box.max.allFinite() || !(box.diagonal() > 0)) return shift;
  const Eigen::Vector3d center = 0.5 * box.min + 0.5 * box.max;  // no overflow near the largest doubles
  // Float32 (the mesher's grid, the renderer and the viewer) rounds a coordinate c to about
  // |c| 2^-24: below 16 diagonals that is under 2^-20 of the diagonal, far finer than any mesh
  // cell, so such clouds stay where they are.
  const double far = 16 * box.diagonal();
  for (int k = 0; k < 3; ++k)
    if (std::abs(center(k)) > far && std::abs(center(k)) > box.extent()(k)) shift(k) = center(k);
  return shift;
}

}  // namespace clustersurf
