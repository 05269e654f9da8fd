#pragma once
// Running moment sums that make plane and polynomial fits O(1) when points are added to or
// removed from a cluster (the split-plane sweeps, thesis 3.2.3).

#include <clustersurf/proxy/proxy.hpp>

#include <Eigen/Core>

namespace clustersurf {

/// Sums Σ1, Σp, Σppᵀ of points taken relative to a fixed `origin` (for conditioning).
/// fit() equals the PCA plane of the same points.
class PlaneMoments {
 public:
  explicit PlaneMoments(const Eigen::Vector3d& origin = Eigen::Vector3d::Zero()) : origin_(origin) {}

  void add(const Eigen::Vector3d& p);
  void remove(const Eigen::Vector3d& p);
  PlaneMoments& operator+=(const PlaneMoments& o);
  PlaneMoments& operator-=(const PlaneMoments& o);

  double count() const noexcept { return n_; }
  /// The least-squares plane (normal: eigenvector of the smallest covariance eigenvalue).
  PlaneProxy fit() const;
  /// RMS point-to-plane distance of the least-squares plane, sqrt(λ_min).
  double rms_error() const;
  /// Eigenvalues of the covariance, ascending: the squared spreads along the principal axes.
  Eigen::Vector3d spreads() const;

 private:
  Eigen::Matrix3d covariance() const;
  Eigen::Vector3d origin_;
  double n_ = 0;
  Eigen::Vector3d s_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d q_ = Eigen::Matrix3d::Zero();
};

/// Monomial moments Σ B Bᵀ, Σ w B, Σ w² of points in a fixed local frame, with
/// B(u, v) = [1, u, v, u², uv, v²] (coordinates divided by `scale` for conditioning).
/// fit() equals the least-squares polynomial of the same points in that frame.
class PolyMoments {
 public:
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;

  PolyMoments(const Frame& frame, double scale);

  void add(const Eigen::Vector3d& p);
  void remove(const Eigen::Vector3d& p);
  PolyMoments& operator+=(const PolyMoments& o);
  PolyMoments& operator-=(const PolyMoments& o);

  double count() const noexcept { return n_; }
  /// The least-squares polynomial in the frame (pseudo-inverse when rank-deficient).
  PolyProxy fit() const;
  /// RMS of the vertical residual w − f(u, v) of the least-squares fit (an upper bound of the
  /// RMS of Q): fit()'s, up to rounding, but on nearly singular moments, where fit() drops the
  /// directions the pseudo-inverse cannot resolve and this keeps the full least-squares residual.
  double rms_error() const;

 private:
  Vector6 solve() const;  // coefficients in scaled coordinates
  Frame frame_;
  double scale_;
  double n_ = 0;
  Matrix6 bb_ = Matrix6::Zero();
  Vector6 wb_ = Vector6::Zero();
  double ww_ = 0;
};

}  // namespace clustersurf
