// Proxies: fits recover known surfaces, Q is a signed distance near the surface, gradients
// match finite differences, ray hits lie on the surface, degenerate fits stay finite.

#include <clustersurf/proxy/proxy.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

Points heightfield(int n, double noise, std::uint64_t seed) {
  // w = 0.3 + 0.2u − 0.1v + 0.5u² − 0.3uv + 0.25v² over [-1,1]², in a rotated, shifted frame.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> g(0, noise);
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  Points p(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = u(rng), b = u(rng);
    const double w = 0.3 + 0.2 * a - 0.1 * b + 0.5 * a * a - 0.3 * a * b + 0.25 * b * b + (noise > 0 ? g(rng) : 0);
    p.row(i) = (rot * Eigen::Vector3d(a, b, w) + Eigen::Vector3d(5, -2, 1)).transpose();
  }
  return p;
}

Eigen::Vector3d finite_difference(const Proxy& p, const Eigen::Vector3d& x, double h) {
  Eigen::Vector3d g;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e(k) = h;
    g(k) = (p.value(x + e) - p.value(x - e)) / (2 * h);
  }
  return g;
}

}  // namespace

TEST(Proxy, PolyFitReproducesQuadraticExactly) {
  const Points p = heightfield(400, 0.0, 1);
  const auto idx = test::all_rows(p.rows());
  // In the generating frame the height field is exactly quadratic.
  Frame truth;
  truth.origin = Eigen::Vector3d(5, -2, 1);
  truth.axes = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Proxy exact = fit_poly_in_frame(truth, p, idx);
  EXPECT_LT(proxy_error(exact, p, idx).max, 1e-9);
  const auto& c = std::get<PolyProxy>(exact.variant()).coeffs;
  EXPECT_NEAR(c[3], 0.5, 1e-9);
  EXPECT_NEAR(c[4], -0.3, 1e-9);
  // In its own PCA frame the fit is close, and far better than a plane.
  const double poly = proxy_error(fit_proxy(ProxyKind::Poly, p, idx), p, idx).rms;
  const double plane = proxy_error(fit_proxy(ProxyKind::Plane, p, idx), p, idx).rms;
  EXPECT_LT(poly * 5, plane);
  EXPECT_GT(plane, 0.05);
}

TEST(Proxy, HermiteFitFollowsNormalsOfEitherSign) {
  // Noisy heights, exact normals of the noise-free height field: the normals pin the slopes,
  // so the curvature comes out several times closer than from the positions alone.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> g(0, 0.05);
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const int n = 60;
  Points p(n, 3), normals(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = u(rng), b = u(rng);
    const double w = 0.3 + 0.2 * a - 0.1 * b + 0.5 * a * a - 0.3 * a * b + 0.25 * b * b;
    const Eigen::Vector3d slope(0.2 + a - 0.3 * b, -0.1 - 0.3 * a + 0.5 * b, -1);
    p.row(i) = (rot * Eigen::Vector3d(a, b, w + g(rng)) + Eigen::Vector3d(5, -2, 1)).transpose();
    normals.row(i) = (rot * (i % 2 ? -slope : slope).normalized()).transpose();
  }
  Frame truth;
  truth.origin = Eigen::Vector3d(5, -2, 1);
  truth.axes = rot;
  const auto idx = test::all_rows(p.rows());
  const std::vector<double> ones(idx.size(), 1.0);
  const auto curvature_error = [](const PolyProxy& f) {
    return std::hypot(f.coeffs[3] - 0.5, f.coeffs[4] + 0.3, f.coeffs[5] - 0.25);
  };
  const PolyProxy positions = fit_poly_in_frame(truth, p, idx, ones);
  const PolyProxy hermite = fit_poly_in_frame(truth, p, idx, ones, &normals, 1.0);
  EXPECT_LT(curvature_error(hermite) * 4, curvature_error(positions));
  EXPECT_LT(curvature_error(hermite), 0.02);
  // A normal's sign does not matter; a zero weight is the positions' fit.
  Points flipped = -normals;
  const PolyProxy hermite_flipped = fit_poly_in_frame(truth, p, idx, ones, &flipped, 1.0);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(hermite_flipped.coeffs[k], hermite.coeffs[k], 1e-12);
  EXPECT_EQ(fit_poly_in_frame(truth, p, idx, ones, &normals, 0.0).coeffs, positions.coeffs);
}

TEST(Proxy, QuadricFitsSphereExactly) {
  const PointCloud s = test::sample_sphere(500, 2.0, Eigen::Vector3d(1, 2, 3));
  const auto idx = test::all_rows(s.positions.rows());
  const Proxy q = fit_proxy(ProxyKind::Quadric, s.positions, idx);
  EXPECT_LT(proxy_error(q, s.positions, idx).max, 1e-8);
  // Q approximates the signed distance off the surface too (within 5 % at 0.1 R).
  const Eigen::Vector3d out = Eigen::Vector3d(1, 2, 3) + 2.2 * Eigen::Vector3d(0, 0, 1);
  EXPECT_NEAR(std::abs(q.value(out)), 0.2, 0.01);
}

TEST(Proxy, PlaneFitOfNoisyPlaneHasRmsNearNoise) {
  PointCloud c = test::sample_plane(40, 40);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0, 0.01);
  for (Eigen::Index i = 0; i < c.size(); ++i) c.positions(i, 2) += g(rng);
  const auto idx = test::all_rows(c.positions.rows());
  const Proxy plane = fit_proxy(ProxyKind::Plane, c.positions, idx);
  EXPECT_NEAR(proxy_error(plane, c.positions, idx).rms, 0.01, 0.001);
  EXPECT_GT(std::abs(plane.normal().z()), 0.999);
}

TEST(Proxy, GradientsMatchFiniteDifferences) {
  const Points hp = heightfield(300, 0.01, 2);
  const PointCloud sp = test::sample_sphere(300, 1.0);
  for (ProxyKind kind : {ProxyKind::Plane, ProxyKind::Poly, ProxyKind::Quadric}) {
    const Points& pts = kind == ProxyKind::Quadric ? sp.positions : hp;
    const Proxy p = fit_proxy(kind, pts, test::all_rows(pts.rows()));
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-0.3, 0.3);
    for (int t = 0; t < 50; ++t) {
      const Eigen::Vector3d x = pts.row(t * 5).transpose() + Eigen::Vector3d(u(rng), u(rng), u(rng));
      const Eigen::Vector3d fd = finite_difference(p, x, 1e-6);
      EXPECT_LT((p.gradient(x) - fd).norm(), 1e-5 * std::max(1.0, fd.norm())) << to_string(kind);
    }
  }
}

TEST(Proxy, ValueAndGradientGivesValuesValue) {
  const Points hp = heightfield(300, 0.01, 2);
  const PointCloud sp = test::sample_sphere(300, 1.0);
  const PlaneProxy a{Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0.6, 0.8)};
  const PlaneProxy b{Eigen::Vector3d(0.2, 0, 0), Eigen::Vector3d(0.8, 0, 0.6)};
  std::vector<Proxy> proxies = {PointProxy{Eigen::Vector3d(0.1, 0.2, 0.3)}, CreaseProxy{a, b, true},
                                CreaseProxy{a, b, false}};
  for (ProxyKind kind : {ProxyKind::Plane, ProxyKind::Poly, ProxyKind::Quadric})
    proxies.push_back(fit_proxy(kind, kind == ProxyKind::Quadric ? sp.positions : hp,
                                test::all_rows((kind == ProxyKind::Quadric ? sp.positions : hp).rows())));
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-2, 2);
  for (const Proxy& p : proxies)
    for (int t = 0; t < 200; ++t) {
      const Eigen::Vector3d x(u(rng), u(rng), u(rng));
      EXPECT_EQ(p.value_and_gradient(x).first, p.value(x)) << to_string(p.kind());
    }
}

TEST(Proxy, RayIntersectionLiesOnTheZeroSet) {
  const Points hp = heightfield(300, 0.0, 4);
  const PointCloud sp = test::sample_sphere(300, 1.0);
  for (ProxyKind kind : {ProxyKind::Plane, ProxyKind::Poly, ProxyKind::Quadric}) {
    const Points& pts = kind == ProxyKind::Quadric ? sp.positions : hp;
    const Proxy p = fit_proxy(kind, pts, test::all_rows(pts.rows()));
    int hits = 0;
    for (int t = 0; t < 40; ++t) {
      const Eigen::Vector3d target = pts.row(t * 7).transpose();
      const Eigen::Vector3d origin = target + 3.0 * p.gradient(target).normalized() + Eigen::Vector3d(0.1, -0.05, 0.02);
      const Ray ray{origin, (target - origin).normalized()};
      const auto t_hit = p.intersect(ray, 0, 100);
      if (!t_hit) continue;
      ++hits;
      EXPECT_LT(std::abs(p.value(ray.origin + *t_hit * ray.direction)), 1e-9) << to_string(kind);
    }
    EXPECT_GT(hits, 30) << to_string(kind);
  }
}

TEST(Proxy, FlipNegatesValueKeepsZeroSet) {
  const Points hp = heightfield(100, 0.01, 6);
  for (ProxyKind kind : {ProxyKind::Plane, ProxyKind::Poly, ProxyKind::Quadric}) {
    const Proxy p = fit_proxy(kind, hp, test::all_rows(hp.rows()));
    Proxy f = p;
    f.flip();
    for (int t = 0; t < 20; ++t) {
      const Eigen::Vector3d x = hp.row(t).transpose() + Eigen::Vector3d(0.1, 0.2, -0.1) * (t % 3);
      EXPECT_NEAR(f.value(x), -p.value(x), 1e-12) << to_string(kind);
      EXPECT_LT((f.gradient(x) + p.gradient(x)).norm(), 1e-9) << to_string(kind);
    }
    EXPECT_LT((f.normal() + p.normal()).norm(), 1e-9) << to_string(kind);
  }
}

TEST(Proxy, RankDeficientFitsStayFinite) {
  // Collinear points, a single point, fewer points than polynomial coefficients, duplicates.
  Points line(10, 3);
  for (int i = 0; i < 10; ++i) line.row(i) << i, 2 * i, -i;
  Points one(1, 3);
  one << 1, 2, 3;
  Points few(4, 3);
  few << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.5;
  Points dup = Points::Constant(8, 3, 2.5);
  for (const Points* pts : {&line, &one, &few, &dup}) {
    for (ProxyKind kind : {ProxyKind::Point, ProxyKind::Plane, ProxyKind::Poly, ProxyKind::Quadric}) {
      const Proxy p = fit_proxy(kind, *pts, test::all_rows(pts->rows()));
      const ProxyError e = proxy_error(p, *pts, test::all_rows(pts->rows()));
      EXPECT_TRUE(std::isfinite(e.rms) && std::isfinite(e.max)) << to_string(kind);
      EXPECT_TRUE(std::isfinite(p.value(Eigen::Vector3d(0.3, 0.2, 0.1)))) << to_string(kind);
      EXPECT_TRUE(p.gradient(Eigen::Vector3d(0.3, 0.2, 0.1)).allFinite()) << to_string(kind);
    }
  }
  // Fewer than 6 points on a height field: the poly interpolates them (minimum-norm solution).
  const Proxy p = fit_proxy(ProxyKind::Poly, few, test::all_rows(few.rows()));
  EXPECT_LT(proxy_error(p, few, test::all_rows(few.rows())).max, 1e-9);
}

// A crease: a roof (convex, max) and a valley (concave, min) of two planes meeting on the y axis.
TEST(Proxy, CreaseIsTheMaxOrMinOfItsPlanes) {
  const Eigen::Vector3d na = Eigen::Vector3d(-1, 0, 1).normalized(), nb = Eigen::Vector3d(1, 0, 1).normalized();
  const CreaseProxy roof{PlaneProxy{Eigen::Vector3d::Zero(), na}, PlaneProxy{Eigen::Vector3d::Zero(), nb}, true};
  const Proxy p(roof);
  EXPECT_EQ(p.kind(), ProxyKind::Crease);
  EXPECT_STREQ(to_string(p.kind()), "crease");
  // On the roof's faces (z = −|x|) Q = 0; above the ridge positive, below negative.
  for (double x : {-0.7, -0.2, 0.0, 0.3, 0.9}) EXPECT_NEAR(p.value(Eigen::Vector3d(x, 0.4, -std::abs(x))), 0, 1e-12);
  EXPECT_GT(p.value(Eigen::Vector3d(0, 0, 0.1)), 0);
  EXPECT_LT(p.value(Eigen::Vector3d(0, 0, -0.1)), 0);
  EXPECT_LT((p.gradient(Eigen::Vector3d(-0.5, 0, 0)) - na).norm(), 1e-12);  // plane a decides for x < 0
  EXPECT_LT((p.gradient(Eigen::Vector3d(0.5, 0, 0)) - nb).norm(), 1e-12);
  EXPECT_LT((p.normal() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  // A ray down onto each face hits the face, not the other plane's extension.
  for (double x : {-0.6, 0.25}) {
    const Ray ray{Eigen::Vector3d(x, 0, 2), -Eigen::Vector3d::UnitZ()};
    const auto t = p.intersect(ray, 0, 10);
    ASSERT_TRUE(t.has_value());
    EXPECT_NEAR(*t, 2 + std::abs(x), 1e-12);
  }
  // Flipping negates Q and turns the convex max into a concave min with the same zero set.
  Proxy f = p;
  f.flip();
  EXPECT_FALSE(std::get<CreaseProxy>(f.variant()).convex);
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(0.3, 1, 0.2), Eigen::Vector3d(-0.4, 0, -0.9)}) {
    EXPECT_NEAR(f.value(x), -p.value(x), 1e-12);
    EXPECT_LT((f.gradient(x) + p.gradient(x)).norm(), 1e-12);
  }
  const auto t = f.intersect(Ray{Eigen::Vector3d(0.25, 0, 2), -Eigen::Vector3d::UnitZ()}, 0, 10);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 2.25, 1e-12);
}
