#pragma once
// Surface normals estimated from positions alone.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <cstddef>
#include <vector>

namespace clustersurf {

/// The unoriented normal at `at`: the axis of least spread of its `k` nearest points among the
/// points `index` holds, a unit vector in a canonical sign (largest component positive: the
/// sign is not estimated), or zero when they span no plane (fewer than 3, or all on a line).
/// `scratch` holds the neighbours between calls.
Eigen::Vector3d unoriented_normal(const KdTree& index, const Eigen::Vector3d& at, std::size_t k,
                                  std::vector<Neighbor>& scratch);

/// unoriented_normal() at each of the first `rows` points of `index` (itself among its
/// neighbours), as rows. Each row depends on its point's neighbours only, never on the thread
/// count.
Points estimate_unoriented_normals(const KdTree& index, std::size_t k, std::size_t rows);

}  // namespace clustersurf
