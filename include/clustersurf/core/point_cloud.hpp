#pragma once
// The point cloud value type shared by every stage of the pipeline.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace clustersurf {

/// n x 3 matrix of 3D vectors, one per row (positions or normals), row-major so a point is
/// contiguous in memory.
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// n x 3 matrix of 8-bit RGB colors, one per row.
using Colors = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// n x 3 matrix of vertex indices, one triangle per row.
using Triangles = Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// The axis that points up in a file's convention: +y for meshes and most point formats, +z for
/// georeferenced surveys (LAS, E57 and PTX are z-up). Pictures and the viewer take it as up.
enum class UpAxis : std::uint8_t { Y = 0, Z = 1 };

/// The unit vector of `axis`.
inline Eigen::Vector3d up_vector(UpAxis axis) {
  return axis == UpAxis::Z ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
}

/// A named per-point scalar a scanner file carries (LAS intensity and classification, E57 and
/// PTX intensity): one value per point.
struct PointAttribute {
  std::string name;
  Eigen::VectorXf values;
};

/// A set of points with optional per-point normals, colors, attributes and scanner positions.
/// Every per-point member is either empty or has exactly as many rows as `positions`.
struct PointCloud {
  Points positions;
  Points normals;
  Colors colors;
  /// Where the points are in the file's coordinates: a point is positions.row(i) + origin.
  /// Readers move a cloud that lies far from zero next to it (see shift_to_origin) so that no
  /// stage loses precision; writers add the origin back. Zero for clouds near zero.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  /// Which axis is up in the file's convention (readers set it; stages pass it on).
  UpAxis up = UpAxis::Y;
  /// Extra scalars per point, kept through every selection of rows.
  std::vector<PointAttribute> attributes;
  /// Where the scanners stood (one row per scan, in the same frame as `positions`) and which
  /// scan saw each point; both empty when the file does not say. The side of the surface a
  /// point's scanner was on is outside, so orientation needs no propagation.
  Points scanner_positions;
  std::vector<std::uint32_t> scanner_of_point;

  Eigen::Index size() const noexcept { return positions.rows(); }
  bool empty() const noexcept { return positions.rows() == 0; }
  bool has_normals() const noexcept { return normals.rows() != 0; }
  bool has_colors() const noexcept { return colors.rows() != 0; }
  bool has_scanners() const noexcept { return !scanner_of_point.empty(); }
};

/// An indexed triangle mesh; `normals` and `colors` are per vertex, empty or one row per vertex.
/// A vertex is at vertices.row(i) + origin in the coordinates of the files it came from.
struct TriangleMesh {
  Points vertices;
  Triangles triangles;
  Points normals;
  Colors colors;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  /// Which axis is up (the input's, PointCloud::up): PLY files record it, GLB files turn a z-up
  /// mesh to glTF's +y up.
  UpAxis up = UpAxis::Y;
  /// Extra scalars per vertex (`filled`: 1 where a closed mesh was filled in, not fitted),
  /// kept by every operation that keeps vertices and written to PLY as float properties.
  std::vector<PointAttribute> attributes;
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

/// A ray origin + t · direction.
struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
};

/// Bounding box of the rows of `points` (empty box for no points).
BoundingBox bounding_box(const Points& points);

/// Throws OptionError naming the first triangle of `mesh` with a corner that is not one of its
/// vertices.
void check_triangle_indices(const TriangleMesh& mesh);

/// The rows `indices` of every per-point member of `cloud`, in that order (origin and scanner
/// positions kept).
PointCloud select(const PointCloud& cloud, const std::vector<Eigen::Index>& indices);

/// Moves a cloud that lies far from zero next to it: along each axis whose bounding-box centre
/// is farther from zero than 16 diagonals (there float32, which the mesher and the viewer use,
/// would round coordinates by more than 2^-20 of the diagonal), subtracts the centre from the
/// positions (and the scanner positions) and adds it to `origin`. The subtraction and the
/// writers' addition are exact in double precision (Sterbenz), so positions + origin
/// round-trips bit for bit, while every stage works on small numbers. Returns the shift (zero:
/// nothing moved).
Eigen::Vector3d shift_to_origin(PointCloud& cloud);
/// The same for a mesh: its vertices moved, the shift added to its origin.
Eigen::Vector3d shift_to_origin(TriangleMesh& mesh);
/// How many distinct scans cloud.scanner_of_point names (0: it names none).
std::size_t scan_count(const PointCloud& cloud);
/// The shift shift_to_origin() gives a cloud with bounding box `box` (zero: none).
Eigen::Vector3d origin_shift(const BoundingBox& box);

}  // namespace clustersurf
