// Supports along a ray: ray–sphere tests down the hierarchy (or over every blended node) and
// each proxy restricted to the ray.

#include "render/ray_support.hpp"
#include "core/overloaded.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clustersurf::render {

namespace {

constexpr double kTinyD = 1e-24;  // the square of the proxies' smallest gradient norm

/// Writes N(t) and D(t) of `proxy` along `ray` into `span`.
void restrict_proxy(const Proxy& proxy, const Ray& ray, SupportSpan& span) {
  const Eigen::Vector3d& o = ray.origin;
  const Eigen::Vector3d& d = ray.direction;
  std::visit(detail::Overloaded{
                 [&](const PointProxy& p) {
                   // Q = ‖x − c‖ = D / sqrt(D) with D = ‖x − c‖².
                   const Eigen::Vector3d oc = o - p.center;
                   span.d0 = span.n0 = oc.squaredNorm();
                   span.d1 = span.n1 = 2 * oc.dot(d);
                   span.d2 = span.n2 = d.squaredNorm();
                 },
                 [&](const PlaneProxy& p) {
                   span.n0 = p.normal.dot(o - p.point);
                   span.n1 = p.normal.dot(d);
                   span.n2 = 0;
                   span.d0 = 1, span.d1 = 0, span.d2 = 0;
                 },
                 [&](const CreaseProxy& p) {
                   span.n0 = p.a.normal.dot(o - p.a.point);
                   span.n1 = p.a.normal.dot(d);
                   span.n2 = 0;
                   span.d0 = 1, span.d1 = 0, span.d2 = 0;
                   span.m0 = p.b.normal.dot(o - p.b.point);
                   span.m1 = p.b.normal.dot(d);
                   span.crease = p.convex ? 1 : -1;
                 },
                 [&](const PolyProxy& p) {
                   const Eigen::Vector3d ol = p.frame.to_local(o);
                   const Eigen::Vector3d dl = p.frame.axes.transpose() * d;
                   const auto& c = p.coeffs;
                   const double ou = ol.x(), ov = ol.y(), du = dl.x(), dv = dl.y();
                   const double f0 = p.height(ou, ov);
                   const double f1 =
                       c[1] * du + c[2] * dv + 2 * c[3] * ou * du + c[4] * (ou * dv + ov * du) + 2 * c[5] * ov * dv;
                   const double f2 = c[3] * du * du + c[4] * du * dv + c[5] * dv * dv;
                   span.n0 = ol.z() - f0;
                   span.n1 = dl.z() - f1;
                   span.n2 = -f2;
                   // fu = a0 + a1 t, fv = b0 + b1 t; D = 1 + fu² + fv².
                   const double a0 = c[1] + 2 * c[3] * ou + c[4] * ov, a1 = 2 * c[3] * du + c[4] * dv;
                   const double b0 = c[2] + c[4] * ou + 2 * c[5] * ov, b1 = c[4] * du + 2 * c[5] * dv;
                   span.d0 = 1 + a0 * a0 + b0 * b0;
                   span.d1 = 2 * (a0 * a1 + b0 * b1);
                   span.d2 = a1 * a1 + b1 * b1;
                 },
                 [&](const QuadricProxy& p) {
                   const auto& c = p.coeffs;
                   Eigen::Matrix3d h;
                   h << 2 * c[0], c[3], c[4], c[3], 2 * c[1], c[5], c[4], c[5], 2 * c[2];
                   const Eigen::Vector3d b(c[6], c[7], c[8]);
                   const Eigen::Vector3d y0 = (o - p.center) / p.scale;
                   const Eigen::Vector3d e = d / p.scale;
                   const double q0 = 0.5 * y0.dot(h * y0) + b.dot(y0) + c[9];
                   // Q = scale · q / ‖∇q‖ = (scale · q) / sqrt(‖∇q‖²), ∇q = g0 + g1 t.
                   span.n0 = p.scale * q0;
                   span.n1 = p.scale * (y0.dot(h * e) + b.dot(e));
                   span.n2 = p.scale * 0.5 * e.dot(h * e);
                   const Eigen::Vector3d g0 = h * y0 + b, g1 = h * e;
                   span.d0 = g0.squaredNorm();
                   span.d1 = 2 * g0.dot(g1);
                   span.d2 = g1.squaredNorm();
                 },
             },
             proxy.variant());
}

/// Sets span.flip0 and flip1 from the zeros of N (and M) inside the span: at most two (N is a
/// quadratic; a crease's N and M are linear).
void find_flips(SupportSpan& span) {
  span.flip0 = span.flip1 = std::numeric_limits<double>::infinity();
  double roots[2];
  int k = 0;
  const auto add = [&](double root) {
    if (root > span.t_enter && root < span.t_exit && k < 2) roots[k++] = root;
  };
  if (span.n2 == 0) {
    if (span.n1 != 0) add(-span.n0 / span.n1);
  } else {
    const double disc = span.n1 * span.n1 - 4 * span.n2 * span.n0;
    if (disc >= 0) {
      const double q = -0.5 * (span.n1 + std::copysign(std::sqrt(disc), span.n1));  // no cancellation
      add(q / span.n2);
      if (q != 0) add(span.n0 / q);
    }
  }
  if (span.crease != 0 && span.m1 != 0) add(-span.m0 / span.m1);
  if (k == 2 && roots[1] < roots[0]) std::swap(roots[0], roots[1]);
  if (k > 0) span.flip0 = roots[0];
  if (k > 1) span.flip1 = roots[1];
}

/// The span of `node`, whose support (squared radius r2) the ray meets on [t0, t1], from
/// oc = origin − center; not restricted yet.
SupportSpan make_span(std::int32_t node, const Eigen::Vector3d& oc, double r2, const Ray& ray, double t0, double t1) {
  SupportSpan s;
  s.node = node;
  s.t_enter = t0;
  s.t_exit = t1;
  const double inv_r2 = 1 / r2;
  s.s0 = oc.squaredNorm() * inv_r2;
  s.s1 = 2 * oc.dot(ray.direction) * inv_r2;
  s.s2 = ray.direction.squaredNorm() * inv_r2;
  return s;
}

}  // namespace

void restrict_span(const ClusterTree& tree, const Ray& ray, SupportSpan& span) {
  const ClusterNode& n = tree.nodes[static_cast<std::size_t>(span.node)];
  span.radius = n.support.radius;
  restrict_proxy(n.proxy, ray, span);
  find_flips(span);
  span.restricted = true;
}

double SupportSpan::q(double t) const {
  const double n = n0 + t * (n1 + t * n2);
  if (crease != 0) {
    const double m = m0 + t * m1;
    return crease > 0 ? std::max(n, m) : std::min(n, m);
  }
  const double d = d0 + t * (d1 + t * d2);
  return n / std::sqrt(std::max(d, kTinyD));
}

std::optional<std::pair<double, double>> ray_sphere(const Ray& ray, const Sphere& sphere) {
  const Eigen::Vector3d oc = ray.origin - sphere.center;
  const double b = oc.dot(ray.direction);
  const double c = oc.squaredNorm() - sphere.radius * sphere.radius;
  const double disc = b * b - c;
  if (!(disc > 0)) return std::nullopt;
  const double root = std::sqrt(disc);
  return std::pair{-b - root, -b + root};
}

SupportIndex::SupportIndex(const ClusterTree& tree, const LevelOfDetail& lod) : surface_(tree, lod) {
  supports_.resize(tree.nodes.size());
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const Sphere& sp = tree.nodes[i].support;
    supports_[i] = Eigen::Vector4d(sp.center.x(), sp.center.y(), sp.center.z(), sp.radius * sp.radius);
  }
}

namespace {

/// Whether a sphere may meet the cone (apex, unit axis, half-angle), conservatively.
bool sphere_meets_cone(const Sphere& sphere, const Eigen::Vector3d& apex, const Eigen::Vector3d& axis,
                       double half_angle) {
  const Eigen::Vector3d v = sphere.center - apex;
  const double dist = v.norm();
  if (dist <= sphere.radius) return true;
  const double angle = std::acos(std::clamp(v.dot(axis) / dist, -1.0, 1.0));
  return angle <= half_angle + std::asin(sphere.radius / dist) + 1e-9;
}

void sort_spans(std::vector<SupportSpan>& out) {
  std::sort(out.begin(), out.end(), [](const SupportSpan& a, const SupportSpan& b) {
    return a.t_enter < b.t_enter || (a.t_enter == b.t_enter && a.node < b.node);
  });
}

}  // namespace

void SupportIndex::collect_in_cone(const Eigen::Vector3d& eye, const Eigen::Vector3d& axis, double half_angle,
                                   std::vector<std::int32_t>& out) const {
  out.clear();
  if (tree().nodes.empty()) return;
  surface_.walk([&](const Sphere& bound) { return sphere_meets_cone(bound, eye, axis, half_angle); },
                [&](std::int32_t i) {
                  if (sphere_meets_cone(tree().nodes[static_cast<std::size_t>(i)].support, eye, axis, half_angle))
                    out.push_back(i);
                });
}

void SupportIndex::gather(std::span<const std::int32_t> nodes, SupportSet& out) const {
  out.nodes.assign(nodes.begin(), nodes.end());
  out.x.resize(nodes.size()), out.y.resize(nodes.size()), out.z.resize(nodes.size()), out.r2.resize(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const Eigen::Vector4d& sp = supports_[static_cast<std::size_t>(nodes[k])];
    out.x[k] = sp.x(), out.y[k] = sp.y(), out.z[k] = sp.z(), out.r2[k] = sp.w();
  }
}

void cull_to_cone(const SupportSet& in, const RayCone& cone, SupportSet& out) {
  // A sphere (c, r) meets the cone only if c lies within r of the cone's boundary line in the
  // plane through the axis and c: d⊥ cos θ − d∥ sin θ ≤ r, with d∥ and d⊥ the distances of c
  // along and off the axis. Angle and radius get a little slack against rounding.
  constexpr double kAngleSlack = 1e-9, kRadiusSlack = 1e-9;
  // cos(θ + ε) and sin(θ + ε) to first order in ε.
  const double cos_a = cone.cos_half - kAngleSlack * cone.sin_half;
  const double sin_a = cone.sin_half + kAngleSlack * cone.cos_half;
  const double ax = cone.axis.x(), ay = cone.axis.y(), az = cone.axis.z();
  const std::size_t n = in.nodes.size();
  out.nodes.resize(n), out.x.resize(n), out.y.resize(n), out.z.resize(n), out.r2.resize(n);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double vx = in.x[k] - cone.apex.x(), vy = in.y[k] - cone.apex.y(), vz = in.z[k] - cone.apex.z();
    const double along = vx * ax + vy * ay + vz * az;
    const double wx = vx - along * ax, wy = vy - along * ay, wz = vz - along * az;
    const double gap = std::sqrt(wx * wx + wy * wy + wz * wz) * cos_a - along * sin_a;
    // Written unconditionally, kept by advancing the count: no branch to mispredict.
    out.nodes[kept] = in.nodes[k];
    out.x[kept] = in.x[k], out.y[kept] = in.y[k], out.z[kept] = in.z[k], out.r2[kept] = in.r2[k];
    kept += static_cast<std::size_t>(gap <= 0 || gap * gap <= in.r2[k] * (1 + kRadiusSlack));
  }
  out.nodes.resize(kept), out.x.resize(kept), out.y.resize(kept), out.z.resize(kept), out.r2.resize(kept);
}

void order_along(const RayCone& cone, SupportSet& set) {
  const std::size_t n = set.nodes.size();
  auto& order = set.order;
  order.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double along = (set.x[k] - cone.apex.x()) * cone.axis.x() + (set.y[k] - cone.apex.y()) * cone.axis.y() +
                         (set.z[k] - cone.apex.z()) * cone.axis.z();
    order[k] = {along - std::sqrt(set.r2[k]), k};
  }
  std::sort(order.begin(), order.end());
  // Each array gathered into the scratch, which then takes its place.
  const auto permute = [&](auto& values, auto& scratch) {
    scratch.resize(n);
    for (std::size_t k = 0; k < n; ++k) scratch[k] = values[order[k].second];
    values.swap(scratch);
  };
  permute(set.nodes, set.moved_nodes);
  permute(set.x, set.moved), permute(set.y, set.moved), permute(set.z, set.moved), permute(set.r2, set.moved);
}

void SupportIndex::collect_from(const Ray& ray, double t_min, double t_max, const SupportSet& set,
                                std::vector<SupportSpan>& out) const {
  out.clear();
  const double ox = ray.origin.x(), oy = ray.origin.y(), oz = ray.origin.z();
  const double dx = ray.direction.x(), dy = ray.direction.y(), dz = ray.direction.z();
  const std::size_t n = set.nodes.size();
  set.b.resize(n), set.disc.resize(n);
  double* bs = set.b.data();
  double* discs = set.disc.data();
  // First every discriminant, in a loop without branches (vectorized), then the spans of the
  // supports crossed. ray_sphere()'s arithmetic in its order: oc = origin − center, b = oc · d,
  // c = |oc|² − r².
  for (std::size_t k = 0; k < n; ++k) {
    const double cx = ox - set.x[k], cy = oy - set.y[k], cz = oz - set.z[k];
    const double b = cx * dx + cy * dy + cz * dz;
    bs[k] = b;
    discs[k] = b * b - ((cx * cx + cy * cy + cz * cz) - set.r2[k]);
  }
  // The crossings sorted by (t_enter, node) before their spans are made, so that the sort moves
  // small records.
  auto& crossings = set.crossings;
  crossings.clear();
  for (std::size_t k = 0; k < n; ++k) {
    const double disc = discs[k], b = bs[k];
    if (!(disc > 0)) continue;
    const double root = std::sqrt(disc);
    const double t0 = -b - root, t1 = -b + root;
    if (t1 > t_min && t0 < t_max) crossings.push_back({std::max(t0, t_min), std::min(t1, t_max), k});
  }
  // By insertion: a set ordered along its cone (order_along()) leaves them nearly sorted; a set in
  // tree order (brute force) costs more here, beside its test of every support.
  const auto before = [&](const SupportSet::Crossing& a, const SupportSet::Crossing& c) {
    return a.t_enter < c.t_enter || (a.t_enter == c.t_enter && set.nodes[a.k] < set.nodes[c.k]);
  };
  for (std::size_t i = 1; i < crossings.size(); ++i) {
    const SupportSet::Crossing c = crossings[i];
    std::size_t j = i;
    for (; j > 0 && before(c, crossings[j - 1]); --j) crossings[j] = crossings[j - 1];
    crossings[j] = c;
  }
  for (const SupportSet::Crossing& c : crossings) {
    const Eigen::Vector3d oc(ox - set.x[c.k], oy - set.y[c.k], oz - set.z[c.k]);
    out.push_back(make_span(set.nodes[c.k], oc, set.r2[c.k], ray, c.t_enter, c.t_exit));
  }
}

void SupportIndex::collect(const Ray& ray, double t_min, double t_max, SupportSearch search,
                           std::vector<SupportSpan>& out) const {
  out.clear();
  const auto& nodes = tree().nodes;
  if (nodes.empty()) return;
  const auto consider = [&](std::int32_t i) {
    const ClusterNode& n = nodes[static_cast<std::size_t>(i)];
    const auto span = ray_sphere(ray, n.support);
    if (span && span->second > t_min && span->first < t_max)
      out.push_back(make_span(i, ray.origin - n.support.center, n.support.radius * n.support.radius, ray,
                              std::max(span->first, t_min), std::min(span->second, t_max)));
  };
  if (search == SupportSearch::BruteForce) {
    for (std::int32_t i : cut()) consider(i);
  } else {
    surface_.walk(
        [&](const Sphere& sphere) {
          const auto bound = ray_sphere(ray, sphere);
          return bound && bound->second > t_min && bound->first < t_max;
        },
        consider);
  }
  sort_spans(out);
}

}  // namespace clustersurf::render
