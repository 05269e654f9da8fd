#pragma once
// Which mesh vertices the input points reach: the trim's test, shared with the closed mesh's
// marking of what was filled in.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/mesh/mesh_trim.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace clustersurf::detail {

/// Per vertex of `mesh`, 1 when it lies no farther from its nearest point of `index` than
/// options.spread_factor times that point's spread (mean distance to its options.neighbors
/// nearest points), or within 1.5 times that with data all around it on one sheet of the data,
/// and not more than a spread off the sheet the data forms around it with a neighbour as far
/// off (TrimOptions::spread_factor; the reach bounded by TrimOptions::max_reach_spreads), else 0.
/// `spread`: those spreads, one per point of `index`, or empty: measured here.
std::vector<std::uint8_t> vertices_near_data(const TriangleMesh& mesh, const KdTree& index, const TrimOptions& options,
                                             std::span<const double> spread = {});

}  // namespace clustersurf::detail
