#pragma once
// The colors that tell nodes and distances apart: the same in meshes (mesh_colors.hpp), pictures
// (render.hpp) and the viewer.

#include <Eigen/Core>

#include <cstdint>

namespace clustersurf {

/// The RGB color of node `index` (a golden-ratio hue walk: neighbours almost always differ;
/// the same on every machine).
Eigen::Matrix<std::uint8_t, 3, 1> node_color(std::int32_t index);

/// The color of `fraction` of a distance scale: green (0) → yellow (0.5) → red (≥ 1; NaN too).
Eigen::Matrix<std::uint8_t, 3, 1> distance_color(double fraction);

}  // namespace clustersurf
