// The noise a blend of leaf fits keeps at a point, against that of one local fit there.

#include "mesh/blend_noise.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace clustersurf::detail {

namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// ∫ r^a (1 − r²)^k r dr over [0, 1]: ½ B(a/2 + 1, k + 1).
double radial_moment(double a, double k) {
  return 0.5 * std::exp(std::lgamma(a / 2 + 1) + std::lgamma(k + 1) - std::lgamma(a / 2 + k + 2));
}

/// Σ w m mᵀ over the unit disk for the weight (1 − r²)^k and the monomials
/// m = (1, u, v, u², uv, v²), per unit density.
Matrix6 disk_moments(double k) {
  constexpr double pi = std::numbers::pi;
  Matrix6 m = Matrix6::Zero();
  m(0, 0) = 2 * pi * radial_moment(0, k);
  m(1, 1) = m(2, 2) = m(0, 3) = m(3, 0) = m(0, 5) = m(5, 0) = pi * radial_moment(2, k);
  m(3, 3) = m(5, 5) = 0.75 * pi * radial_moment(4, k);
  m(3, 5) = m(5, 3) = m(4, 4) = 0.25 * pi * radial_moment(4, k);
  return m;
}

/// The covariance of the weighted fit's coefficients per unit noise variance and density,
/// A⁻¹ B A⁻¹ with A the moments of the weight and B those of its square.
Matrix6 coefficient_covariance() {
  const Matrix6 a = disk_moments(3).inverse();
  return a * disk_moments(6) * a;
}

}  // namespace

double off_center_variance(double rho2) {
  static const Matrix6 covariance = coefficient_covariance();
  const auto at = [&](double r2) {
    Vector6 m;
    m << 1, std::sqrt(r2), 0, r2, 0, 0;
    return m.dot(covariance * m);
  };
  static const double center = at(0);
  return at(std::clamp(rho2, 0.0, 1.0)) / center;
}

double blend_variance_share(const ImplicitSurface& surface, const Eigen::Vector3d& x, double fit_radius) {
  double weight = 0, deviation = 0;
  surface.for_each_support(x, [&](std::int32_t i, double s) {
    const double w = blend_weight(s);
    weight += w;
    deviation += w * fit_radius / surface.radius(i) * std::sqrt(off_center_variance(s));
  });
  if (!(weight > 0)) return 0;
  const double ratio = deviation / weight;
  return std::min(1.0, ratio * ratio);
}

}  // namespace clustersurf::detail
