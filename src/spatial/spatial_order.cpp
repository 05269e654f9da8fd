// Morton order of points for batches of neighbour queries.

#include "spatial/spatial_order.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <utility>

namespace clustersurf::detail {

namespace {

/// The low 21 bits of v spread to every third bit.
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

/// The Morton order of `count` points, the k-th at `position(k)`.
template <class Position>
std::vector<std::uint32_t> morton_order(std::size_t count, const Position& position) {
  BoundingBox box;
  for (std::size_t k = 0; k < count; ++k) box.extend(position(k));
  const Eigen::Vector3d extent = box.extent().cwiseMax(Eigen::Vector3d::Constant(1e-300));
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const auto& r) {
    for (std::size_t k = r.begin(); k != r.end(); ++k) {
      const Eigen::Vector3d t = ((position(k) - box.min).array() / extent.array()) * 2097151.0;
      keyed[k] = {morton_code(static_cast<std::uint64_t>(t.z()), static_cast<std::uint64_t>(t.y()),
                              static_cast<std::uint64_t>(t.x())),
                  static_cast<std::uint32_t>(k)};
    }
  });
  tbb::parallel_sort(keyed.begin(), keyed.end());  // (code, row) pairs are distinct: one order on any thread count
  std::vector<std::uint32_t> order(count);
  for (std::size_t k = 0; k < count; ++k) order[k] = keyed[k].second;
  return order;
}

}  // namespace

std::uint64_t morton_code(std::uint64_t x, std::uint64_t y, std::uint64_t z) {
  return spread_bits(x) << 2 | spread_bits(y) << 1 | spread_bits(z);
}

std::vector<std::uint32_t> spatial_order(const Points& points) {
  return morton_order(static_cast<std::size_t>(points.rows()), [&](std::size_t k) -> Eigen::Vector3d {
    return points.row(static_cast<Eigen::Index>(k)).transpose();
  });
}

std::vector<std::uint32_t> spatial_order(const Points& points, std::span<const Eigen::Index> rows) {
  return morton_order(rows.size(), [&](std::size_t k) -> Eigen::Vector3d { return points.row(rows[k]).transpose(); });
}

}  // namespace clustersurf::detail
