#include <clustersurf/cluster/noise_field.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <clustersurf/cluster/noise.hpp>

#include <algorithm>
#include <cmath>

namespace clustersurf {

NoiseField::NoiseField() = default;
NoiseField::~NoiseField() = default;
NoiseField::NoiseField(NoiseField&&) noexcept = default;
NoiseField& NoiseField::operator=(NoiseField&&) noexcept = default;

NoiseField::NoiseField(Points sites, std::vector<double> sigma, std::vector<double> kurtosis, double estimate,
                       std::size_t widest_points, std::size_t narrowest_points)
    : sigma_(std::move(sigma)), kurtosis_(std::move(kurtosis)), estimate_(estimate) {
  if (static_cast<std::size_t>(sites.rows()) != sigma_.size() ||
      (!kurtosis_.empty() && kurtosis_.size() != sigma_.size()))
    throw OptionError("noise field: one sigma per site, and one kurtosis or none, are needed");
  if (sigma_.empty()) return;
  // The sample kurtosis of n Gaussian values varies by √(24 / n); the median of m such by
  // about √(π / 2) times that over √m.
  const double sites_read = static_cast<double>(std::min(kFieldSites, sigma_.size()));
  const double median_spread = std::sqrt(M_PI / 2 / sites_read);
  min_kurtosis_ = 3 - kNoiseMargin * median_spread * std::sqrt(24 / std::max(static_cast<double>(widest_points), 1.0));
  // A site's σ is a narrowest fit's mean of k − 6 squares; the median of m sites is as precise as
  // a mean of 2 / π times m times as many.
  const double squares = std::max(static_cast<double>(narrowest_points), 7.0) - 6;
  sampling_ = noise_variance_quantile(2 / M_PI * sites_read * squares);
  sites_ = std::make_unique<Points>(std::move(sites));
  index_ = std::make_unique<KdTree>(*sites_);
}

double NoiseField::at(const Eigen::Vector3d& x) const {
  if (empty()) return 0;
  std::vector<Neighbor> near;
  index_->knn(x, kFieldSites, near);
  const auto median = [&](const std::vector<double>& of) {
    std::vector<double> v;
    v.reserve(near.size());
    for (const Neighbor& q : near) v.push_back(of[q.index]);
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  if (!kurtosis_.empty() && median(kurtosis_) < min_kurtosis_) return estimate_;
  const double sigma = median(sigma_), e2 = estimate_ * estimate_;
  return std::sqrt(e2 + std::max(0.0, sigma * sigma - sampling_ * e2));
}

}  // namespace clustersurf
