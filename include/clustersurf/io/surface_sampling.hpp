#pragma once
// Area-uniform random samples of a triangle mesh, optionally perturbed: the inputs of
// reproducible benchmarks (a known surface, a known noise level, known outliers).

#include <clustersurf/core/point_cloud.hpp>

#include <cstddef>
#include <cstdint>

namespace clustersurf {

/// How `sample_surface` draws its points.
struct SurfaceSamplingOptions {
  /// Number of points on the surface (outliers come on top of these).
  std::size_t count = 200'000;
  /// Standard deviation of isotropic Gaussian noise added to each surface point, as a fraction
  /// of the mesh's bounding-box diagonal (0: exactly on the surface).
  double noise = 0;
  /// Outliers as a fraction of `count`, uniform in the bounding box enlarged by 5 % per side.
  double outliers = 0;
  /// Seed of the generator; the same mesh, options and seed give the same points on any machine
  /// (the generator and the distributions are fixed, not the standard library's).
  std::uint64_t seed = 1;
};

/// `options.count` points distributed uniformly by area over the triangles of `mesh`, with the
/// unit normal of the triangle each was drawn from (outliers get a random unit normal), the
/// mesh's vertex colors interpolated where it has them (outliers grey), and its origin.
/// Degenerate triangles (zero area) are never drawn. Throws OptionError when the mesh has no
/// triangle of positive area or an option is out of range.
PointCloud sample_surface(const TriangleMesh& mesh, const SurfaceSamplingOptions& options = {});

}  // namespace clustersurf
