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

/// m += sign · b bᵀ on the lower triangle only (the part GramSolver and selfadjointView<Lower>
/// read), one product per entry: the sums of Eigen's rankUpdate, half of a full outer product's.
template <int N>
void add_outer_lower(Eigen::Matrix<double, N, N>& m, const Eigen::Matrix<double, N, 1>& b, double sign = 1.0) {
  for (int j = 0; j < N; ++j) {
    const double bj = sign * b(j);
    for (int i = j; i < N; ++i) m(i, j) += bj * b(i);
  }
}

/// A least-squares problem min_c Σ (w − bᵀc)² solved from its augmented Gram matrix
/// G = [Σbbᵀ Σwb; Σwbᵀ Σw²] (N − 1 unknowns) by one unpivoted LDLᵀ factorization of G: the last
/// pivot is the residual sum of squares, the last row of the factor gives the solution.
template <int N>
class GramSolver {
 public:
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N - 1, 1>;

  /// Factors `gram` (only its lower triangle is read). Nullopt when a pivot of Σbbᵀ is at most
  /// `relative_tolerance` times its largest diagonal entry: then the normal equations are
  /// rank-deficient or ill-conditioned, for a solver that handles them. Larger pivots do not
  /// prove the converse in general; the callers' bases (monomials of coordinates scaled to the
  /// cluster) keep the factor itself well-conditioned.
  static std::optional<GramSolver> factor(const Matrix& gram, double relative_tolerance) {
    double top = 0;
    for (int j = 0; j < N - 1; ++j) top = std::max(top, gram(j, j));
    if (!(top > 0) || !std::isfinite(top)) return std::nullopt;
    GramSolver f;
    Matrix& l = f.l_;  // unit lower factor below the diagonal, pivots on it
    for (int j = 0; j < N; ++j) {
      double d = gram(j, j);
      for (int k = 0; k < j; ++k) d -= l(j, k) * l(j, k) * l(k, k);
      if (j == N - 1) {
        l(j, j) = std::max(0.0, d);
        break;
      }
      if (!(d > relative_tolerance * top)) return std::nullopt;
      l(j, j) = d;
      for (int i = j + 1; i < N; ++i) {
        double v = gram(i, j);
        for (int k = 0; k < j; ++k) v -= l(i, k) * l(j, k) * l(k, k);
        l(i, j) = v / d;
      }
    }
    return f;
  }

  /// min_c Σ (w − bᵀc)².
  double residual_sum_of_squares() const { return l_(N - 1, N - 1); }

  /// The minimizing c: Lᵀ c = (last row of L), by back substitution.
  Vector solution() const {
    Vector c;
    for (int i = N - 2; i >= 0; --i) {
      double v = l_(N - 1, i);
      for (int k = i + 1; k < N - 1; ++k) v -= l_(k, i) * c(k);
      c(i) = v;
    }
    return c;
  }

 private:
  GramSolver() = default;
  Matrix l_;
};

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
