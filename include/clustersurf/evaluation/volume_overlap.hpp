#pragma once
// How much of the solid a closed reference bounds a closed reconstruction bounds too: the
// volumetric intersection over union that shape-completion papers report.

#include <clustersurf/core/point_cloud.hpp>

#include <cstddef>
#include <cstdint>

namespace clustersurf {

/// How volume_overlap() samples the space.
struct VolumeOverlapOptions {
  /// Points tested, one jittered in each cell of a regular grid over the box holding both meshes
  /// (rounded to a cube of cells per side).
  std::size_t samples = 512'000;
  std::uint64_t seed = 1;
};

/// The solids two meshes bound, compared over the same sample points. Volumes are in the
/// input's units cubed.
struct VolumeOverlap {
  double iou = 0;                    ///< |A ∩ B| / |A ∪ B| (1 when both are empty)
  double reconstruction_volume = 0;  ///< |A|
  double reference_volume = 0;       ///< |B|
  std::size_t samples = 0;           ///< points tested
};

/// Compares the solids `reconstruction` and `reference` bound (each in its own frame: positions
/// plus origin). A point is inside a mesh when at least two of three rays from it, in fixed
/// directions, cross the mesh an odd number of times: exact for closed meshes, and a crossing
/// miscounted at a defect (a non-manifold edge, a pinhole) sways one ray, not the vote. The
/// same figures for a seed whatever the thread count. Throws OptionError when either mesh has no
/// triangles, a coordinate that is not finite or a triangle corner that is not one of its
/// vertices, or the options sample nothing.
VolumeOverlap volume_overlap(const TriangleMesh& reconstruction, const TriangleMesh& reference,
                             const VolumeOverlapOptions& options = {});

}  // namespace clustersurf
