#include <clustersurf/kd_tree.hpp>
#include <clustersurf/noise.hpp>
#include <clustersurf/proxy.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace clustersurf {

double estimate_noise(const Points& points, const NoiseOptions& options) {
  const auto n = static_cast<std::size_t>(points.rows());
  if (std::min(options.neighbors, n) < 10 || options.samples == 0) return 0;
  return estimate_noise(points, KdTree(points), options);
}

double estimate_noise(const Points& points, const KdTree& tree, const NoiseOptions& options) {
  const auto n = static_cast<std::size_t>(points.rows());
  const std::size_t k = std::min(options.neighbors, n);
  if (k < 10 || options.samples == 0) return 0;
  const std::size_t samples = std::min(options.samples, n);
  const double stride = static_cast<double>(n) / static_cast<double>(samples);
  std::vector<double> sigma(samples);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples), [&](const auto& r) {
    std::vector<Neighbor> nb;
    std::vector<std::uint32_t> idx;
    for (std::size_t s = r.begin(); s != r.end(); ++s) {
      const auto i = static_cast<Eigen::Index>(static_cast<double>(s) * stride);
      tree.knn(points.row(i).transpose(), k, nb);
      idx.clear();
      for (const auto& m : nb) idx.push_back(m.index);
      const Frame frame = pca_frame(points, idx);
      const PolyProxy poly = fit_poly_in_frame(frame, points, idx);
      double ss = 0;
      for (auto j : idx) {
        const Eigen::Vector3d l = frame.to_local(points.row(j).transpose());
        const double f = poly.height(l.x(), l.y());
        ss += (l.z() - f) * (l.z() - f);
      }
      // Six coefficients are fitted from k residuals: E[ss] = (k − 6) σ².
      sigma[s] = std::sqrt(ss / static_cast<double>(k - 6));
    }
  });
  std::nth_element(sigma.begin(), sigma.begin() + static_cast<std::ptrdiff_t>(samples / 2), sigma.end());
  return sigma[samples / 2];
}

}  // namespace clustersurf
