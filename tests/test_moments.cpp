// Moment sums: fits from incrementally added/removed moments equal direct fits.

#include <clustersurf/proxy/moments.hpp>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <numeric>
#include <random>

using namespace clustersurf;

namespace {

Points curved_patch(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> g(0, 0.02);
  Points p(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = u(rng), b = u(rng);
    p.row(i) << 10 + a, -3 + b, 2 + 0.4 * a * a - 0.2 * a * b + 0.3 * b * b + 0.1 * a + g(rng);
  }
  return p;
}

double relative_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / std::max(1e-300, std::max(a.norm(), b.norm()));
}

}  // namespace

TEST(Moments, PolyIncrementalEqualsDirectFit) {
  const Points p = curved_patch(600, 1);
  std::vector<std::uint32_t> all(600);
  std::iota(all.begin(), all.end(), 0u);
  const Frame frame = pca_frame(p, all);
  // Add everything, then remove the second half: the moments must describe the first half.
  PolyMoments m(frame, 1.3);
  for (int i = 0; i < 600; ++i) m.add(p.row(i).transpose());
  for (int i = 300; i < 600; ++i) m.remove(p.row(i).transpose());
  const std::vector<std::uint32_t> half(all.begin(), all.begin() + 300);
  const PolyProxy direct = fit_poly_in_frame(frame, p, half);
  const PolyProxy incremental = m.fit();
  const Eigen::Map<const Eigen::VectorXd> a(direct.coeffs.data(), 6), b(incremental.coeffs.data(), 6);
  EXPECT_LT(relative_difference(a, b), 1e-9);
  // And its residual equals the direct one.
  double ss = 0;
  for (auto i : half) {
    const Eigen::Vector3d l = frame.to_local(p.row(i).transpose());
    const double f = direct.height(l.x(), l.y());
    ss += (l.z() - f) * (l.z() - f);
  }
  EXPECT_NEAR(m.rms_error(), std::sqrt(ss / 300), 1e-9 * std::sqrt(ss / 300));
}

TEST(Moments, PolySplitSumsMatch) {
  const Points p = curved_patch(200, 2);
  std::vector<std::uint32_t> all(200);
  std::iota(all.begin(), all.end(), 0u);
  const Frame frame = pca_frame(p, all);
  PolyMoments total(frame, 1.0), left(frame, 1.0);
  for (int i = 0; i < 200; ++i) total.add(p.row(i).transpose());
  for (int i = 0; i < 80; ++i) left.add(p.row(i).transpose());
  PolyMoments right = total;
  right -= left;
  const std::vector<std::uint32_t> tail(all.begin() + 80, all.end());
  const PolyProxy direct = fit_poly_in_frame(frame, p, tail);
  const PolyProxy fitted = right.fit();
  const Eigen::Map<const Eigen::VectorXd> a(direct.coeffs.data(), 6), b(fitted.coeffs.data(), 6);
  EXPECT_LT(relative_difference(a, b), 1e-9);
}

TEST(Moments, PlaneIncrementalEqualsDirectFit) {
  const Points p = curved_patch(500, 3);
  PlaneMoments m(Eigen::Vector3d(10, -3, 2));
  for (int i = 0; i < 500; ++i) m.add(p.row(i).transpose());
  for (int i = 0; i < 200; ++i) m.remove(p.row(i).transpose());
  std::vector<std::uint32_t> rest(300);
  std::iota(rest.begin(), rest.end(), 200u);
  const Proxy direct = fit_proxy(ProxyKind::Plane, p, rest);
  const PlaneProxy& d = std::get<PlaneProxy>(direct.variant());
  const PlaneProxy inc = m.fit();
  EXPECT_LT((d.point - inc.point).norm(), 1e-9 * d.point.norm());
  EXPECT_LT(std::min((d.normal - inc.normal).norm(), (d.normal + inc.normal).norm()), 1e-9);
  EXPECT_NEAR(m.rms_error(), proxy_error(direct, p, rest).rms, 1e-9 * proxy_error(direct, p, rest).rms);
}

TEST(Moments, RankDeficientMomentsGiveFiniteFit) {
  Frame frame;
  PolyMoments m(frame, 1.0);
  for (int i = 0; i < 5; ++i) m.add(Eigen::Vector3d(i, 0, 0.5 * i));  // collinear, 5 points
  const PolyProxy p = m.fit();
  for (double c : p.coeffs) EXPECT_TRUE(std::isfinite(c));
  EXPECT_LT(m.rms_error(), 1e-9);  // a line is fitted exactly
}

TEST(Moments, SpreadsOfAThinFlatClusterMatchPca) {
  // A flat, clean scan patch: its thickness is 1e-6 of its width, the regime of the sweep's
  // smallest spreads, which must stay the squared RMS of its PCA plane (not rounding noise).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> g(0, 1e-6);
  Points p(400, 3);
  const Eigen::Vector3d normal = Eigen::Vector3d(1, 2, 3).normalized();
  const Eigen::Vector3d t1 = normal.unitOrthogonal(), t2 = normal.cross(t1);
  for (int i = 0; i < 400; ++i)
    p.row(i) = (Eigen::Vector3d(5, 1, -2) + u(rng) * t1 + u(rng) * t2 + g(rng) * normal).transpose();
  PlaneMoments m(Eigen::Vector3d(5.1, 0.9, -2));
  for (int i = 0; i < 400; ++i) m.add(p.row(i).transpose());
  std::vector<std::uint32_t> all(400);
  std::iota(all.begin(), all.end(), 0u);
  const double pca_rms = proxy_error(fit_proxy(ProxyKind::Plane, p, all), p, all).rms;
  EXPECT_NEAR(m.rms_error(), pca_rms, 1e-3 * pca_rms);
  const Eigen::Vector3d s = m.spreads();
  EXPECT_NEAR(s(1), 1.0 / 3, 0.05);  // uniform on [-1, 1]: variance 1/3 along both tangents
  EXPECT_NEAR(s(2), 1.0 / 3, 0.05);
}
