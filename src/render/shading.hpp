#pragma once
// Shading of hits: camera-fixed key and fill lights, two-sided Lambert, color ramps, and the
// deterministic per-pixel random numbers of anti-aliasing and ambient occlusion.

#include <clustersurf/render/camera.hpp>
#include <clustersurf/render/image.hpp>

#include "core/splitmix.hpp"

#include <Eigen/Core>

#include <cstdint>

namespace clustersurf::render {

/// RGB in [0, 1].
using Color = Eigen::Vector3d;

/// Directions toward the lights, fixed relative to the camera (key: upper left, fill: right).
struct Lighting {
  Eigen::Vector3d key;
  Eigen::Vector3d fill;
};
Lighting camera_lighting(const Camera& camera);

/// Two-sided Lambert: the normal is turned toward the viewer; ambient + key + fill, times
/// `occlusion` (1: open, 0: fully occluded) on the ambient and fill terms.
Color shade(const Lighting& lights, Eigen::Vector3d normal, const Eigen::Vector3d& ray_direction, const Color& base,
            double occlusion = 1);

/// 8-bit RGB to Color.
Color to_color(const Eigen::Matrix<std::uint8_t, 3, 1>& c);
/// Red (0) → green (0.5) → blue (1).
Color rank_color(double fraction);
/// Color in [0, 1] (and alpha) to an 8-bit pixel.
Rgba8 to_pixel(const Color& c, double alpha);

/// A number in [0, 1) from the top 53 bits of `bits`.
double unit_interval(std::uint64_t bits);
/// A cosine-distributed direction on the hemisphere around unit `normal` from two numbers in [0, 1).
Eigen::Vector3d cosine_direction(const Eigen::Vector3d& normal, double u1, double u2);

/// The color of a surface drawn without colors of its own (trees, meshes, clouds).
inline const Color kSurfaceColor(0.80, 0.77, 0.72);

/// Ambient occlusion: the reach of its rays and their start off the surface, as fractions of the
/// scene's diagonal.
inline constexpr double kOcclusionReach = 0.08;
inline constexpr double kOcclusionOffset = 1e-4;

/// The occlusion factor of a hit (0.35: every ray blocked, 1: open) from 8 short rays on the
/// cosine-weighted hemisphere around unit `facing` (the normal turned to the viewer), drawn
/// from `seed`; `blocked(direction)` says whether the ray leaving the hit that way meets the
/// scene within the reach.
template <class Blocked>
double ambient_occlusion(const Eigen::Vector3d& facing, std::uint64_t seed, Blocked&& blocked) {
  constexpr int kRays = 8;
  int open = 0;
  for (int k = 0; k < kRays; ++k) {
    const std::uint64_t bits = detail::splitmix64(seed + 0x9e37 * static_cast<std::uint64_t>(k + 1));
    const Eigen::Vector3d d = cosine_direction(facing, unit_interval(bits), unit_interval(detail::splitmix64(bits)));
    if (!blocked(d)) ++open;
  }
  return 0.35 + 0.65 * open / kRays;
}

}  // namespace clustersurf::render
