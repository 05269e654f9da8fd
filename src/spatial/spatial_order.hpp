// A cache-friendly order for many neighbour queries.

#pragma once

#include <clustersurf/point_cloud.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf::detail {

/// The positions 0..count-1 in Morton (Z-curve) order of the cells of `point(k)` on a 2^21 grid
/// over their bounding box (ties by position): consecutive queries then touch the same k-d tree
/// nodes and points, which keeps them in cache (random order made queries 2–3× slower). The
/// order only changes which query runs when, never a query's answer.
std::vector<std::uint32_t> spatial_order(const Points& points);

/// The same for the rows `rows` of `points`: a permutation of 0..rows.size()-1.
std::vector<std::uint32_t> spatial_order(const Points& points, const std::vector<Eigen::Index>& rows);

}  // namespace clustersurf::detail
