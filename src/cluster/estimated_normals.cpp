#include "cluster/estimated_normals.hpp"

#include <clustersurf/spatial/normal_estimation.hpp>

namespace clustersurf::detail {

EstimatedNormals::EstimatedNormals(const KdTree& index, std::size_t ids)
    : index_(index), normals_(static_cast<Eigen::Index>(ids), 3), known_(ids, 0) {}

Eigen::Vector3d EstimatedNormals::at(std::uint32_t id, const Eigen::Vector3d& position) const {
  if (known_[id] == 0) {
    thread_local std::vector<Neighbor> scratch;
    normals_.row(id) = unoriented_normal(index_, position, kFrameNeighbors, scratch).transpose();
    known_[id] = 1;
  }
  return normals_.row(id).transpose();
}

}  // namespace clustersurf::detail
