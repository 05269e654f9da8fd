#pragma once
// Points that repeat another point's position exactly: one point kept per position.

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace clustersurf {

/// The rows of `rows`, in their order, without those whose position an earlier one of them
/// holds exactly: one row per distinct position (a repeat adds nothing of the surface and
/// would count twice in every fit and spacing). With `coincident` (one flag per row of
/// `positions`, nonzero where another point lies at the same position: find_outliers()'s), only
/// the flagged rows are compared, so a cloud without repeats costs one pass; without it, all of
/// `rows` are. Deterministic: the kept rows depend on the positions and the order of `rows` only.
std::vector<std::uint32_t> first_of_each_position(const Points& positions, std::vector<std::uint32_t> rows,
                                                  std::span<const std::uint8_t> coincident = {});

}  // namespace clustersurf
