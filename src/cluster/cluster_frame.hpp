#pragma once
// A cluster's local frame: its tangent plane, from its positions or its input normals,
// whichever is more certain.

#include <clustersurf/proxy/proxy.hpp>

#include "cluster/estimated_normals.hpp"

#include <cstdint>
#include <span>

namespace clustersurf::detail {

/// A cluster's frame, and whether it is determined: whether the cluster is resolved against
/// the noise.
struct ClusterFrame {
  Frame frame;
  /// Whether the frame's tangent plane is known: it comes from the input normals, or the
  /// cluster's spread across its plane (the frame's second axis) is at least
  /// kDeterminedSpread times the noise variance. Below it the points are a blob as thick as
  /// it is wide, whose principal axes the noise chooses: no proxy fitted in that frame, nor
  /// the split of it, follows the surface.
  bool determined = true;
};

/// A principal frame is determined when the variance across the plane, λ₁, is at least twice
/// the noise's, λ₀ = σ²: its normal then tilts with the noise by at most about as much height,
/// at one spread from the centre, as the offset's own standard error σ/√n (the tilt's share
/// grows as λ₁ / (λ₁ − λ₀)).
inline constexpr double kDeterminedSpread = 2;

/// Normals a cluster's frame may follow: the input's (oriented consistently, rows indexed like
/// the input cloud: the `ids` of the cluster rows), or normals estimated from the positions
/// (unoriented), or none.
struct FrameNormals {
  const Points* input = nullptr;
  const EstimatedNormals* estimated = nullptr;
};

/// The frame of the points `range` (rows of `points`): origin at their mean, x along their
/// largest spread, z the normal of their tangent plane. The normal is the principal
/// component's (pca_frame()) unless the normals (of input rows `ids[row]`) pin it down better;
/// estimated normals, which carry the positions' own information over overlapping
/// neighbourhoods, are consulted only when the principal frame is not determined. The
/// principal normal's tilt varies by σ² / (ℓ² n) over n points of noise σ (the tree's
/// estimate) spread ℓ across the plane, the mean normal's by its normals' own spread over n: 2 (1 − |mean|) for
/// oriented normals, 1 − μ for unoriented ones (μ the largest eigenvalue of their mean outer product n nᵀ, whose axis
/// is then the normal); the smaller wins. Clean data (σ ≈ 0) keep the principal frame exactly; noisy positions with
/// consistent normals take the normals' plane, where the principal one tilts with the noise
/// (a noisy blob around a finger has no principal plane). A frame from the normals is
/// determined; so is every frame when the normals are the input's.
ClusterFrame cluster_frame(const Points& points, std::span<const std::uint32_t> range, const FrameNormals& normals,
                           std::span<const std::uint32_t> ids, double noise);

}  // namespace clustersurf::detail
