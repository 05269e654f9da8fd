#pragma once
// Reducing a point cloud: random subsets and voxel-grid averaging.

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf {

/// A uniformly random subset of `count` points (all of them if count >= size), kept in input
/// order. The same seed gives the same subset.
PointCloud subsample(const PointCloud& cloud, std::size_t count, std::uint64_t seed = 1);

/// One point per occupied cube of side `voxel_size` (grid anchored at the bbox minimum): the
/// mean position, the normalized mean normal and the mean color of the points inside. Output is
/// ordered by voxel (x fastest), independent of input order; attributes are averaged, the
/// origin kept and the scanners dropped. Throws OptionError for size <= 0.
PointCloud voxel_downsample(const PointCloud& cloud, double voxel_size);

}  // namespace clustersurf
