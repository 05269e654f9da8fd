#pragma once
// Telling a proxy's systematic misfit from noise by the structure of its residuals.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/proxy/proxy.hpp>

#include <cstdint>
#include <span>

namespace clustersurf::detail {

/// The correlation of each point's residual Q(p) with the residual of its nearest neighbour in
/// the cluster, ρ = Σ qᵢ q_nn(i) / √(Σ qᵢ² Σ q_nn(i)²), over points[range]. Neighbours are
/// found in the projection onto the frame's tangent plane (e1, e2), so the noise along the
/// normal does not choose them. Independent noise gives ρ near 0 (spread at most √(2/n)); relief
/// the proxy does not follow gives ρ near 1, even when it is well below the noise. 0 for fewer
/// than 4 points or residuals that are all 0.
double residual_correlation(const Points& points, std::span<const std::uint32_t> range, const Frame& frame,
                            const Proxy& proxy);

}  // namespace clustersurf::detail
