// A cluster's local frame from its positions or normals.

#include "cluster/cluster_frame.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <optional>
#include <utility>

namespace clustersurf::detail {

namespace {

/// The mean axis of the normals of the rows `range` and their spread about it (the tilt
/// variance of one normal): 2 (1 − |mean|) for the input's oriented normals, 1 − μ for
/// estimated unoriented ones.
/// Nullopt without usable normals (a zero mean, or a NaN among them).
std::optional<std::pair<Eigen::Vector3d, double>> normals_axis(const Points& points,
                                                               std::span<const std::uint32_t> range,
                                                               const FrameNormals& normals,
                                                               std::span<const std::uint32_t> ids) {
  const double n = static_cast<double>(range.size());
  if (normals.input != nullptr) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (auto row : range) sum += normals.input->row(ids[row]).transpose();
    const double length = sum.norm() / n;
    if (!(length > 0)) return std::nullopt;
    return std::pair{Eigen::Vector3d(sum / sum.norm()), 2 * std::max(0.0, 1 - length)};
  }
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  for (auto row : range) {
    const Eigen::Vector3d m = normals.estimated->at(ids[row], points.row(row).transpose());
    outer.noalias() += m * m.transpose();
  }
  if (!outer.allFinite()) return std::nullopt;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(outer / n);  // ascending eigenvalues
  if (eig.info() != Eigen::Success || !(eig.eigenvalues()(2) > 0)) return std::nullopt;
  return std::pair{Eigen::Vector3d(eig.eigenvectors().col(2)), std::max(0.0, 1 - eig.eigenvalues()(2))};
}

}  // namespace

ClusterFrame cluster_frame(const Points& points, std::span<const std::uint32_t> range, const FrameNormals& normals,
                           std::span<const std::uint32_t> ids, double noise) {
  ClusterFrame out{pca_frame(points, range)};
  Frame& f = out.frame;
  if (!(noise > 0) || range.empty()) return out;
  double across = 0;  // Σ squared distance along the frame's second axis (the plane's narrower spread)
  for (auto row : range) {
    const double d = (points.row(row).transpose() - f.origin).dot(f.axes.col(1));
    across += d * d;
  }
  const double n = static_cast<double>(range.size());
  out.determined = normals.input != nullptr || across >= kDeterminedSpread * noise * noise * n;
  if (range.size() < 3 || !(across > 0)) return out;  // a line
  // Estimated normals carry the positions' own information, over overlapping neighbourhoods:
  // they only stand in for a principal frame the noise chooses.
  if (normals.input == nullptr && (normals.estimated == nullptr || out.determined)) return out;
  const auto mean = normals_axis(points, range, normals, ids);
  if (!mean) return out;
  const double tilt_principal = noise * noise / (across / n * n);
  const double tilt_normals = mean->second / n;
  if (!(tilt_normals < tilt_principal)) return out;
  const Eigen::Vector3d& z = mean->first;
  Eigen::Vector3d x = f.axes.col(0) - f.axes.col(0).dot(z) * z;
  if (!(x.norm() > 1e-6)) x = z.unitOrthogonal();
  x.normalize();
  f.axes.col(0) = x;
  f.axes.col(1) = z.cross(x);
  f.axes.col(2) = z;
  out.determined = true;
  return out;
}

}  // namespace clustersurf::detail
