#include <clustersurf/point_cloud.hpp>

namespace clustersurf {

BoundingBox bounding_box(const Points& points) {
  BoundingBox box;
  if (points.rows() > 0) {
    box.min = points.colwise().minCoeff().transpose();
    box.max = points.colwise().maxCoeff().transpose();
  }
  return box;
}

}  // namespace clustersurf
