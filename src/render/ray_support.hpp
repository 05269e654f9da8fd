#pragma once
// The supports a ray crosses, each with its blending weight and proxy written as functions of
// the ray parameter t, so that f along the ray costs a few multiply-adds per support.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/surface/implicit_surface.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace clustersurf::render {

/// A blended node whose support sphere the ray crosses on [t_enter, t_exit]. Along the ray,
/// ‖x(t) − c‖² / r² = s0 + s1 t + s2 t². Once restrict_span() has run, the proxy's
/// Q(x(t)) = N(t) / sqrt(D(t)) with N and D quadratics (exact for every proxy kind); a crease
/// is the max (or min) of two such planes, the second M(t) = m0 + m1 t.
struct SupportSpan {
  std::int32_t node = -1;
  double t_enter = 0, t_exit = 0;
  double s0 = 0, s1 = 0, s2 = 0;
  bool restricted = false;  ///< whether the members below hold the support's radius and proxy
  double radius = 0;
  double n0 = 0, n1 = 0, n2 = 0;
  double d0 = 1, d1 = 0, d2 = 0;
  double m0 = 0, m1 = 0;
  std::int8_t crease = 0;  ///< 0: one proxy; +1: max(N, M) (convex crease); −1: min(N, M)
  /// The parameters in (t_enter, t_exit) where N or M vanishes, ascending (+inf: none): between
  /// them the proxy's value keeps its sign.
  double flip0 = std::numeric_limits<double>::infinity(), flip1 = std::numeric_limits<double>::infinity();

  /// ‖x(t) − c‖² / r² (< 1 inside the support).
  double s(double t) const { return s0 + t * (s1 + t * s2); }
  /// The proxy's value at x(t) (once restricted).
  double q(double t) const;
  /// Whether the proxy's value at x(t) is positive (once restricted): the sign of q(t), without
  /// its normalization.
  bool positive(double t) const {
    const double n = n0 + t * (n1 + t * n2);
    if (crease == 0) return n > 0;
    const double m = m0 + t * m1;
    return crease > 0 ? std::max(n, m) > 0 : std::min(n, m) > 0;
  }
};

/// Writes the proxy of `span`'s node along `ray` (the ray the span was collected for) into it.
void restrict_span(const ClusterTree& tree, const Ray& ray, SupportSpan& span);

/// How the supports crossed by a ray are found.
enum class SupportSearch {
  Hierarchy,   ///< descend the bounding spheres of the tree
  BruteForce,  ///< test the support of every blended node
};

/// The parameter interval where a ray (unit direction) is inside a sphere, if it meets it.
std::optional<std::pair<double, double>> ray_sphere(const Ray& ray, const Sphere& sphere);

/// Supports to test rays against, copied side by side (centers' coordinates and squared radii
/// each in their own array) so that testing many of them is one tight loop.
struct SupportSet {
  std::vector<std::int32_t> nodes;
  std::vector<double> x, y, z, r2;
  /// A support a ray crosses, on [t_enter, t_exit]: the k-th of the set.
  struct Crossing {
    double t_enter, t_exit;
    std::size_t k;
  };
  mutable std::vector<double> b, disc;                // collect_from()'s scratch: one set per thread
  mutable std::vector<Crossing> crossings;            // the same
  std::vector<std::pair<double, std::size_t>> order;  // order_along()'s scratch
  std::vector<std::int32_t> moved_nodes;              // the same
  std::vector<double> moved;                          // the same
};

/// The rays from `apex` within the half-angle θ of the unit `axis`, held as cos θ and sin θ
/// (the cull needs no more, and the cone of a pixel rectangle gets them without an arccosine).
struct RayCone {
  Eigen::Vector3d apex = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double cos_half = 1, sin_half = 0;

  /// The cone of half-angle `angle` radians.
  static RayCone of_half_angle(const Eigen::Vector3d& apex, const Eigen::Vector3d& axis, double angle) {
    return {apex, axis, std::cos(angle), std::sin(angle)};
  }
  /// θ in radians.
  double half_angle() const { return std::atan2(sin_half, cos_half); }
};

/// The supports of `in` that may meet a ray of `cone`: a conservative superset of those that do,
/// in the order of `in`, found by one branch-free pass (no tree walk).
void cull_to_cone(const SupportSet& in, const RayCone& cone, SupportSet& out);

/// Orders the supports of `set` by where the ray along the cone's axis would enter them
/// ((center − apex) · axis − radius): rays of a narrow cone then cross them nearly in that
/// order, which collect_from() sorts in linear time.
void order_along(const RayCone& cone, SupportSet& set);

/// The blended nodes (a cut of the tree) and how to find the supports along a ray.
class SupportIndex {
 public:
  /// Keeps a reference to `tree`, which must outlive the index.
  SupportIndex(const ClusterTree& tree, const LevelOfDetail& lod);

  /// Every blended node whose support the ray crosses within [t_min, t_max], sorted by
  /// (t_enter, node) — the same list, in the same order, for both searches — not yet restricted.
  void collect(const Ray& ray, double t_min, double t_max, SupportSearch search, std::vector<SupportSpan>& out) const;

  /// The blended nodes whose support may meet a ray from `eye` within the cone of unit `axis`
  /// and half-angle `half_angle` (radians): a conservative superset, in pre-order.
  void collect_in_cone(const Eigen::Vector3d& eye, const Eigen::Vector3d& axis, double half_angle,
                       std::vector<std::int32_t>& out) const;
  /// The supports of `nodes`, for collect_from() of many rays.
  void gather(std::span<const std::int32_t> nodes, SupportSet& out) const;
  /// As collect(), testing only the supports of the set (every blended node when it holds the
  /// whole cut: the brute-force search).
  void collect_from(const Ray& ray, double t_min, double t_max, const SupportSet& set,
                    std::vector<SupportSpan>& out) const;

  const ClusterTree& tree() const { return surface_.tree(); }
  const std::vector<std::int32_t>& cut() const { return surface_.cut(); }
  bool in_cut(std::int32_t node) const { return surface_.in_cut(node); }

 private:
  ImplicitSurface surface_;                // the cut and the walk down the bounding spheres
  std::vector<Eigen::Vector4d> supports_;  // per node: support center and squared radius (cache-friendly)
};

}  // namespace clustersurf::render
