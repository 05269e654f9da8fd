// The pipeline: a point cloud to an oriented cluster tree and, on request, its mesh.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <Eigen/Eigenvalues>

#include <chrono>
#include <string>

namespace clustersurf {

void require_surface_extent(const PointCloud& cloud) {
  if (cloud.empty()) return;  // build_cluster_tree() refuses it as an option error
  const Eigen::RowVector3d mean = cloud.positions.colwise().mean();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i) {
    const Eigen::Vector3d d = (cloud.positions.row(i) - mean).transpose();
    covariance.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d spread = eig.eigenvalues();  // ascending
  const std::string n = std::to_string(cloud.size());
  if (!(spread(2) > 0)) throw InputError({}, {}, "all " + n + " points coincide: there is no surface to reconstruct");
  if (!(spread(1) > 1e-18 * spread(2)))
    throw InputError({}, {}, "all " + n + " points lie on one line: there is no surface to reconstruct");
}

Reconstruction reconstruct(const PointCloud& cloud, const ReconstructOptions& options,
                           const ProgressCallback& progress) {
  require_surface_extent(cloud);
  const auto start = std::chrono::steady_clock::now();
  const CloudIndex index(cloud);
  Reconstruction out;
  out.tree = build_cluster_tree(index, options.build, progress);
  out.orientation = orient_tree(out.tree, index, options.build.use_normals);
  if (cloud.has_scanners()) out.registration = measure_registration(cloud, index.points());
  out.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (options.mesh) out.mesh = mesh_tree(out.tree, options.meshing, &index, progress);
  return out;
}

}  // namespace clustersurf
