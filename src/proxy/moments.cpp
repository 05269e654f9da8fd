// Running moment sums for O(1) plane and polynomial fits.

#include <clustersurf/proxy/moments.hpp>

#include "proxy/linear_algebra.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace clustersurf {

void PlaneMoments::add(const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - origin_;
  n_ += 1;
  s_ += d;
  q_.noalias() += d * d.transpose();
}

void PlaneMoments::remove(const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - origin_;
  n_ -= 1;
  s_ -= d;
  q_.noalias() -= d * d.transpose();
}

PlaneMoments& PlaneMoments::operator+=(const PlaneMoments& o) {
  n_ += o.n_, s_ += o.s_, q_ += o.q_;
  return *this;
}

PlaneMoments& PlaneMoments::operator-=(const PlaneMoments& o) {
  n_ -= o.n_, s_ -= o.s_, q_ -= o.q_;
  return *this;
}

Eigen::Matrix3d PlaneMoments::covariance() const {
  if (n_ <= 0) return Eigen::Matrix3d::Zero();
  const Eigen::Vector3d m = s_ / n_;
  return q_ / n_ - m * m.transpose();
}

PlaneProxy PlaneMoments::fit() const {
  PlaneProxy p;
  if (n_ <= 0) return p;
  p.point = origin_ + s_ / n_;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance());
  Eigen::Vector3d nrm = eig.eigenvectors().col(0);
  Eigen::Index k;
  nrm.cwiseAbs().maxCoeff(&k);
  p.normal = nrm(k) < 0 ? Eigen::Vector3d(-nrm) : nrm;
  return p;
}

double PlaneMoments::rms_error() const {
  if (n_ <= 0) return 0;
  return std::sqrt(std::max(0.0, spreads()(0)));
}

Eigen::Vector3d PlaneMoments::spreads() const {
  if (n_ <= 0) return Eigen::Vector3d::Zero();
  // Closed form (the sweeps take one per candidate split): as exact as the iterative solver
  // for the spreads a sweep compares, several times faster.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(covariance(), Eigen::EigenvaluesOnly);
  return eig.eigenvalues().cwiseMax(0.0);
}

PolyMoments::PolyMoments(const Frame& frame, double scale) : frame_(frame), scale_(scale > 0 ? scale : 1.0) {}

namespace {
Eigen::Matrix<double, 6, 1> basis(const Eigen::Vector3d& l) {
  Eigen::Matrix<double, 6, 1> b;
  b << 1, l.x(), l.y(), l.x() * l.x(), l.x() * l.y(), l.y() * l.y();
  return b;
}
}  // namespace

void PolyMoments::add(const Eigen::Vector3d& p) {
  const Eigen::Vector3d l = frame_.to_local(p) / scale_;
  const Vector6 b = basis(l);
  n_ += 1;
  detail::add_outer_lower(bb_, b);
  wb_ += l.z() * b;
  ww_ += l.z() * l.z();
}

void PolyMoments::remove(const Eigen::Vector3d& p) {
  const Eigen::Vector3d l = frame_.to_local(p) / scale_;
  const Vector6 b = basis(l);
  n_ -= 1;
  detail::add_outer_lower(bb_, b, -1.0);
  wb_ -= l.z() * b;
  ww_ -= l.z() * l.z();
}

PolyMoments& PolyMoments::operator+=(const PolyMoments& o) {
  n_ += o.n_, bb_ += o.bb_, wb_ += o.wb_, ww_ += o.ww_;
  return *this;
}

PolyMoments& PolyMoments::operator-=(const PolyMoments& o) {
  n_ -= o.n_, bb_ -= o.bb_, wb_ -= o.wb_, ww_ -= o.ww_;
  return *this;
}

PolyMoments::Vector6 PolyMoments::solve() const {
  const Matrix6 a = bb_.selfadjointView<Eigen::Lower>();
  // Fast path: a well-conditioned system (the common case in a sweep) by LDLT; otherwise the
  // pseudo-inverse of thesis eq. 4.13.
  const Eigen::LDLT<Matrix6> ldlt(a);
  if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
    const auto d = ldlt.vectorD();
    if (d.minCoeff() > 1e-10 * d.maxCoeff()) return ldlt.solve(wb_);
  }
  return detail::solve_psd_pinv<6>(a, wb_, 1e-13);
}

PolyProxy PolyMoments::fit() const {
  const Vector6 c = solve();
  PolyProxy p;
  p.frame = frame_;
  const double s = scale_;
  p.coeffs = {s * c(0), c(1), c(2), c(3) / s, c(4) / s, c(5) / s};
  return p;
}

double PolyMoments::rms_error() const {
  if (n_ <= 0) return 0;
  // The sweeps take one per candidate split: the residual straight from one factorization of
  // the augmented moments, unless a pivot says they are nearly singular.
  Eigen::Matrix<double, 7, 7> gram;
  gram.topLeftCorner<6, 6>() = bb_;
  gram.block<1, 6>(6, 0) = wb_.transpose();
  gram(6, 6) = ww_;
  if (const auto f = detail::GramSolver<7>::factor(gram, 1e-10))
    return scale_ * std::sqrt(f->residual_sum_of_squares() / n_);
  const Vector6 c = solve();
  const Matrix6 a = bb_.selfadjointView<Eigen::Lower>();
  // Σ (w − Bᵀc)² = Σw² − 2 cᵀΣwB + cᵀ(ΣBBᵀ)c, in scaled units.
  const double ss = ww_ - 2 * c.dot(wb_) + c.dot(a * c);
  return scale_ * std::sqrt(std::max(0.0, ss) / n_);
}

}  // namespace clustersurf
