// The noise a blend of leaf fits keeps at a point, against that of one local fit there.

#include "mesh/blend_noise.hpp"

#include <clustersurf/surface/box_walk.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace clustersurf::detail {

namespace {

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

/// The fit's variance at squared distance ρ² from the disk's centre over that at the centre, as
/// 1 + a ρ² + b ρ⁴: mᵀ C m for m = (1, ρ, 0, ρ², 0, 0) and C = A⁻¹ B A⁻¹ the coefficients'
/// covariance (A the moments of the weight, B those of its square), whose odd moments vanish on
/// the disk.
struct OffCenterPolynomial {
  double a = 0, b = 0;
  OffCenterPolynomial() {
    const Matrix6 inverse = disk_moments(3).inverse();
    const Matrix6 c = inverse * disk_moments(6) * inverse;
    a = (c(1, 1) + 2 * c(0, 3)) / c(0, 0);
    b = c(3, 3) / c(0, 0);
  }
};

}  // namespace

double off_center_variance(double rho2) {
  static const OffCenterPolynomial p;
  const double r2 = std::clamp(rho2, 0.0, 1.0);
  return 1 + r2 * (p.a + r2 * p.b);
}

double blend_variance_share(const ImplicitSurface::BoxWalk& near, const Eigen::Vector3d& x, double fit_radius) {
  const ImplicitSurface& surface = near.surface();
  double weight = 0, deviation = 0;
  near.for_each_support(x, [&](std::int32_t i, double s) {
    const double w = blend_weight(s);
    weight += w;
    deviation += w * fit_radius / surface.radius(i) * std::sqrt(off_center_variance(s));
  });
  if (!(weight > 0)) return 0;
  const double ratio = deviation / weight;
  return std::min(1.0, ratio * ratio);
}

}  // namespace clustersurf::detail
