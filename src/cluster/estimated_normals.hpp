#pragma once
// Normals estimated from the positions, on demand, for the frames of clusters whose own
// principal frame the noise chooses.

#include <clustersurf/spatial/kd_tree.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf::detail {

/// Without input normals, the frames follow normals estimated over this many nearest points
/// of each point: about what the support of a leaf of min_points holds (alpha × its extent),
/// so that the normals' scale is that of the narrowest supports.
inline constexpr std::size_t kFrameNeighbors = 30;

/// The unoriented normal of each input point over its kFrameNeighbors nearest points of
/// `index`, computed the first time it is asked for and kept. Calls for distinct ids may run
/// concurrently (the tree builder's subtrees hold disjoint points); calls for one id may not.
class EstimatedNormals {
 public:
  /// `index`: the points the neighbourhoods come from; `ids`: how many input ids there are.
  EstimatedNormals(const KdTree& index, std::size_t ids);

  /// The normal of input point `id`, at `position`: unoriented_normal() over its neighbours.
  Eigen::Vector3d at(std::uint32_t id, const Eigen::Vector3d& position) const;

 private:
  const KdTree& index_;
  mutable Points normals_;
  mutable std::vector<std::uint8_t> known_;
};

}  // namespace clustersurf::detail
