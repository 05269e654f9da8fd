// The weighted quadratic fits of the input points around a mesh vertex.

#include "mesh/vertex_fit.hpp"

#include <clustersurf/cluster/noise.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace clustersurf::detail {

namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
/// The monomials uᵃvᵇ of degree up to 4: 1, u, v, u², uv, v², u³, u²v, uv², v³, u⁴, u³v, u²v², uv³, v⁴.
using Moments15 = Eigen::Matrix<double, 15, 1>;

/// Σ m mᵀ over the quadratic's monomials m = (1, u, v, u², uv, v²) from the sums of the monomials
/// of degree up to 4 (Moments15's order).
Matrix6 normal_matrix(const Moments15& s) {
  // The index in Moments15 of the product of monomials i and j of m.
  static constexpr int kProduct[6][6] = {{0, 1, 2, 3, 4, 5},    {1, 3, 4, 6, 7, 8},    {2, 4, 5, 7, 8, 9},
                                         {3, 6, 7, 10, 11, 12}, {4, 7, 8, 11, 12, 13}, {5, 8, 9, 12, 13, 14}};
  Matrix6 a;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) a(i, j) = s(kProduct[i][j]);
  return a;
}

/// A fit whose normal equations have a pivot below this share of the largest is undetermined
/// (the points on a line, or too few around the vertex).
constexpr double kMinPivot = 1e-8;

}  // namespace

LocalFit fit_at(const Eigen::Vector3d& x, const Eigen::Vector3d& normal, const Points& data,
                std::span<const Neighbor> near, const ClusterTree& tree, bool with_residual_noise) {
  LocalFit out;
  if (near.size() < 6 || !(normal.squaredNorm() > 0)) return out;
  const double h2 = near.back().distance_squared * (1 + 1e-4);
  if (!(h2 > 0)) return out;
  const double h = std::sqrt(h2);
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d t1 = n.unitOrthogonal();
  const Eigen::Vector3d t2 = n.cross(t1);
  // The normal equations' entries are sums of the monomials uᵃvᵇ of degree up to 4, weighted
  // by w (A = Σw m mᵀ) and by w² (B = Σw² m mᵀ): 15 of each instead of 21 products.
  Moments15 wm = Moments15::Zero(), w2m = Moments15::Zero();
  Vector6 rhs = Vector6::Zero();  // Σw z m
  double zz = 0;                  // Σw z²
  for (const Neighbor& nb : near) {
    const Eigen::Vector3d d = (data.row(nb.index).transpose() - x) / h;
    const double s = 1 - nb.distance_squared / h2;
    const double w = s * s * s;
    const double u = d.dot(t1), v = d.dot(t2), z = d.dot(n);
    const double uu = u * u, uv = u * v, vv = v * v;
    Moments15 m;
    m << 1, u, v, uu, uv, vv, uu * u, uu * v, u * vv, vv * v, uu * uu, uu * uv, uu * vv, uv * vv, vv * vv;
    wm += w * m;
    w2m += (w * w) * m;
    rhs += (w * z) * m.head<6>();
    zz += w * z * z;
  }
  const Matrix6 a = normal_matrix(wm), b = normal_matrix(w2m);
  const double weight = wm(0), weight2 = w2m(0);  // Σw, Σw²
  const Eigen::LDLT<Matrix6> solver(a);
  const Vector6 pivots = solver.vectorD().cwiseAbs();
  if (solver.info() != Eigen::Success || !(pivots.minCoeff() > kMinPivot * pivots.maxCoeff())) return out;
  // A⁻¹ whole where its trace against B is wanted, else only the columns the height needs.
  const Matrix6 inverse = with_residual_noise ? Matrix6(solver.solve(Matrix6::Identity())) : Matrix6();
  Eigen::Matrix<double, 6, 2> solved;  // A⁻¹ (Σw z m, e₀)
  if (with_residual_noise) {
    solved << inverse * rhs, inverse.col(0);
  } else {
    solved << rhs, Vector6::Unit(0);
    solved = solver.solve(solved).eval();
  }
  const Vector6 c = solved.col(0);
  // Σw r² of the least-squares solution: Σw z² − cᵀ(Σw z m).
  const double residual = std::max(0.0, zz - c.dot(rhs));
  if (!(weight > 0) || !(h * std::sqrt(residual / weight) <= cluster_error_threshold(tree, weight * weight / weight2)))
    return out;
  // The height's weights on the rows are w gᵀm with g = A⁻¹ e₀: its variance per unit variance
  // of the noise is Σ w² (gᵀm)² = gᵀBg.
  const Vector6 g = solved.col(1);
  const double unit_variance = g.dot(b * g);
  out.move = h * c(0);
  out.unit_variance = unit_variance;
  if (with_residual_noise) {
    const double trace = inverse.cwiseProduct(b).sum();  // tr(A⁻¹B), both symmetric
    out.dof = std::max(0.0, weight - trace);             // Σw − tr(A⁻¹B)
    out.residual_variance = out.dof > 0 ? h * h * residual / out.dof : 0.0;
  }
  out.radius = h;
  out.valid = std::isfinite(out.move) && std::isfinite(out.unit_variance) && std::abs(out.move) < h;
  if (!out.valid) out.move = out.unit_variance = 0;
  return out;
}

double relief_free_noise(const LocalFit& narrow, const LocalFit& wide) {
  const double q = wide.valid ? (wide.radius * wide.radius) / (narrow.radius * narrow.radius) : 0.0;
  if (!(wide.dof > 0) || !(q > 1)) return narrow.residual_variance;
  return std::max(0.0, (q * narrow.residual_variance - wide.residual_variance) / (q - 1));
}

LocalFit widest_consistent_fit(const Eigen::Vector3d& x, const Eigen::Vector3d& normal, const Points& data,
                               std::span<const Neighbor> near, std::size_t points, const ClusterTree& tree) {
  LocalFit best = fit_at(x, normal, data, near.first(std::min(points, near.size())), tree, true);
  if (!best.valid) return best;
  const LocalFit narrow = best;
  double noise = narrow.residual_variance;
  double low = -std::numeric_limits<double>::infinity(), high = std::numeric_limits<double>::infinity();
  const auto meet = [&](const LocalFit& f) {
    const double margin = kNoiseMargin * std::sqrt(tree.noise_sigma * tree.noise_sigma * f.unit_variance);
    low = std::max(low, f.move - margin), high = std::min(high, f.move + margin);
    return low <= high;
  };
  meet(best);
  for (int width = 1; width < kFitWidths && (points << width) <= near.size(); ++width) {
    const LocalFit wider = fit_at(x, normal, data, near.first(points << width), tree, width == 1);
    if (width == 1) noise = relief_free_noise(narrow, wider);
    if (!wider.valid || !meet(wider)) break;
    best = wider;
  }
  best.residual_variance = noise;
  best.dof = narrow.dof;
  return best;
}

}  // namespace clustersurf::detail
