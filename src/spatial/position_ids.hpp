#pragma once
// Points at the same position, as one (a mesh's vertices, a cloud's repeated points).

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf::detail {

/// One id per distinct position of `vertices`: the lowest index of the vertices exactly there
/// (NaN coordinates order last and never equal). Deterministic for any thread count.
std::vector<std::int32_t> position_ids(const Points& vertices);

}  // namespace clustersurf::detail
