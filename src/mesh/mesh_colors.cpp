#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace clustersurf {

namespace {

/// The weighted median of `values` (pairs of value and weight, reordered): the smallest value at
/// which the cumulated weight reaches half the total.
std::uint8_t weighted_channel_median(std::vector<std::pair<std::uint8_t, double>>& values, double total) {
  std::sort(values.begin(), values.end());
  double sum = 0;
  for (const auto& [value, weight] : values)
    if ((sum += weight) >= 0.5 * total) return value;
  return values.back().first;
}

}  // namespace

Colors colors_from_points(const TriangleMesh& mesh, const KdTree& points, const Colors& colors, std::size_t neighbors) {
  if (colors.rows() != static_cast<Eigen::Index>(points.size()))
    throw OptionError("the points' colors must have one row per point");
  Colors c(mesh.vertices.rows(), 3);
  if (points.size() == 0) {
    c.setConstant(128);
    return c;
  }
  neighbors = std::max<std::size_t>(neighbors, 1);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, mesh.vertices.rows(), 512), [&](const auto& r) {
    std::vector<Neighbor> nb;
    std::vector<double> weight;
    std::vector<std::pair<std::uint8_t, double>> channel;
    for (Eigen::Index v = r.begin(); v != r.end(); ++v) {
      points.knn(mesh.vertices.row(v).transpose(), neighbors, nb);
      const double reach = nb.back().distance_squared;
      weight.clear();
      double total = 0;
      for (const Neighbor& n : nb)
        total += weight.emplace_back(reach > 0 ? std::exp(-n.distance_squared / reach) : 1.0);
      for (int k = 0; k < 3; ++k) {
        channel.clear();
        for (std::size_t i = 0; i < nb.size(); ++i) channel.emplace_back(colors(nb[i].index, k), weight[i]);
        c(v, k) = weighted_channel_median(channel, total);
      }
    }
  });
  return c;
}

Colors intensity_grey(const Eigen::VectorXf& intensity) {
  std::vector<float> sorted;
  sorted.reserve(static_cast<std::size_t>(intensity.size()));
  for (const float v : intensity)
    if (std::isfinite(v)) sorted.push_back(v);
  Colors c(intensity.size(), 3);
  if (sorted.empty()) {
    c.setZero();
    return c;
  }
  const auto at = [&](double q) {
    const auto k = static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1));
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
    return static_cast<double>(sorted[k]);
  };
  const double lo = at(0.01), hi = at(0.99);
  for (Eigen::Index i = 0; i < intensity.size(); ++i) {
    const double v = intensity(i);
    const double t = hi > lo ? (v - lo) / (hi - lo) : 0.5;
    const auto grey = static_cast<std::uint8_t>(std::isfinite(v) ? std::lround(255.0 * std::clamp(t, 0.0, 1.0)) : 0);
    c.row(i).setConstant(grey);
  }
  return c;
}

Colors colors_by_node(const TriangleMesh& mesh, const ImplicitSurface& surface) {
  Colors c(mesh.vertices.rows(), 3);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, mesh.vertices.rows(), 512), [&](const auto& r) {
    for (Eigen::Index v = r.begin(); v != r.end(); ++v) {
      std::int32_t best = -1;
      double best_s = 2;
      surface.for_each_support(mesh.vertices.row(v).transpose(), [&](std::int32_t i, double s) {
        if (s < best_s || (s == best_s && i < best)) best_s = s, best = i;
      });
      c.row(v) = best >= 0 ? node_color(best).transpose() : Eigen::Matrix<std::uint8_t, 1, 3>(128, 128, 128);
    }
  });
  return c;
}

Colors colors_by_distance(const TriangleMesh& mesh, const Points& points, double max_distance,
                          std::vector<double>* distances) {
  return colors_by_distance(mesh, KdTree(points), max_distance, distances);
}

Colors colors_by_distance(const TriangleMesh& mesh, const KdTree& tree, double max_distance,
                          std::vector<double>* distances) {
  Colors c(mesh.vertices.rows(), 3);
  if (distances != nullptr) distances->assign(static_cast<std::size_t>(mesh.vertices.rows()), 0.0);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, mesh.vertices.rows(), 512), [&](const auto& r) {
    std::vector<Neighbor> nb;
    for (Eigen::Index v = r.begin(); v != r.end(); ++v) {
      tree.knn(mesh.vertices.row(v).transpose(), 1, nb);
      const double d = nb.empty() ? max_distance : std::sqrt(nb[0].distance_squared);
      if (distances != nullptr) (*distances)[static_cast<std::size_t>(v)] = d;
      const double t = max_distance > 0 ? d / max_distance : 0.0;
      c.row(v) = distance_color(t).transpose();
    }
  });
  return c;
}

}  // namespace clustersurf
