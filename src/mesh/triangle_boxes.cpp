// Triangles' bounding boxes in float, rounded outwards, and the triangles near a marked few.

#include "mesh/triangle_boxes.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace clustersurf::detail {

namespace {

/// A float bound at or below (down) / at or above (up) x.
float round_down(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float round_up(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

/// Whether the closed boxes a and b meet.
bool overlap(const TriangleBox& a, const TriangleBox& b) {
  for (int axis = 0; axis < 3; ++axis)
    if (a.upper[axis] < b.lower[axis] || b.upper[axis] < a.lower[axis]) return false;
  return true;
}

/// Triangle f's longest edge.
double longest_edge(const TriangleMesh& mesh, Eigen::Index f) {
  const auto t = mesh.triangles.row(f);
  const auto p0 = mesh.vertices.row(t(0)), p1 = mesh.vertices.row(t(1)), p2 = mesh.vertices.row(t(2));
  return std::sqrt(std::max({(p1 - p0).squaredNorm(), (p2 - p1).squaredNorm(), (p0 - p2).squaredNorm()}));
}

}  // namespace

TriangleBox triangle_box(const TriangleMesh& mesh, Eigen::Index f, double pad) {
  const auto t = mesh.triangles.row(f);
  const auto p0 = mesh.vertices.row(t(0)), p1 = mesh.vertices.row(t(1)), p2 = mesh.vertices.row(t(2));
  TriangleBox box;
  for (int axis = 0; axis < 3; ++axis) {
    box.lower[axis] = round_down(std::min({p0(axis), p1(axis), p2(axis)}) - pad);
    box.upper[axis] = round_up(std::max({p0(axis), p1(axis), p2(axis)}) + pad);
  }
  return box;
}

std::vector<std::int32_t> near_suspects(const TriangleMesh& mesh, const std::vector<std::uint8_t>& suspect,
                                        double tolerance) {
  const auto nt = static_cast<std::size_t>(mesh.triangles.rows());
  const auto box_of = [&](Eigen::Index f) { return triangle_box(mesh, f, tolerance * longest_edge(mesh, f)); };
  std::vector<TriangleBox> boxes;
  for (std::size_t f = 0; f < nt; ++f)
    if (suspect[f] != 0) boxes.push_back(box_of(static_cast<Eigen::Index>(f)));
  if (boxes.empty()) return {};
  double cell = 0;
  std::array<double, 3> origin{};
  origin.fill(std::numeric_limits<double>::infinity());
  for (const TriangleBox& b : boxes)
    for (std::size_t axis = 0; axis < 3; ++axis) {
      cell = std::max(cell, static_cast<double>(b.upper[axis]) - b.lower[axis]);
      origin[axis] = std::min(origin[axis], static_cast<double>(b.lower[axis]));
    }
  if (!(cell > 0) || !std::isfinite(cell)) cell = 1;
  // Cell coordinates clamped to 21 bits each, packed in one key; a clamped cell only merges
  // far boxes, which the overlap test then tells apart.
  constexpr std::int64_t kMaxCell = (std::int64_t{1} << 21) - 1;
  const auto coordinate = [&](double x, std::size_t axis) {
    const double c = std::floor((x - origin[axis]) / cell);
    return static_cast<std::int64_t>(std::clamp(std::isfinite(c) ? c : 0.0, 0.0, static_cast<double>(kMaxCell)));
  };
  const auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
    return static_cast<std::uint64_t>((i << 42) | (j << 21) | k);
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cells;  // (key, suspect box), sorted
  for (std::size_t s = 0; s < boxes.size(); ++s) {
    const TriangleBox& b = boxes[s];
    for (std::int64_t i = coordinate(b.lower[0], 0); i <= coordinate(b.upper[0], 0); ++i)
      for (std::int64_t j = coordinate(b.lower[1], 1); j <= coordinate(b.upper[1], 1); ++j)
        for (std::int64_t k = coordinate(b.lower[2], 2); k <= coordinate(b.upper[2], 2); ++k)
          cells.emplace_back(key(i, j, k), static_cast<std::uint32_t>(s));
  }
  tbb::parallel_sort(cells.begin(), cells.end());
  std::vector<std::uint8_t> near(suspect);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nt, 4096), [&](const auto& range) {
    for (std::size_t f = range.begin(); f != range.end(); ++f) {
      if (near[f] != 0) continue;
      const TriangleBox b = box_of(static_cast<Eigen::Index>(f));
      const std::int64_t i0 = coordinate(b.lower[0], 0), i1 = coordinate(b.upper[0], 0);
      const std::int64_t j0 = coordinate(b.lower[1], 1), j1 = coordinate(b.upper[1], 1);
      const std::int64_t k0 = coordinate(b.lower[2], 2), k1 = coordinate(b.upper[2], 2);
      if ((i1 - i0 + 1) * (j1 - j0 + 1) * (k1 - k0 + 1) > 64) {  // a box far larger than the suspects'
        near[f] = 1;
        continue;
      }
      for (std::int64_t i = i0; i <= i1 && near[f] == 0; ++i)
        for (std::int64_t j = j0; j <= j1 && near[f] == 0; ++j)
          for (std::int64_t k = k0; k <= k1 && near[f] == 0; ++k) {
            const std::uint64_t at = key(i, j, k);
            for (auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(at, std::uint32_t{0}));
                 it != cells.end() && it->first == at; ++it)
              if (overlap(b, boxes[it->second])) {
                near[f] = 1;
                break;
              }
          }
    }
  });
  std::vector<std::int32_t> found;
  for (std::size_t f = 0; f < nt; ++f)
    if (near[f] != 0) found.push_back(static_cast<std::int32_t>(f));
  return found;
}

}  // namespace clustersurf::detail
