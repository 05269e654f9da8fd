// The volumetric IoU of two closed meshes: ray-parity inside tests at jittered grid points.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/volume_overlap.hpp>

#include "core/embree_scene.hpp"
#include "core/portable_random.hpp"
#include "core/splitmix.hpp"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace clustersurf {

namespace {

/// Directions of the three rays each inside test casts: generic (no axis, no face of a
/// lattice-aligned model lies along them) and far apart.
const std::array<Eigen::Vector3d, 3> kDirections{Eigen::Vector3d(0.8112, 0.4663, 0.3527).normalized(),
                                                 Eigen::Vector3d(-0.3922, 0.8517, -0.3476).normalized(),
                                                 Eigen::Vector3d(-0.2719, -0.3143, 0.9096).normalized()};

/// Rays pass this share of the box's diagonal beyond each crossing before looking for the next
/// (many times a float's precision there): the two triangles that share an edge a ray meets
/// count once, parts thinner than this as none.
constexpr double kCrossingGap = 1e-6;

/// A closed mesh's inside test.
class Solid {
 public:
  /// `mesh` in the frame of `origin`.
  Solid(const TriangleMesh& mesh, const Eigen::Vector3d& origin, double diagonal)
      : scene_(true), gap_(kCrossingGap * diagonal) {
    TriangleMesh local = mesh;
    local.vertices.rowwise() += (mesh.origin - origin).transpose();
    box_ = bounding_box(local.vertices);
    scene_.commit_triangles(local);
    triangles_ = static_cast<std::size_t>(mesh.triangles.rows());
  }

  bool contains(const Eigen::Vector3d& x) const {
    if ((x.array() < box_.min.array()).any() || (x.array() > box_.max.array()).any()) return false;
    // The third ray is cast only when the first two disagree.
    const bool first = crossings(Ray{x, kDirections[0]}) % 2 == 1;
    if (first == (crossings(Ray{x, kDirections[1]}) % 2 == 1)) return first;
    return crossings(Ray{x, kDirections[2]}) % 2 == 1;
  }

 private:
  /// How many times the ray crosses the mesh; at most one more than its triangles, however the
  /// float arithmetic falls.
  std::size_t crossings(Ray ray) const {
    std::size_t count = 0;
    RTCRayHit hit;
    while (count <= triangles_ && scene_.intersect(ray, std::numeric_limits<float>::infinity(), hit)) {
      ++count;
      ray.origin += (static_cast<double>(hit.ray.tfar) + gap_) * ray.direction;
    }
    return count;
  }

  detail::EmbreeScene scene_;
  double gap_;
  BoundingBox box_;
  std::size_t triangles_ = 0;
};

}  // namespace

VolumeOverlap volume_overlap(const TriangleMesh& reconstruction, const TriangleMesh& reference,
                             const VolumeOverlapOptions& options) {
  if (reconstruction.triangles.rows() == 0 || reference.triangles.rows() == 0)
    throw OptionError("volume_overlap needs two meshes with triangles");
  if (options.samples == 0) throw OptionError("volume_overlap needs samples > 0");
  if (!reconstruction.vertices.allFinite() || !reference.vertices.allFinite() || !reconstruction.origin.allFinite() ||
      !reference.origin.allFinite())
    throw OptionError("volume_overlap needs finite vertex coordinates");
  check_triangle_indices(reconstruction);
  check_triangle_indices(reference);
  BoundingBox box = bounding_box(reference.vertices);
  const BoundingBox other = bounding_box(reconstruction.vertices);
  box.extend(other.min + reconstruction.origin - reference.origin);
  box.extend(other.max + reconstruction.origin - reference.origin);
  const double diagonal = box.extent().norm();
  const Solid a(reconstruction, reference.origin, diagonal), b(reference, reference.origin, diagonal);
  const auto side = static_cast<std::size_t>(std::max(1.0, std::round(std::cbrt(double(options.samples)))));
  const Eigen::Vector3d cell = box.extent() / static_cast<double>(side);
  // Per grid row, how many of its points lie in A, in B and in both: integer sums, so the
  // figures do not depend on how the rows are shared among threads.
  std::vector<std::array<std::uint32_t, 3>> counts(side * side);
  tbb::parallel_for(std::size_t{0}, side * side, [&](std::size_t row) {
    detail::PortableRandom random(detail::splitmix64(options.seed ^ detail::splitmix64(row)));
    const std::size_t i = row / side, j = row % side;
    std::array<std::uint32_t, 3>& c = counts[row];
    c = {0, 0, 0};
    for (std::size_t k = 0; k < side; ++k) {
      const Eigen::Vector3d jitter(random.uniform(), random.uniform(), random.uniform());
      const Eigen::Vector3d x = box.min + cell.cwiseProduct(Eigen::Vector3d(double(i), double(j), double(k)) + jitter);
      const bool in_a = a.contains(x), in_b = b.contains(x);
      c[0] += in_a, c[1] += in_b, c[2] += in_a && in_b;
    }
  });
  std::array<std::uint64_t, 3> total{0, 0, 0};
  for (const auto& c : counts)
    for (std::size_t t = 0; t < 3; ++t) total[t] += c[t];
  VolumeOverlap out;
  out.samples = side * side * side;
  const double per_sample = cell.prod();
  out.reconstruction_volume = per_sample * static_cast<double>(total[0]);
  out.reference_volume = per_sample * static_cast<double>(total[1]);
  const std::uint64_t united = total[0] + total[1] - total[2];
  out.iou = united > 0 ? static_cast<double>(total[2]) / static_cast<double>(united) : 1.0;
  return out;
}

}  // namespace clustersurf
