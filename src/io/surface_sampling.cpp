#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/surface_sampling.hpp>

#include "core/portable_random.hpp"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace clustersurf {

using detail::PortableRandom;

PointCloud sample_surface(const TriangleMesh& mesh, const SurfaceSamplingOptions& options) {
  if (!(options.noise >= 0) || !std::isfinite(options.noise))
    throw OptionError(fmt::format("noise must be a finite fraction >= 0, got {}", options.noise));
  if (!(options.outliers >= 0) || !std::isfinite(options.outliers))
    throw OptionError(fmt::format("outlier fraction must be finite and >= 0, got {}", options.outliers));
  const Eigen::Index vertex_count = mesh.vertices.rows();
  const Eigen::Index triangle_count = mesh.triangles.rows();
  check_triangle_indices(mesh);

  // Cumulative areas; a triangle is drawn with probability proportional to its area.
  std::vector<double> cumulative(static_cast<std::size_t>(triangle_count));
  std::vector<Eigen::Vector3d> normals(static_cast<std::size_t>(triangle_count));
  double total = 0;
  for (Eigen::Index t = 0; t < triangle_count; ++t) {
    const auto tri = mesh.triangles.row(t);
    const Eigen::Vector3d a = mesh.vertices.row(tri(0)), b = mesh.vertices.row(tri(1)), c = mesh.vertices.row(tri(2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double area = 0.5 * n.norm();
    if (std::isfinite(area) && area > 0) {
      total += area;
      normals[static_cast<std::size_t>(t)] = n.normalized();
    }
    cumulative[static_cast<std::size_t>(t)] = total;
  }
  if (!(total > 0)) throw OptionError("the mesh has no triangle of positive area to sample");

  BoundingBox box;
  for (const auto& row : mesh.triangles.rowwise())
    for (int k = 0; k < 3; ++k) box.extend(mesh.vertices.row(row(k)).transpose());
  const double sigma = options.noise * box.diagonal();
  const auto outlier_count =
      static_cast<std::size_t>(std::llround(options.outliers * static_cast<double>(options.count)));
  const std::size_t n = options.count + outlier_count;

  PointCloud cloud;
  cloud.origin = mesh.origin;
  cloud.up = mesh.up;
  cloud.positions.resize(static_cast<Eigen::Index>(n), 3);
  cloud.normals.resize(static_cast<Eigen::Index>(n), 3);
  const bool colored = mesh.colors.rows() == vertex_count && vertex_count > 0;
  if (colored) cloud.colors.resize(static_cast<Eigen::Index>(n), 3);
  PortableRandom random(options.seed);
  for (std::size_t i = 0; i < options.count; ++i) {
    const double target = random.uniform() * total;
    // First triangle whose cumulative area exceeds the target: never a zero-area one.
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
    const auto t = static_cast<Eigen::Index>(std::min<std::ptrdiff_t>(it - cumulative.begin(), triangle_count - 1));
    const auto tri = mesh.triangles.row(t);
    const Eigen::Vector3d a = mesh.vertices.row(tri(0)), b = mesh.vertices.row(tri(1)), c = mesh.vertices.row(tri(2));
    // Uniform barycentric coordinates by the square-root map (Osada et al. 2002).
    const double r1 = std::sqrt(random.uniform()), r2 = random.uniform();
    const Eigen::Vector3d weight(1 - r1, r1 * (1 - r2), r1 * r2);
    Eigen::Vector3d p = weight(0) * a + weight(1) * b + weight(2) * c;
    if (colored) {
      Eigen::Vector3d rgb = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) rgb += weight(k) * mesh.colors.row(tri(k)).cast<double>().transpose();
      for (int channel = 0; channel < 3; ++channel)
        cloud.colors(static_cast<Eigen::Index>(i), channel) =
            static_cast<std::uint8_t>(std::clamp(std::round(rgb(channel)), 0.0, 255.0));
    }
    if (sigma > 0) p += sigma * Eigen::Vector3d(random.normal(), random.normal(), random.normal());
    cloud.positions.row(static_cast<Eigen::Index>(i)) = p;
    cloud.normals.row(static_cast<Eigen::Index>(i)) = normals[static_cast<std::size_t>(t)];
  }
  const Eigen::Vector3d margin = 0.05 * box.extent();
  const Eigen::Vector3d lo = box.min - margin, span = box.extent() + 2 * margin;
  for (std::size_t i = options.count; i < n; ++i) {
    const Eigen::Vector3d u(random.uniform(), random.uniform(), random.uniform());
    cloud.positions.row(static_cast<Eigen::Index>(i)) = lo + span.cwiseProduct(u);
    cloud.normals.row(static_cast<Eigen::Index>(i)) = random.unit_vector();
    if (colored) cloud.colors.row(static_cast<Eigen::Index>(i)).setConstant(128);
  }
  return cloud;
}

}  // namespace clustersurf
