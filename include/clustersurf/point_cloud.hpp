#pragma once
// The point cloud value type shared by every stage of the pipeline.

#include <Eigen/Core>
#include <cstdint>
#include <limits>

namespace clustersurf {

/// n x 3 matrix of 3D vectors, one per row (positions or normals), row-major so a point is
/// contiguous in memory.
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// n x 3 matrix of 8-bit RGB colors, one per row.
using Colors = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// n x 3 matrix of vertex indices, one triangle per row.
using Triangles = Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// A set of points with optional per-point normals and colors. `normals` and `colors` are
/// either empty (0 rows) or have exactly as many rows as `positions`.
struct PointCloud {
  Points positions;
  Points normals;
  Colors colors;

  Eigen::Index size() const noexcept { return positions.rows(); }
  bool empty() const noexcept { return positions.rows() == 0; }
  bool has_normals() const noexcept { return normals.rows() != 0; }
  bool has_colors() const noexcept { return colors.rows() != 0; }
};

/// An indexed triangle mesh; `normals` and `colors` are per vertex, empty or one row per vertex.
struct TriangleMesh {
  Points vertices;
  Triangles triangles;
  Points normals;
  Colors colors;
};

/// Axis-aligned bounding box; empty() when min > max.
struct BoundingBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

  bool empty() const noexcept { return (min.array() > max.array()).any(); }
  Eigen::Vector3d extent() const noexcept { return empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(max - min); }
  double diagonal() const noexcept { return extent().norm(); }
  void extend(const Eigen::Vector3d& p) noexcept {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

/// Bounding box of the rows of `points` (empty box for no points).
BoundingBox bounding_box(const Points& points);

}  // namespace clustersurf
