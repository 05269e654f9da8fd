#pragma once
// The lattice mesh extraction walks and evaluates: cell keys, blocks of cells, the clip, the
// field it evaluates, and the Newton projection onto its zero set (shared by the walk's seeds
// and the mesh's vertices).

#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/surface/box_walk.hpp>

#include "mesh/clipped_extraction.hpp"
#include "mesh/walk_grid.hpp"

#include <Eigen/Core>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace clustersurf::detail {

/// A cell or corner of the lattice packed into 63 bits (21 per axis).
using Key = std::uint64_t;
inline constexpr std::int64_t kBias = std::int64_t{1} << 20;  // grid coordinates in [-2^20, 2^20)

inline Key pack(std::int64_t i, std::int64_t j, std::int64_t k) {
  return static_cast<Key>(i + kBias) | (static_cast<Key>(j + kBias) << 21) | (static_cast<Key>(k + kBias) << 42);
}
inline std::array<std::int64_t, 3> unpack(Key key) {
  const Key mask = (Key{1} << 21) - 1;
  return {static_cast<std::int64_t>(key & mask) - kBias, static_cast<std::int64_t>((key >> 21) & mask) - kBias,
          static_cast<std::int64_t>((key >> 42) & mask) - kBias};
}

/// The grid coordinates of a key (within [-2^20, 2^20) on each axis).
inline GridIndex grid_index(Key key) {
  const auto [i, j, k] = unpack(key);
  return {static_cast<std::int32_t>(i), static_cast<std::int32_t>(j), static_cast<std::int32_t>(k)};
}

/// Corners and vertices are evaluated in blocks of 2^kBlockShift cells a side, one
/// ImplicitSurface::BoxWalk per block.
inline constexpr int kBlockShift = 3;

/// Items grouped by block: block b holds order[begin[b] .. begin[b + 1]), in item order.
struct Blocks {
  std::vector<std::uint32_t> order;
  std::vector<std::size_t> begin;
  std::size_t count() const { return begin.size() - 1; }
  std::span<const std::uint32_t> block(std::size_t b) const {
    return std::span(order).subspan(begin[b], begin[b + 1] - begin[b]);
  }
};

/// Items 0 … n − 1 grouped by the block of their grid cell `cell(t)`.
template <class Cell>
Blocks group_by_block(std::size_t n, Cell&& cell) {
  std::vector<std::pair<Key, std::uint32_t>> keyed(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      const auto [i, j, k] = cell(t);
      keyed[t] = {pack(i >> kBlockShift, j >> kBlockShift, k >> kBlockShift), static_cast<std::uint32_t>(t)};
    }
  });
  tbb::parallel_sort(keyed.begin(), keyed.end());  // distinct pairs: one order on any thread count
  Blocks blocks;
  blocks.order.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    if (t == 0 || keyed[t].first != keyed[t - 1].first) blocks.begin.push_back(t);
    blocks.order[t] = keyed[t].second;
  }
  blocks.begin.push_back(n);
  return blocks;
}

/// The lattice of one walk: cells `h` wide from the tree box's lower corner (`origin`), only
/// those meeting the clip box when there is one.
struct Lattice {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double h = 0;
  const MeshClip* clip = nullptr;
  Eigen::Array3d clip_lo = Eigen::Array3d::Constant(-static_cast<double>(kBias)), clip_hi = -clip_lo;

  Lattice(const Eigen::Vector3d& lower, double cell, const MeshClip* clipped) : origin(lower), h(cell), clip(clipped) {
    if (clip == nullptr) return;
    clip_lo = ((clip->box.min - origin) / h).array().floor();
    clip_hi = ((clip->box.max - origin) / h).array().floor();
  }
  Eigen::Vector3d corner(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return Eigen::Vector3d(origin +
                           h * Eigen::Vector3d(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)));
  }
  /// A polygonizer vertex (in cell units) in the surface's coordinates.
  Eigen::Vector3d at(const std::array<float, 3>& p) const {
    return Eigen::Vector3d(origin + h * Eigen::Vector3d(p[0], p[1], p[2]));
  }
  Key cell_of(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d c = ((x - origin) / h).array().floor();
    return pack(static_cast<std::int64_t>(c.x()), static_cast<std::int64_t>(c.y()), static_cast<std::int64_t>(c.z()));
  }
  bool allowed(Key cell) const {
    const auto [i, j, k] = unpack(cell);
    const Eigen::Array3d c(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
    return (c >= clip_lo).all() && (c <= clip_hi).all();
  }
  bool meets(const Sphere& s) const { return clip == nullptr || sphere_meets_box(s, clip->box); }
};

/// What a walk evaluates: f of `surface`, or F of `closed` when given; where f is undefined and
/// `fill`, the same blend with supports `fill_cells` cells wider (`wide`).
struct Field {
  const ImplicitSurface& surface;
  const ClosedSurface* closed;
  ImplicitSurface wide;
  bool fill;
  double min_weight;
};

/// Newton steps x ← x − f ∇f / |∇f|² towards f = 0 of `s`, its supports found through `near`
/// (null: from the root); returns false if f is undefined or the point wanders farther than
/// `max_move`. `at_x`, when given, receives the sample of f at the returned x when the steps
/// settled within `tolerance` (its `defined` stays false otherwise).
bool project(const ImplicitSurface& s, const ImplicitSurface::BoxWalk* near, Eigen::Vector3d& x, int steps,
             double max_move, double tolerance, SurfaceSample* at_x = nullptr);

}  // namespace clustersurf::detail
