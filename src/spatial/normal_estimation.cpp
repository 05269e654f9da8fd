#include <clustersurf/spatial/normal_estimation.hpp>

#include "spatial/neighborhood_shape.hpp"

#include <Eigen/Eigenvalues>

#include <tbb/parallel_for.h>

#include <algorithm>

namespace clustersurf {

Eigen::Vector3d unoriented_normal(const KdTree& index, const Eigen::Vector3d& at, std::size_t k,
                                  std::vector<Neighbor>& scratch) {
  index.knn(at, k, scratch);
  if (scratch.size() < 3) return Eigen::Vector3d::Zero();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(
      detail::neighborhood_shape(index.points(), scratch).covariance);  // ascending
  // A line (or a point) spans no plane: its two smaller spreads are both about zero.
  if (eig.info() != Eigen::Success || !(eig.eigenvalues()(1) > 1e-12 * eig.eigenvalues()(2)))
    return Eigen::Vector3d::Zero();
  Eigen::Vector3d n = eig.eigenvectors().col(0);
  Eigen::Index largest = 0;
  n.cwiseAbs().maxCoeff(&largest);
  return n(largest) < 0 ? Eigen::Vector3d(-n) : n;
}

Points estimate_unoriented_normals(const KdTree& index, std::size_t k, std::size_t rows) {
  const Points& points = index.points();
  rows = std::min(rows, static_cast<std::size_t>(points.rows()));
  Points normals(static_cast<Eigen::Index>(rows), 3);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<Neighbor> scratch;
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const auto row = static_cast<Eigen::Index>(i);
      normals.row(row) = unoriented_normal(index, points.row(row).transpose(), k, scratch).transpose();
    }
  });
  return normals;
}

}  // namespace clustersurf
