#include "cluster/splitters.hpp"

namespace clustersurf::detail {

TwoMeans two_means(const Points& points, std::span<const std::uint32_t> range, const Eigen::Vector3d& seed0,
                   const Eigen::Vector3d& seed1, int max_rounds) {
  TwoMeans r;
  r.centers[0] = seed0;
  r.centers[1] = seed1;
  r.labels.assign(range.size(), 0);
  for (int round = 0; round < max_rounds; ++round) {
    bool changed = round == 0;
    Eigen::Vector3d sum[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    std::size_t count[2] = {0, 0};
    for (std::size_t k = 0; k < range.size(); ++k) {
      const Eigen::Vector3d p = points.row(range[k]).transpose();
      const std::uint8_t label = (p - r.centers[1]).squaredNorm() < (p - r.centers[0]).squaredNorm() ? 1 : 0;
      changed = changed || label != r.labels[k];
      r.labels[k] = label;
      sum[label] += p;
      ++count[label];
    }
    for (int c = 0; c < 2; ++c) {
      r.sizes[c] = count[c];
      if (count[c] > 0) r.centers[c] = sum[c] / static_cast<double>(count[c]);
    }
    if (!changed) break;
  }
  r.energy = 0;
  for (std::size_t k = 0; k < range.size(); ++k)
    r.energy += (points.row(range[k]).transpose() - r.centers[r.labels[k]]).squaredNorm();
  return r;
}

}  // namespace clustersurf::detail
