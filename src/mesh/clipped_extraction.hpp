#pragma once
// Mesh extraction over part of the lattice: the tiles of a tiled mesh.

#include <clustersurf/mesh/mesh_extraction.hpp>

namespace clustersurf::detail {

/// The part of the lattice a clipped extraction visits.
struct MeshClip {
  BoundingBox box;                ///< only cells meeting this box are visited
  const Points* seeds = nullptr;  ///< points whose cells also start the walk (points near the surface)
};

/// Whether sphere `s` meets box `box`.
inline bool sphere_meets_box(const Sphere& s, const BoundingBox& box) {
  const Eigen::Vector3d below = (box.min - s.center).cwiseMax(0.0), above = (s.center - box.max).cwiseMax(0.0);
  return (below + above).norm() <= s.radius;
}

/// estimate_mesh() of the blended clusters whose supports meet `box` (all of them when null).
MeshEstimate estimate_mesh_within(const ImplicitSurface& surface, double cell_size, const BoundingBox* box);

/// extract_mesh() on the lattice anchored at the tree's box, visiting only the cells meeting
/// clip.box, seeded on the proxies whose supports meet it and on the cells of clip.seeds. Cells
/// both clips visit get the same polygons and vertices (to the bit), so tiles meet exactly.
TriangleMesh extract_clipped(const ImplicitSurface& surface, const MeshClip& clip, const MeshOptions& options,
                             MeshReport* report, const ProgressCallback& progress);

}  // namespace clustersurf::detail
