#pragma once
// A leaf's support: how far it reaches and how well its proxy holds over the input points
// inside it (MPU's local fit and its N_min rule).

#include "cluster/build_state.hpp"
#include "cluster/support_sampler.hpp"

#include <optional>

namespace clustersurf::detail {

/// The weighted RMS of |Q| over a support and the effective number of points behind it,
/// (Σw)² / Σw².
struct SupportError {
  double rms = 0;
  double effective_points = 0;
};

/// The support checks of one build. Thread-safe; holds references to its arguments.
class SupportFit {
 public:
  /// `input`: the clustered points in input order (indexed by `sampler`); `cluster_points`:
  /// the working copy in cluster order (the ranges index it); `tolerance` and `noise` as the
  /// builder's.
  SupportFit(const Points& input, const Points& cluster_points, const SupportSampler& sampler,
             const BuildOptions& options, double tolerance, double noise, const Points* normals);

  /// The radius around `center` that holds BuildOptions::support_points input points (MPU's
  /// N_min; 0 when that is 0), at most kMaxSupportGrowth × `alpha_radius`: a small cluster's
  /// support overlaps its neighbours' instead of leaving gaps, but never reaches across a gap
  /// for a few strays.
  double coverage_radius(const Eigen::Vector3d& center, double alpha_radius) const;

  /// Whether BuildOptions::support_points of the cluster's own points (`range`, which are among
  /// the input points) lie within `radius` of `center`, with a margin of a billionth of the
  /// radius: the coverage radius is then below `radius` (no k-nearest-neighbour query needed).
  bool own_points_cover(std::span<const std::uint32_t> range, const Eigen::Vector3d& center, double radius) const;

  /// The support check: a bounded sample of the input points inside the node's support; a
  /// polynomial proxy is first refitted to them (refit()); returns the weighted RMS of |Q|.
  SupportError check(ClusterNode& node, std::span<const std::uint32_t> range) const;

  /// The crease that fits the points inside the node's support (the same sample as check()),
  /// with its edge anywhere within the support, and its weighted RMS there; nullopt when they
  /// do not lie on two faces (fit_crease()).
  struct SupportCrease {
    CreaseProxy proxy;
    SupportError error;
  };
  std::optional<SupportCrease> crease(const ClusterNode& node, const Frame& frame) const;

  /// Whether the points inside the node's support (the same sample as check()), weighted by the
  /// blend's weights, are fitted by a quadratic per half in `frame` significantly better than by
  /// one, halved along either of its first two axes (halves_drops() beyond halves_drop_bound()
  /// of their mean weight). The blend reaches a leaf's proxy out to its support's rim, where a
  /// quadratic that holds on the leaf's own points may not.
  bool halves_fit_better(const ClusterNode& node, const Frame& frame) const;
  /// How far the node's support may reach before another sheet: the distance from its centre to
  /// the kOtherSheetPoints-th nearest input point inside it that lies off the proxy (beyond the
  /// support fit's reach) with its normal facing away from the leaf's own sheet (the mean normal
  /// of the support points the proxy fits): the far side of a thin part, a fold's other wall.
  /// The support's radius when there is none or no normals are known.
  double other_sheet_distance(const ClusterNode& node, std::span<const std::uint32_t> range) const;

 private:
  /// The weighted RMS of |Q| of `proxy` over the support points `inside` of `support`.
  SupportError weighted_error(const Proxy& proxy, const Sphere& support, std::span<const Neighbor> inside) const;
  /// Where the node's cluster fit misses `threshold` because of one stray point (the fit of the
  /// others meets it, and the stray lies beyond kSupportFitReach thresholds of that fit), the
  /// others' fit, with its RMS over all of `range` in `rms`; nullopt otherwise (`rms` untouched).
  std::optional<Proxy> unbent(const ClusterNode& node, std::span<const std::uint32_t> range, double threshold,
                              double& rms) const;
  void refit(ClusterNode& node, std::span<const std::uint32_t> range, std::span<const Neighbor> inside) const;
  bool accept(ClusterNode& node, std::span<const std::uint32_t> range, double threshold, double cut, Proxy fit) const;

  const Points& input_;
  const Points& points_;
  const SupportSampler& sampler_;
  const BuildOptions& options_;
  double tolerance_;
  double noise_;
  const Points* normals_;  // the input normals, rows as of input_, or null
};

}  // namespace clustersurf::detail
