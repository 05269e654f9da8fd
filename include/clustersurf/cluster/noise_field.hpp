#pragma once
// The noise level as it varies over a scan: where scans overlap at grazing angles, or a
// scanner's noise grows with range and incidence, a single estimate is the quiet parts'.

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace clustersurf {

class KdTree;
struct NoiseOptions;

/// The noise σ sampled at sites over the surface: each site's σ is the noise estimate scaled by
/// how much its local fits read against the median fits of the same widths, the least of its
/// three widths' readings (relief grows a fit's residual with its width, noise does not; the
/// differences of neighbouring residuals are not read: two scans' layers, each smooth, cancel
/// in them). Empty: no sites, at() gives 0. Movable; queries are const and safe to run
/// concurrently.
class NoiseField {
 public:
  NoiseField();
  /// `sites` (one row each) and their σ, as many; their widest fits' residual kurtosis, as
  /// many, or none where the fits kept only the neighbours facing their centre's way (input
  /// normals part a thin part's sides; two layers of overlapping scans, flatter than noise too,
  /// are then noise); the cloud's `estimate`, and the points of a site's widest and narrowest fits.
  NoiseField(Points sites, std::vector<double> sigma, std::vector<double> kurtosis, double estimate,
             std::size_t widest_points, std::size_t narrowest_points);
  ~NoiseField();
  NoiseField(NoiseField&&) noexcept;
  NoiseField& operator=(NoiseField&&) noexcept;

  bool empty() const { return sigma_.empty(); }
  std::size_t sites() const { return sigma_.size(); }
  /// The noise at `x`, from the median σ of the kFieldSites sites nearest it (fewer when there
  /// are fewer): the estimate plus that median's excess variance over it beyond what the sites'
  /// sampling lets a median of noise of the estimate read (noise_variance_quantile() of the
  /// narrowest fits' squares); with kurtosis, the estimate where the sites' median kurtosis lies
  /// below Gaussian noise's 3 by more than kNoiseMargin standard errors (min_kurtosis()):
  /// residuals flatter than noise's are relief a fit cannot follow, or the two sides of a thin
  /// part, not noise. 0 when empty.
  double at(const Eigen::Vector3d& x) const;
  /// The median kurtosis below which the sites' σ is not taken for noise.
  double min_kurtosis() const { return min_kurtosis_; }

 private:
  std::unique_ptr<Points> sites_;
  std::unique_ptr<KdTree> index_;
  std::vector<double> sigma_;
  std::vector<double> kurtosis_;
  double estimate_ = 0;
  double min_kurtosis_ = 3;
  double sampling_ = 1;  // the variance ratio a median of the sites' noise reads at most
};

/// Sites a NoiseField::at() query takes the median of: one site's σ is a fit of about 96
/// points, whose residual varies by about 7 %; the median of 8 varies by less than the
/// difference between two overlapping scans' noise and one's.
inline constexpr std::size_t kFieldSites = 8;

/// The most a cluster's local noise (NoiseField) exceeds the cloud's estimate by. Relief a
/// sampled fit could not follow at any of its widths reads as noise too; the bound keeps it
/// from averaging detail away. Overlapping scans of the Stanford bunny read up to 1.6 times the
/// estimate where they meet at grazing angles.
inline constexpr double kMaxLocalNoise = 2;

/// The noise estimate (estimate_noise()) and its field over the surface, from the same fits.
struct NoiseEstimate {
  double sigma = 0;
  NoiseField field;
};

/// estimate_noise() with its field: the same sigma, and one site per sampled fit at the
/// subsample the estimate settled on.
NoiseEstimate estimate_noise_field(const Points& points, const KdTree& index, const NoiseOptions& options,
                                   const Points* normals = nullptr, std::uint64_t cloud_points = 0);

}  // namespace clustersurf
