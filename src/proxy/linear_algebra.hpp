#pragma once
// Numerical helpers shared by the proxy fits.

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <optional>

namespace clustersurf::detail {

/// Minimum-norm solution of A x = b for a symmetric positive semi-definite A (the normal
/// equations of a least-squares problem): the pseudo-inverse of thesis eq. 4.13, dropping
/// eigenvalues below `relative_tolerance` times the largest.
template <int N>
Eigen::Matrix<double, N, 1> solve_psd_pinv(const Eigen::Matrix<double, N, N>& a, const Eigen::Matrix<double, N, 1>& b,
                                           double relative_tolerance = 1e-12) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(a);
  const auto& values = eig.eigenvalues();
  const double top = values.cwiseAbs().maxCoeff();
  Eigen::Matrix<double, N, 1> x = Eigen::Matrix<double, N, 1>::Zero();
  if (!(top > 0) || !std::isfinite(top)) return x;
  const Eigen::Matrix<double, N, 1> proj = eig.eigenvectors().transpose() * b;
  for (int i = 0; i < N; ++i)
    if (values(i) > relative_tolerance * top) x += eig.eigenvectors().col(i) * (proj(i) / values(i));
  return x;
}

/// The residual sum of squares min_c Σ (w − bᵀc)² of a least-squares problem from its augmented
/// Gram matrix G = [Σbbᵀ Σwb; Σwbᵀ Σw²] (only the lower triangle is read): the last pivot of the
/// LDLᵀ factorization of G, in one unpivoted pass. Nullopt when a pivot of Σbbᵀ is at most
/// `relative_tolerance` times its largest diagonal entry (rank-deficient or ill-conditioned
/// normal equations, for a solver that handles them).
template <int N>
std::optional<double> residual_sum_of_squares(const Eigen::Matrix<double, N, N>& gram, double relative_tolerance) {
  constexpr int m = N - 1;  // unknowns
  double top = 0;
  for (int j = 0; j < m; ++j) top = std::max(top, gram(j, j));
  if (!(top > 0) || !std::isfinite(top)) return std::nullopt;
  Eigen::Matrix<double, N, N> l;  // unit lower factor (below the diagonal), pivots on it
  for (int j = 0; j < N; ++j) {
    double d = gram(j, j);
    for (int k = 0; k < j; ++k) d -= l(j, k) * l(j, k) * l(k, k);
    if (j == m) return std::max(0.0, d);
    if (!(d > relative_tolerance * top)) return std::nullopt;
    l(j, j) = d;
    for (int i = j + 1; i < N; ++i) {
      double v = gram(i, j);
      for (int k = 0; k < j; ++k) v -= l(i, k) * l(j, k) * l(k, k);
      l(i, j) = v / d;
    }
  }
  return std::nullopt;
}

/// Smallest root t of a t² + b t + c = 0 within [t_min, t_max] (degenerates to the linear case).
inline std::optional<double> smallest_root(double a, double b, double c, double t_min, double t_max) {
  auto inside = [&](double t) { return std::isfinite(t) && t >= t_min && t <= t_max; };
  const double scale = std::max({std::abs(a), std::abs(b), std::abs(c)});
  if (scale == 0) return std::nullopt;
  if (std::abs(a) <= 1e-14 * scale) {
    if (b == 0) return std::nullopt;
    const double t = -c / b;
    return inside(t) ? std::optional<double>(t) : std::nullopt;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return std::nullopt;
  // Numerically stable pair of roots.
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double t0 = q / a;
  double t1 = q != 0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  if (inside(t0)) return t0;
  if (inside(t1)) return t1;
  return std::nullopt;
}

}  // namespace clustersurf::detail
