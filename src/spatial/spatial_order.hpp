// A cache-friendly order for many neighbour queries.

#pragma once

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace clustersurf::detail {

/// The Morton (Z-curve) code of the cell (x, y, z), each coordinate's low 21 bits interleaved (x
/// highest): the code of the cell 2^l times larger that holds it is the code shifted right by
/// 3 l.
std::uint64_t morton_code(std::uint64_t x, std::uint64_t y, std::uint64_t z);

/// The rows of `points` in Morton (Z-curve) order of their cells on a 2^21 grid over their
/// bounding box (ties by row): consecutive queries then touch the same k-d tree nodes and points,
/// which keeps them in cache (random order made queries 2–3× slower). The order only changes
/// which query runs when, never a query's answer.
std::vector<std::uint32_t> spatial_order(const Points& points);

/// The same for the rows `rows` of `points`: a permutation of 0..rows.size()-1.
std::vector<std::uint32_t> spatial_order(const Points& points, std::span<const Eigen::Index> rows);

}  // namespace clustersurf::detail
