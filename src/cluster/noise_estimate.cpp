#include <clustersurf/kd_tree.hpp>
#include <clustersurf/noise.hpp>
#include <clustersurf/proxy.hpp>

#include "core/splitmix.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace clustersurf {

namespace {

/// The sampled neighbourhoods never come from fewer points than this.
constexpr std::size_t kMinCoarsePoints = 4096;

struct LocalNoise {
  double sigma = 0;  // median RMS residual of the local fits
  double width = 0;  // median neighbourhood radius
};

/// Median noise and neighbourhood radius over evenly strided points of `points`.
LocalNoise local_noise(const Points& points, const KdTree& tree, const NoiseOptions& options) {
  const auto n = static_cast<std::size_t>(points.rows());
  const std::size_t k = std::min(options.neighbors, n);
  const std::size_t samples = std::min(options.samples, n);
  const double stride = static_cast<double>(n) / static_cast<double>(samples);
  std::vector<double> sigma(samples), width(samples);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples), [&](const auto& r) {
    std::vector<Neighbor> nb;
    std::vector<std::uint32_t> idx;
    for (std::size_t s = r.begin(); s != r.end(); ++s) {
      const auto i = static_cast<Eigen::Index>(static_cast<double>(s) * stride);
      tree.knn(points.row(i).transpose(), k, nb);
      idx.clear();
      for (const auto& m : nb) idx.push_back(m.index);
      width[s] = nb.empty() ? 0 : std::sqrt(nb.back().distance_squared);
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
  const auto median = [&](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(samples / 2), v.end());
    return v[samples / 2];
  };
  return {median(sigma), median(width)};
}

/// The points of the nested subsample of `level` (about 4^-level of them; the support
/// sampler's levels).
Points subsample(const Points& points, unsigned level) {
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    if (detail::in_subsample(static_cast<std::uint64_t>(i), level)) keep.push_back(i);
  Points out(static_cast<Eigen::Index>(keep.size()), 3);
  for (std::size_t j = 0; j < keep.size(); ++j) out.row(static_cast<Eigen::Index>(j)) = points.row(keep[j]);
  return out;
}

}  // namespace

double estimate_noise(const Points& points, const NoiseOptions& options) {
  const auto n = static_cast<std::size_t>(points.rows());
  if (std::min(options.neighbors, n) < 10 || options.samples == 0) return 0;
  return estimate_noise(points, KdTree(points), options);
}

double estimate_noise(const Points& points, const KdTree& tree, const NoiseOptions& options) {
  const auto n = static_cast<std::size_t>(points.rows());
  if (std::min(options.neighbors, n) < 10 || options.samples == 0) return 0;
  LocalNoise est = local_noise(points, tree, options);
  // Dense samples of a noisy surface: the neighbourhoods are thin slabs of noise, and the
  // local fit follows it. Coarsen until the neighbourhoods are wide compared with the noise.
  for (unsigned level = 1; est.width < options.min_width_ratio * est.sigma && (n >> (2 * level)) >= kMinCoarsePoints; ++level) {
    const Points coarse = subsample(points, level);
    est = local_noise(coarse, KdTree(coarse), options);
  }
  return est.sigma;
}

}  // namespace clustersurf
