#pragma once
// Where a ray meets the surface of a tree, given the supports it crosses: the first zero of
// the blended f (implicit) or the blend of the proxies' own hits (hit-blend, thesis 5.1).

#include "render/ray_support.hpp"

#include <optional>
#include <span>

namespace clustersurf::render {

/// A surface point found along a ray.
struct SurfaceHit {
  double t = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit; direction of ∇f (outside)
  std::int32_t dominant = -1;                         ///< blended node of largest weight at the hit
};

/// Settings of the root finder.
struct MarchSettings {
  double min_weight = 0.1;  ///< f counts as defined only where the total weight exceeds this
  double tolerance = 1e-9;  ///< refine the zero to this bracket width (input units)
};

/// The first zero of f along the ray in [t_min, t_max]: a sign change between two samples where
/// f is defined, refined by the Illinois method. Stretches where every blended proxy has one
/// sign (f, their weighted mean, then has it too) are crossed in one step, and where f is
/// defined with the other sign at the stretch's end, with proxies of that sign beyond, the end
/// is the zero; elsewhere steps follow |f| (an approximate distance) and the secant's zero,
/// capped by a fraction of the smallest support radius around. `spans` as SupportIndex gives them; those the march
/// reaches are restricted to the ray on the way. `evaluations`, when given, is increased by the number of evaluations
/// of f.
std::optional<SurfaceHit> first_zero(const ClusterTree& tree, std::span<SupportSpan> spans, const Ray& ray,
                                     double t_min, double t_max, const MarchSettings& settings,
                                     std::size_t* evaluations = nullptr);

/// The thesis's hit blending: each support's proxy is intersected within its support; hits
/// whose parameters agree within a quarter of the first's support radius are blended (depth and
/// normal) with the weights at the hits; the nearest group whose weights sum above
/// `min_weight` wins.
std::optional<SurfaceHit> blended_hit(const ClusterTree& tree, std::span<const SupportSpan> spans, const Ray& ray,
                                      double t_min, double t_max, double min_weight);

/// ∇f direction and dominant node at x from the supports in `spans` that contain it.
void finish_hit(const ClusterTree& tree, std::span<const SupportSpan> spans, SurfaceHit& hit);

}  // namespace clustersurf::render
