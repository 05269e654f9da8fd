#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/resample.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <tuple>

namespace clustersurf {

PointCloud subsample(const PointCloud& cloud, std::size_t count, std::uint64_t seed) {
  const auto n = static_cast<std::size_t>(cloud.size());
  if (count >= n) return cloud;
  // Selection sampling (Knuth's algorithm S): one pass, order kept, exactly `count` points.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Index> keep;
  keep.reserve(count);
  for (std::size_t i = 0; i < n && keep.size() < count; ++i)
    if (static_cast<double>(n - i) * u(rng) < static_cast<double>(count - keep.size()))
      keep.push_back(static_cast<Eigen::Index>(i));
  return select(cloud, keep);
}

PointCloud voxel_downsample(const PointCloud& cloud, double voxel_size) {
  if (!(voxel_size > 0) || !std::isfinite(voxel_size)) throw OptionError("voxel size must be a positive number");
  const BoundingBox box = bounding_box(cloud.positions);
  const auto n = cloud.size();
  const Eigen::Vector3d cells = (box.extent() / voxel_size).array().floor() + 1;
  if (cells.prod() > 9.0e18) throw OptionError("voxel size is too small for this cloud's extent");
  using Key = std::tuple<std::int64_t, std::int64_t, std::int64_t>;  // (z, y, x): x fastest
  std::vector<std::pair<Key, Eigen::Index>> keyed(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d c = ((cloud.positions.row(i).transpose() - box.min) / voxel_size).array().floor();
    keyed[static_cast<std::size_t>(i)] = {
        Key{static_cast<std::int64_t>(c.z()), static_cast<std::int64_t>(c.y()), static_cast<std::int64_t>(c.x())}, i};
  }
  std::sort(keyed.begin(), keyed.end());
  PointCloud out;
  std::vector<double> pos, nrm, col;
  std::vector<std::vector<float>> attr(cloud.attributes.size());
  for (std::size_t a = 0; a < keyed.size();) {
    std::size_t b = a;
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), nn = Eigen::Vector3d::Zero(), cc = Eigen::Vector3d::Zero();
    for (; b < keyed.size() && std::get<0>(keyed[b]) == std::get<0>(keyed[a]); ++b) {
      const Eigen::Index i = keyed[b].second;
      p += cloud.positions.row(i).transpose();
      if (cloud.has_normals()) nn += cloud.normals.row(i).transpose();
      if (cloud.has_colors()) cc += cloud.colors.row(i).transpose().cast<double>();
    }
    const double m = static_cast<double>(b - a);
    for (std::size_t k = 0; k < attr.size(); ++k) {
      double sum = 0;
      for (std::size_t j = a; j < b; ++j) sum += cloud.attributes[k].values(keyed[j].second);
      attr[k].push_back(static_cast<float>(sum / m));
    }
    p /= m;
    pos.insert(pos.end(), {p.x(), p.y(), p.z()});
    if (cloud.has_normals()) {
      if (nn.norm() > 0) nn.normalize();
      nrm.insert(nrm.end(), {nn.x(), nn.y(), nn.z()});
    }
    if (cloud.has_colors()) {
      cc = (cc / m).array().round();
      col.insert(col.end(), {cc.x(), cc.y(), cc.z()});
    }
    a = b;
  }
  const auto m = static_cast<Eigen::Index>(pos.size() / 3);
  out.positions = Eigen::Map<Points>(pos.data(), m, 3);
  if (cloud.has_normals()) out.normals = Eigen::Map<Points>(nrm.data(), m, 3);
  if (cloud.has_colors())
    out.colors =
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(col.data(), m, 3).cast<std::uint8_t>();
  out.origin = cloud.origin;
  out.up = cloud.up;
  for (std::size_t k = 0; k < attr.size(); ++k)
    out.attributes.push_back({cloud.attributes[k].name, Eigen::Map<Eigen::VectorXf>(attr[k].data(), m)});
  return out;
}

}  // namespace clustersurf
