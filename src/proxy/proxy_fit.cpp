// Least-squares fits of the proxies to a cluster's points (thesis ch. 4).

#include <clustersurf/proxy/moments.hpp>
#include <clustersurf/proxy/proxy.hpp>

#include "proxy/crease_fit.hpp"
#include "proxy/linear_algebra.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/QR>

#include <cmath>

namespace clustersurf {

namespace {

Eigen::Vector3d mean_of(const Points& points, std::span<const std::uint32_t> indices) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (auto i : indices) m += points.row(i).transpose();
  return indices.empty() ? m : Eigen::Vector3d(m / static_cast<double>(indices.size()));
}

/// Flips `axis` so that its largest-magnitude component is positive (a reproducible sign).
Eigen::Vector3d canonical_sign(Eigen::Vector3d axis) {
  Eigen::Index k;
  axis.cwiseAbs().maxCoeff(&k);
  return axis(k) < 0 ? Eigen::Vector3d(-axis) : axis;
}

/// RMS radius of the points about `center`, or 1 when they coincide (a conditioning scale).
double spread(const Points& points, std::span<const std::uint32_t> indices, const Eigen::Vector3d& center) {
  double s = 0;
  for (auto i : indices) s += (points.row(i).transpose() - center).squaredNorm();
  s = indices.empty() ? 0 : std::sqrt(s / static_cast<double>(indices.size()));
  return s > 0 && std::isfinite(s) ? s : 1.0;
}

PlaneProxy fit_plane(const Points& points, std::span<const std::uint32_t> indices) {
  const Frame f = pca_frame(points, indices);
  return PlaneProxy{f.origin, f.axes.col(2)};
}

QuadricProxy fit_quadric(const Points& points, std::span<const std::uint32_t> indices) {
  // Taubin's method: minimize Σ q² / Σ |∇q|² as a generalized eigenproblem. The constant term
  // has no gradient, so it is eliminated by centering the other monomials (c9 = −mean(l)ᵀc).
  using Matrix9 = Eigen::Matrix<double, 9, 9>;
  using Vector9 = Eigen::Matrix<double, 9, 1>;
  QuadricProxy q;
  q.center = mean_of(points, indices);
  q.scale = spread(points, indices, q.center);
  const auto n = static_cast<double>(indices.size());
  Matrix9 m = Matrix9::Zero(), g = Matrix9::Zero();
  Vector9 mean = Vector9::Zero();
  Eigen::Matrix<double, 9, 3> j;
  for (auto i : indices) {
    const Eigen::Vector3d y = (points.row(i).transpose() - q.center) / q.scale;
    Vector9 l;
    l << y.x() * y.x(), y.y() * y.y(), y.z() * y.z(), y.x() * y.y(), y.x() * y.z(), y.y() * y.z(), y.x(), y.y(), y.z();
    j << 2 * y.x(), 0, 0, 0, 2 * y.y(), 0, 0, 0, 2 * y.z(), y.y(), y.x(), 0, y.z(), 0, y.x(), 0, y.z(), y.y(), 1, 0, 0,
        0, 1, 0, 0, 0, 1;
    m.noalias() += l * l.transpose();
    mean += l;
    g.noalias() += j * j.transpose();
  }
  mean /= n;
  m -= n * mean * mean.transpose();
  // A small ridge keeps the gradient moments positive definite for degenerate clusters.
  g += (1e-9 * g.trace() / 9 + 1e-300) * Matrix9::Identity();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Matrix9> eig(m, g);
  Vector9 c = eig.info() == Eigen::Success ? Vector9(eig.eigenvectors().col(0)) : Vector9::Zero();
  if (!c.allFinite() || c.norm() == 0) {
    c.setZero();  // fall back to the PCA plane: q = e3 · y
    const Eigen::Vector3d e3 = pca_frame(points, indices).axes.col(2);
    c.tail<3>() = e3;
  }
  c.normalize();
  for (int k = 0; k < 9; ++k) q.coeffs[static_cast<std::size_t>(k)] = c(k);
  q.coeffs[9] = -mean.dot(c);
  // Orient like the PCA normal (a reproducible choice; the orientation stage fixes the sign).
  Proxy p(q);
  if (p.normal().dot(pca_frame(points, indices).axes.col(2)) < 0) p.flip();
  return std::get<QuadricProxy>(p.variant());
}

}  // namespace

Frame pca_frame(const Points& points, std::span<const std::uint32_t> indices) {
  Frame f;
  f.origin = mean_of(points, indices);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (auto i : indices) {
    const Eigen::Vector3d d = points.row(i).transpose() - f.origin;
    cov.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);  // ascending eigenvalues
  if (eig.info() != Eigen::Success || !eig.eigenvectors().allFinite()) return f;
  const Eigen::Vector3d e1 = canonical_sign(eig.eigenvectors().col(2));
  const Eigen::Vector3d e3 = canonical_sign(eig.eigenvectors().col(0));
  f.axes.col(0) = e1;
  f.axes.col(1) = e3.cross(e1).normalized();
  f.axes.col(2) = e3;
  return f;
}

PolyProxy fit_poly_in_frame(const Frame& frame, const Points& points, std::span<const std::uint32_t> indices) {
  return fit_poly_in_frame(frame, points, indices, {});
}

PolyProxy fit_poly_in_frame(const Frame& frame, const Points& points, std::span<const std::uint32_t> indices,
                            std::span<const double> weights) {
  return fit_poly_in_frame(frame, points, indices, weights, nullptr, 0);
}

namespace {

/// The rows of fit_poly_in_frame()'s least-squares problem, [1 u v u² uv v² | w] per point in
/// coordinates divided by `scale` (for conditioning), each times the square root of its weight;
/// with `slope_factor` > 0, each point also gives the two rows of n_w ∇f + (n_u, n_v) = 0 times
/// slope_factor (the fit's normal along the input normal n: linear in the coefficients and
/// bounded for any n; slopes are invariant under the scaling).
template <class Row>
void for_each_row(const Frame& frame, const Points& points, std::span<const std::uint32_t> indices,
                  std::span<const double> weights, double scale, const Points* normals, double slope_factor,
                  Row&& row) {
  using Vector7 = Eigen::Matrix<double, 7, 1>;
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const Eigen::Vector3d l = frame.to_local(points.row(indices[k]).transpose()) / scale;
    const double w = weights.empty() ? 1.0 : std::sqrt(weights[k]);
    Vector7 r;
    r << 1, l.x(), l.y(), l.x() * l.x(), l.x() * l.y(), l.y() * l.y(), l.z();
    row(Vector7(w * r));
    if (!(slope_factor > 0)) continue;
    Eigen::Vector3d m = frame.axes.transpose() * normals->row(indices[k]).transpose();
    if (m.z() < 0) m = -m;
    if (!m.allFinite()) continue;
    const double a = w * slope_factor * m.z();
    r << 0, a, 0, 2 * a * l.x(), a * l.y(), 0, -w * slope_factor * m.x();
    row(r);
    r << 0, 0, a, 0, a * l.x(), 2 * a * l.y(), -w * slope_factor * m.y();
    row(r);
  }
}

/// The coefficients of the same rows by a Householder QR, reduced block by block (R of
/// [R; next rows] is R of all rows so far: memory stays O(block) however large the cluster), then
/// the minimum-norm solution of the 6×6 triangular system by a complete orthogonal
/// decomposition: exact where the normal equations are rank-deficient or ill-conditioned.
template <class Rows>
Eigen::Matrix<double, 6, 1> solve_by_qr(std::size_t row_count, Rows&& rows) {
  constexpr Eigen::Index kBlock = 1024;
  using Augmented = Eigen::Matrix<double, Eigen::Dynamic, 7>;
  Augmented stack(std::min<Eigen::Index>(kBlock, static_cast<Eigen::Index>(row_count)) + 9, 7);
  Eigen::Index filled = 0, reduced = 0;  // rows in the stack; rows of R carried over (0 or 7)
  const auto reduce = [&] {
    const Eigen::HouseholderQR<Augmented> qr(stack.topRows(filled));
    const Eigen::Index keep = std::min<Eigen::Index>(filled, 7);
    const Augmented r = qr.matrixQR().topRows(keep).template triangularView<Eigen::Upper>();
    stack.topRows(keep) = r;
    reduced = filled = keep;
  };
  rows([&](const Eigen::Matrix<double, 7, 1>& r) {
    stack.row(filled++) = r.transpose();
    if (filled >= reduced + kBlock) reduce();
  });
  if (filled > reduced || reduced == 0) reduce();
  const Eigen::Index k = std::min<Eigen::Index>(reduced, 6);
  Eigen::CompleteOrthogonalDecomposition<Eigen::Matrix<double, Eigen::Dynamic, 6>> cod(stack.topLeftCorner(k, 6));
  cod.setThreshold(1e-10);
  return cod.solve(stack.col(6).head(k));
}

}  // namespace

PolyProxy fit_poly_in_frame(const Frame& frame, const Points& points, std::span<const std::uint32_t> indices,
                            std::span<const double> weights, const Points* normals, double normal_weight) {
  // Least squares on the rows of for_each_row(): by the normal equations (one pass, no
  // allocation) while they are well-conditioned, which the factorization tells; otherwise by QR.
  const std::size_t n = indices.size();
  PolyProxy p;
  p.frame = frame;
  if (n == 0) return p;
  double scale = 0;
  for (auto i : indices) scale += frame.to_local(points.row(i).transpose()).head<2>().squaredNorm();
  scale = std::sqrt(scale / static_cast<double>(n));
  if (!(scale > 0) || !std::isfinite(scale)) scale = 1;
  const bool hermite = normals != nullptr && normal_weight > 0 && std::isfinite(normal_weight);
  // In scaled units a position row's residual is r / scale; the normal rows' weight keeps the
  // ratio normal_weight (a squared length) between the two sums.
  const double slope_factor = hermite ? std::sqrt(normal_weight) / scale : 0;
  const auto rows = [&](auto&& row) {
    for_each_row(frame, points, indices, weights, scale, normals, slope_factor, row);
  };

  Eigen::Matrix<double, 7, 7> gram = Eigen::Matrix<double, 7, 7>::Zero();
  rows([&](const Eigen::Matrix<double, 7, 1>& r) { detail::add_outer_lower(gram, r); });
  // A pivot at most 1e-8 of the largest diagonal entry sends the fit to the QR: the normal
  // equations would lose most of their digits. Above it, in this scaled monomial basis, the
  // normal equations' fit agrees with the QR's to rounding.
  const auto gram_solver = detail::GramSolver<7>::factor(gram, 1e-8);
  const Eigen::Matrix<double, 6, 1> c = gram_solver ? gram_solver->solution() : solve_by_qr(hermite ? 3 * n : n, rows);
  // Back to unscaled coordinates: w = s·c0 + c1 u + c2 v + (c3 u² + c4 uv + c5 v²) / s.
  p.coeffs = {scale * c(0), c(1), c(2), c(3) / scale, c(4) / scale, c(5) / scale};
  for (double& x : p.coeffs)
    if (!std::isfinite(x)) x = 0;
  return p;
}

namespace {

/// The diagonal of the bounding box of points[indices].
double extent_of(const Points& points, std::span<const std::uint32_t> indices) {
  BoundingBox box;
  for (auto i : indices) box.extend(points.row(i).transpose());
  return box.diagonal();
}

}  // namespace

Proxy fit_proxy(ProxyKind kind, const Points& points, std::span<const std::uint32_t> indices) {
  switch (kind) {
    case ProxyKind::Point:
      return PointProxy{mean_of(points, indices)};
    case ProxyKind::Plane:
      return fit_plane(points, indices);
    case ProxyKind::Poly:
      return fit_poly_in_frame(pca_frame(points, indices), points, indices);
    case ProxyKind::Quadric:
      return fit_quadric(points, indices);
    case ProxyKind::Crease: {
      const auto crease = detail::fit_crease(points, indices, pca_frame(points, indices), extent_of(points, indices));
      if (crease) return crease->proxy;
      return fit_plane(points, indices);
    }
  }
  return PointProxy{};
}

ProxyError proxy_error(const Proxy& proxy, const Points& points, std::span<const std::uint32_t> indices) {
  ProxyError e;
  if (indices.empty()) return e;
  double sum = 0;
  for (auto i : indices) {
    const double q = std::abs(proxy.value(points.row(i).transpose()));
    sum += q * q;
    e.max = std::max(e.max, q);
  }
  e.rms = std::sqrt(sum / static_cast<double>(indices.size()));
  return e;
}

}  // namespace clustersurf
