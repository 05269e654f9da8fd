#pragma once
// Triangles' bounding boxes in float, rounded outwards, and the triangles near a marked few.

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf::detail {

/// An axis-aligned box in float whose bounds enclose the double-precision box it stands for.
struct TriangleBox {
  float lower[3], upper[3];
};

/// Triangle f's box grown by `pad` on every side, rounded outwards to float.
TriangleBox triangle_box(const TriangleMesh& mesh, Eigen::Index f, double pad);

/// The triangles whose boxes (each grown by `tolerance` times its longest edge) meet the box of
/// a marked one (`suspect`, one mark per triangle), the marked ones among them, ascending:
/// found through a hash of the marked boxes on a grid of their largest extent.
std::vector<std::int32_t> near_suspects(const TriangleMesh& mesh, const std::vector<std::uint8_t>& suspect,
                                        double tolerance);

}  // namespace clustersurf::detail
