#pragma once
// A cluster's local frame: its tangent plane, from its positions or its input normals,
// whichever is more certain.

#include <clustersurf/proxy.hpp>

#include <cstdint>
#include <span>

namespace clustersurf::detail {

/// The frame of the points `range` (rows of `points`): origin at their mean, x along their
/// largest spread, z the normal of their tangent plane. The normal is the principal
/// component's (pca_frame()) unless the input normals (rows `ids[row]` of `normals`, or null)
/// pin it down better: the principal normal's tilt varies by σ² / (ℓ² n) over n points of
/// noise σ (the tree's estimate) spread ℓ across the plane, the mean normal's by its normals'
/// own spread, 2 (1 − |mean|), over n; the smaller wins. Clean data (σ ≈ 0) keep the principal
/// frame exactly; noisy positions with consistent normals take the normals' plane, where the
/// principal one tilts with the noise (a noisy blob around a finger has no principal plane).
Frame cluster_frame(const Points& points, std::span<const std::uint32_t> range, const Points* normals,
                    std::span<const std::uint32_t> ids, double noise);

}  // namespace clustersurf::detail
