// Evaluation of the proxies: value, gradient, ray intersection, flipping.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/proxy/proxy.hpp>

#include "core/overloaded.hpp"
#include "proxy/linear_algebra.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace clustersurf {

namespace {

/// Height-field pieces of a polynomial at local (u, v): f, fu, fv.
struct PolyLocal {
  double f, fu, fv;
};
PolyLocal poly_at(const PolyProxy& p, double u, double v) {
  const auto& c = p.coeffs;
  return {p.height(u, v), c[1] + 2 * c[3] * u + c[4] * v, c[2] + c[4] * u + 2 * c[5] * v};
}

Eigen::Matrix3d quadric_hessian(const std::array<double, 10>& c) {
  Eigen::Matrix3d h;
  h << 2 * c[0], c[3], c[4], c[3], 2 * c[1], c[5], c[4], c[5], 2 * c[2];
  return h;
}

double quadric_q(const std::array<double, 10>& c, const Eigen::Vector3d& y) {
  return c[0] * y.x() * y.x() + c[1] * y.y() * y.y() + c[2] * y.z() * y.z() + c[3] * y.x() * y.y() +
         c[4] * y.x() * y.z() + c[5] * y.y() * y.z() + c[6] * y.x() + c[7] * y.y() + c[8] * y.z() + c[9];
}

Eigen::Vector3d quadric_grad(const std::array<double, 10>& c, const Eigen::Vector3d& y) {
  return quadric_hessian(c) * y + Eigen::Vector3d(c[6], c[7], c[8]);
}

constexpr double kTinyGradient = 1e-12;

}  // namespace

const char* to_string(ProxyKind kind) {
  switch (kind) {
    case ProxyKind::Point:
      return "point";
    case ProxyKind::Plane:
      return "plane";
    case ProxyKind::Poly:
      return "poly";
    case ProxyKind::Quadric:
      return "quadric";
    case ProxyKind::Crease:
      return "crease";
  }
  return "unknown";
}

ProxyKind parse_proxy_kind(std::string_view text) {
  for (ProxyKind kind : {ProxyKind::Plane, ProxyKind::Poly, ProxyKind::Quadric})
    if (text == to_string(kind)) return kind;
  throw OptionError("proxy must be plane, poly or quadric, not \"" + std::string(text) + "\"");
}

double Proxy::value(const Eigen::Vector3d& x) const {
  return std::visit(detail::Overloaded{
                        [&](const PointProxy& p) { return (x - p.center).norm(); },
                        [&](const PlaneProxy& p) { return p.normal.dot(x - p.point); },
                        [&](const PolyProxy& p) {
                          const Eigen::Vector3d l = p.frame.to_local(x);
                          const PolyLocal f = poly_at(p, l.x(), l.y());
                          return (l.z() - f.f) / std::sqrt(1 + f.fu * f.fu + f.fv * f.fv);
                        },
                        [&](const QuadricProxy& p) {
                          const Eigen::Vector3d y = (x - p.center) / p.scale;
                          const double g = std::max(quadric_grad(p.coeffs, y).norm(), kTinyGradient);
                          return p.scale * quadric_q(p.coeffs, y) / g;
                        },
                        [&](const CreaseProxy& p) {
                          const double qa = p.a.normal.dot(x - p.a.point), qb = p.b.normal.dot(x - p.b.point);
                          return p.convex ? std::max(qa, qb) : std::min(qa, qb);
                        },
                    },
                    v_);
}

std::pair<double, Eigen::Vector3d> Proxy::value_and_gradient(const Eigen::Vector3d& x) const {
  using Out = std::pair<double, Eigen::Vector3d>;
  return std::visit(detail::Overloaded{
                        [&](const PointProxy& p) -> Out {
                          const Eigen::Vector3d d = x - p.center;
                          const double n = d.norm();
                          return {n, n > 0 ? Eigen::Vector3d(d / n) : Eigen::Vector3d::Zero()};
                        },
                        [&](const PlaneProxy& p) -> Out {
                          return {p.normal.dot(x - p.point), p.normal};
                        },
                        [&](const PolyProxy& p) -> Out {
                          const Eigen::Vector3d l = p.frame.to_local(x);
                          const auto& c = p.coeffs;
                          const PolyLocal f = poly_at(p, l.x(), l.y());
                          const double d2 = 1 + f.fu * f.fu + f.fv * f.fv;
                          const double d = std::sqrt(d2);
                          const double r = l.z() - f.f;
                          // d(D)/du = (fu fuu + fv fuv) / D with fuu = 2c3, fuv = c4, fvv = 2c5.
                          const double ddu = (f.fu * 2 * c[3] + f.fv * c[4]) / d;
                          const double ddv = (f.fu * c[4] + f.fv * 2 * c[5]) / d;
                          const Eigen::Vector3d local(-f.fu / d - r * ddu / d2, -f.fv / d - r * ddv / d2, 1 / d);
                          return {r / d, p.frame.axes * local};
                        },
                        [&](const QuadricProxy& p) -> Out {
                          const Eigen::Vector3d y = (x - p.center) / p.scale;
                          const Eigen::Vector3d g = quadric_grad(p.coeffs, y);
                          const double gn = std::max(g.norm(), kTinyGradient);
                          const double q = quadric_q(p.coeffs, y);
                          return {p.scale * q / gn, g / gn - q * (quadric_hessian(p.coeffs) * g) / (gn * gn * gn)};
                        },
                        [&](const CreaseProxy& p) -> Out {
                          const double qa = p.a.normal.dot(x - p.a.point), qb = p.b.normal.dot(x - p.b.point);
                          return {p.convex ? std::max(qa, qb) : std::min(qa, qb),
                                  (p.convex ? qa >= qb : qa <= qb) ? p.a.normal : p.b.normal};
                        },
                    },
                    v_);
}

Eigen::Vector3d Proxy::gradient(const Eigen::Vector3d& x) const { return value_and_gradient(x).second; }

std::optional<double> Proxy::intersect(const Ray& ray, double t_min, double t_max) const {
  return std::visit(detail::Overloaded{
                        [&](const PointProxy&) -> std::optional<double> { return std::nullopt; },
                        [&](const PlaneProxy& p) -> std::optional<double> {
                          return detail::smallest_root(0, p.normal.dot(ray.direction),
                                                       p.normal.dot(ray.origin - p.point), t_min, t_max);
                        },
                        [&](const PolyProxy& p) -> std::optional<double> {
                          const Eigen::Vector3d o = p.frame.to_local(ray.origin);
                          const Eigen::Vector3d d = p.frame.axes.transpose() * ray.direction;
                          const auto& c = p.coeffs;
                          const double a = -(c[3] * d.x() * d.x() + c[4] * d.x() * d.y() + c[5] * d.y() * d.y());
                          const double b = d.z() - (c[1] * d.x() + c[2] * d.y() + 2 * c[3] * o.x() * d.x() +
                                                    c[4] * (o.x() * d.y() + o.y() * d.x()) + 2 * c[5] * o.y() * d.y());
                          const double c0 = o.z() - poly_at(p, o.x(), o.y()).f;
                          return detail::smallest_root(a, b, c0, t_min, t_max);
                        },
                        [&](const QuadricProxy& p) -> std::optional<double> {
                          const Eigen::Vector3d y0 = (ray.origin - p.center) / p.scale;
                          const Eigen::Vector3d e = ray.direction / p.scale;
                          const Eigen::Matrix3d a = 0.5 * quadric_hessian(p.coeffs);
                          const Eigen::Vector3d b(p.coeffs[6], p.coeffs[7], p.coeffs[8]);
                          return detail::smallest_root(e.dot(a * e), 2 * y0.dot(a * e) + b.dot(e),
                                                       quadric_q(p.coeffs, y0), t_min, t_max);
                        },
                        [&](const CreaseProxy& p) -> std::optional<double> {
                          // Each plane's crossing counts where the other plane lets it decide: below it for
                          // max (convex), above it for min (concave).
                          std::optional<double> best;
                          for (const auto& [own, other] : {std::pair{&p.a, &p.b}, std::pair{&p.b, &p.a}}) {
                            const auto t =
                                detail::smallest_root(0, own->normal.dot(ray.direction),
                                                      own->normal.dot(ray.origin - own->point), t_min, t_max);
                            if (!t) continue;
                            const double q = other->normal.dot(ray.origin + *t * ray.direction - other->point);
                            if ((p.convex ? q <= 0 : q >= 0) && (!best || *t < *best)) best = t;
                          }
                          return best;
                        },
                    },
                    v_);
}

void Proxy::flip() {
  std::visit(detail::Overloaded{
                 [](PointProxy&) {},
                 [](PlaneProxy& p) { p.normal = -p.normal; },
                 [](PolyProxy& p) {
                   // Mirror w: e3 → −e3 and f → −f; swap e1/e2 (and u/v in the coefficients)
                   // so the frame stays right-handed.
                   p.frame.axes.col(2) = -p.frame.axes.col(2);
                   p.frame.axes.col(0).swap(p.frame.axes.col(1));
                   auto& c = p.coeffs;
                   c = {-c[0], -c[2], -c[1], -c[5], -c[4], -c[3]};
                 },
                 [](QuadricProxy& p) {
                   for (double& c : p.coeffs) c = -c;
                 },
                 [](CreaseProxy& p) {
                   // −max(a, b) = min(−a, −b).
                   p.a.normal = -p.a.normal;
                   p.b.normal = -p.b.normal;
                   p.convex = !p.convex;
                 },
             },
             v_);
}

Eigen::Vector3d Proxy::normal() const {
  return std::visit(detail::Overloaded{
                        [](const PointProxy&) -> Eigen::Vector3d { return Eigen::Vector3d::UnitZ(); },
                        [](const PlaneProxy& p) -> Eigen::Vector3d { return p.normal; },
                        [](const PolyProxy& p) -> Eigen::Vector3d {
                          const PolyLocal f = poly_at(p, 0, 0);
                          return (p.frame.axes * Eigen::Vector3d(-f.fu, -f.fv, 1)).normalized();
                        },
                        [](const QuadricProxy& p) -> Eigen::Vector3d {
                          const Eigen::Vector3d g = quadric_grad(p.coeffs, Eigen::Vector3d::Zero());
                          return g.norm() > 0 ? Eigen::Vector3d(g.normalized()) : Eigen::Vector3d::UnitZ();
                        },
                        [](const CreaseProxy& p) -> Eigen::Vector3d {
                          const Eigen::Vector3d m = p.a.normal + p.b.normal;
                          return m.norm() > 1e-12 ? Eigen::Vector3d(m.normalized()) : p.a.normal;
                        },
                    },
                    v_);
}

}  // namespace clustersurf
