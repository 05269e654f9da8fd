// The registration error of a multi-scan cloud: at sampled points, the offset between the plane
// of the point's own scan and another scan's points around it.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/scan_registration.hpp>

#include <Eigen/Eigenvalues>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <vector>

namespace clustersurf {

namespace {

/// The offset at point `row`: from the plane through its own scan's `near` points to the mean
/// of the scan with the most of them among the others; none without enough of both.
std::optional<double> offset_at(const PointCloud& cloud, const Points& points, Eigen::Index row,
                                const std::vector<Neighbor>& near, std::size_t min_points) {
  const std::uint32_t own = cloud.scanner_of_point[static_cast<std::size_t>(row)];
  std::map<std::uint32_t, std::size_t> counts;
  for (const Neighbor& n : near) ++counts[cloud.scanner_of_point[n.index]];
  std::uint32_t other = own;
  std::size_t most = 0;
  for (const auto& [scan, count] : counts)
    if (scan != own && count > most) other = scan, most = count;
  if (counts[own] < min_points || most < min_points) return std::nullopt;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Neighbor& n : near)
    if (cloud.scanner_of_point[n.index] == own) centroid += points.row(n.index).transpose();
  centroid /= static_cast<double>(counts[own]);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Neighbor& n : near)
    if (cloud.scanner_of_point[n.index] == own) {
      const Eigen::Vector3d d = points.row(n.index).transpose() - centroid;
      scatter += d * d.transpose();
    }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  if (solver.info() != Eigen::Success) return std::nullopt;
  const Eigen::Vector3d normal = solver.eigenvectors().col(0);
  double offset = 0;
  for (const Neighbor& n : near)
    if (cloud.scanner_of_point[n.index] == other) offset += normal.dot(points.row(n.index).transpose() - centroid);
  offset /= static_cast<double>(most);
  return std::isfinite(offset) ? std::optional(offset) : std::nullopt;
}

}  // namespace

ScanRegistration measure_registration(const PointCloud& cloud, const KdTree& index,
                                      const RegistrationOptions& options) {
  if (options.neighbors < 2 * options.min_points || options.min_points < 3)
    throw OptionError("the registration measure needs at least 3 points of each scan and twice that many neighbours");
  ScanRegistration out;
  const auto n = static_cast<std::size_t>(cloud.size());
  if (cloud.scanner_of_point.size() != n || n == 0 || index.size() != n) return out;
  out.scans = scan_count(cloud);
  if (out.scans < 2 || options.samples == 0) return out;
  const std::size_t samples = std::min(options.samples, n);
  std::vector<std::optional<double>> offsets(samples);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples, 256), [&](const auto& r) {
    std::vector<Neighbor> near;
    for (std::size_t s = r.begin(); s != r.end(); ++s) {
      const auto row = static_cast<Eigen::Index>(s * n / samples);
      index.knn(cloud.positions.row(row).transpose(), options.neighbors, near);
      offsets[s] = offset_at(cloud, index.points(), row, near, options.min_points);
    }
  });
  std::vector<double> magnitude;
  double squares = 0;
  for (const std::optional<double>& o : offsets)
    if (o) magnitude.push_back(std::abs(*o)), squares += *o * *o;
  out.overlaps = magnitude.size();
  if (magnitude.empty()) return out;
  const auto middle = magnitude.begin() + static_cast<std::ptrdiff_t>(magnitude.size() / 2);
  std::nth_element(magnitude.begin(), middle, magnitude.end());
  out.median_offset = *middle;
  out.rms_offset = std::sqrt(squares / static_cast<double>(magnitude.size()));
  return out;
}

}  // namespace clustersurf
