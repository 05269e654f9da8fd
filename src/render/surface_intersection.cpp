// Ray–surface intersection over the supports a ray crosses.

#include "render/surface_intersection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace clustersurf::render {

namespace {

// Marching steps, as fractions of the smallest support radius at the current sample.
constexpr double kDistanceFactor = 0.7;  // step = 0.7 |f| where f is defined ...
constexpr double kMinStep = 0.02;        // ... but at least this ...
constexpr double kMaxStep = 0.25;        // ... and at most this
constexpr double kUndefinedStep = 0.1;   // step where f is undefined
constexpr double kOvershoot = 0.01;      // past the secant's zero by this
constexpr int kMaxRefine = 60;

/// f along one ray from its spans, each restricted to the ray when first needed. Spans are
/// sorted by t_enter; those entered so far are [begin, end), `end` only grows with t.
class RayFunction {
 public:
  struct Sample {
    double f = 0;
    double weight = 0;
    double r_min = 0;  // smallest radius of the supports containing the sample (0: none)
  };

  /// `evaluations`, when given, counts the calls of at().
  RayFunction(const ClusterTree& tree, const Ray& ray, std::span<SupportSpan> spans, std::size_t* evaluations)
      : tree_(tree), ray_(ray), spans_(spans), evaluations_(evaluations) {}

  Sample at(double t) {
    if (evaluations_ != nullptr) ++*evaluations_;
    while (end_ < spans_.size() && spans_[end_].t_enter <= t) restricted(end_++);
    Sample out;
    double a = 0;
    double r_min = std::numeric_limits<double>::infinity();
    for (std::size_t i = begin_; i < end_; ++i) {
      const SupportSpan& sp = spans_[i];
      if (sp.t_exit < t) continue;
      const double s = sp.s(t);
      if (s >= 1) continue;
      const double om = 1 - s;
      const double w = om * om * om;
      a += w * sp.q(t);
      out.weight += w;
      r_min = std::min(r_min, sp.radius);
    }
    if (out.weight > 0) {
      out.f = a / out.weight;
      out.r_min = r_min;
    }
    return out;
  }
  /// A point up to which every proxy blended after t keeps one sign, the same as f's at t
  /// (`positive`: f > 0, else f ≤ 0), so that f keeps that sign there: t when the signs differ;
  /// +inf past the last span. The spans entered so far must be those entered at t.
  double one_sign_until(double t, bool positive) {
    const int sign = positive ? 1 : -1;
    double until = std::numeric_limits<double>::infinity();
    // Whether the span's proxy has `sign` on (from, its next flip); its sign there is that at
    // the middle (from itself may be a flip).
    const auto agrees = [&](const SupportSpan& sp, double from) {
      const double flip = std::min(sp.flip0 > from ? sp.flip0 : sp.flip1 > from ? sp.flip1 : sp.t_exit, sp.t_exit);
      if ((sp.positive(0.5 * (from + flip)) ? 1 : -1) != sign) return false;
      if (flip < sp.t_exit) until = std::min(until, flip);
      return true;
    };
    for (std::size_t i = begin_; i < end_; ++i)
      if (spans_[i].t_exit >= t && !agrees(spans_[i], t)) return t;
    for (std::size_t j = end_; j < spans_.size() && spans_[j].t_enter < until; ++j)
      if (!agrees(restricted(j), spans_[j].t_enter)) return spans_[j].t_enter;
    return until;
  }
  /// Forgets leading spans that end before t (t must not decrease afterwards below it).
  void drop_before(double t) {
    while (begin_ < end_ && spans_[begin_].t_exit < t) ++begin_;
  }
  /// Parameter of the next span entry after the spans entered so far, or +inf.
  double next_entry() const {
    return end_ < spans_.size() ? spans_[end_].t_enter : std::numeric_limits<double>::infinity();
  }

 private:
  const SupportSpan& restricted(std::size_t i) {
    if (!spans_[i].restricted) restrict_span(tree_, ray_, spans_[i]);
    return spans_[i];
  }

  const ClusterTree& tree_;
  const Ray& ray_;
  std::span<SupportSpan> spans_;
  std::size_t* evaluations_;
  std::size_t begin_ = 0, end_ = 0;
};

/// The zero of f in [a, b], where f(a) = fa and f(b) = fb differ in sign, by the Illinois
/// method (modified regula falsi) down to a bracket of `settings.tolerance`; nullopt when f is
/// undefined in the bracket.
std::optional<double> refine_zero(RayFunction& f, double a, double fa, double b, double fb,
                                  const MarchSettings& settings) {
  int side = 0;
  for (int it = 0; it < kMaxRefine && b - a > settings.tolerance; ++it) {
    double c = (fa * b - fb * a) / (fa - fb);
    if (!(c > a && c < b)) c = 0.5 * (a + b);
    RayFunction::Sample sc = f.at(c);
    if (!(sc.weight > settings.min_weight)) {
      c = 0.5 * (a + b);
      sc = f.at(c);
      if (!(sc.weight > settings.min_weight)) return std::nullopt;
    }
    if ((sc.f > 0) == (fb > 0)) {
      b = c, fb = sc.f;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = c, fa = sc.f;
      if (side == 1) fb *= 0.5;
      side = 1;
    }
  }
  return fa != fb ? std::clamp((fa * b - fb * a) / (fa - fb), a, b) : 0.5 * (a + b);
}

}  // namespace

void finish_hit(const ClusterTree& tree, std::span<const SupportSpan> spans, SurfaceHit& hit) {
  // ∇f = (∇A − f ∇W) / W with A = Σ w Q, W = Σ w; only its direction is needed.
  const Eigen::Vector3d& x = hit.position;
  double a = 0, w_sum = 0, best_w = -1;
  Eigen::Vector3d grad_a = Eigen::Vector3d::Zero(), grad_w = Eigen::Vector3d::Zero();
  for (const SupportSpan& sp : spans) {
    if (hit.t < sp.t_enter || hit.t > sp.t_exit) continue;
    const ClusterNode& n = tree.nodes[static_cast<std::size_t>(sp.node)];
    const Eigen::Vector3d dx = x - n.support.center;
    const double r2 = n.support.radius * n.support.radius;
    const double s = dx.squaredNorm() / r2;
    if (s >= 1) continue;
    const double om = 1 - s;
    const double w = om * om * om;
    const Eigen::Vector3d dw = (-6 * om * om / r2) * dx;
    const auto [q, grad_q] = n.proxy.value_and_gradient(x);
    a += w * q;
    w_sum += w;
    grad_a += dw * q + w * grad_q;
    grad_w += dw;
    if (w > best_w || (w == best_w && sp.node < hit.dominant)) best_w = w, hit.dominant = sp.node;
  }
  if (!(w_sum > 0)) return;
  const Eigen::Vector3d g = grad_a - (a / w_sum) * grad_w;
  if (g.norm() > 0) hit.normal = g.normalized();
}

std::optional<SurfaceHit> first_zero(const ClusterTree& tree, std::span<SupportSpan> spans, const Ray& ray,
                                     double t_min, double t_max, const MarchSettings& settings,
                                     std::size_t* evaluations) {
  if (spans.empty()) return std::nullopt;
  double t_end = t_min;
  for (const SupportSpan& sp : spans) t_end = std::max(t_end, sp.t_exit);
  t_end = std::min(t_end, t_max);
  RayFunction f(tree, ray, spans, evaluations);
  const auto defined = [&](const RayFunction::Sample& s) { return s.weight > settings.min_weight; };
  const auto hit_at = [&](double t_hit) {
    SurfaceHit hit;
    hit.t = t_hit;
    hit.position = ray.origin + t_hit * ray.direction;
    finish_hit(tree, spans, hit);
    return hit;
  };
  double t = std::max(t_min, spans.front().t_enter);
  RayFunction::Sample prev = f.at(t);
  bool have_before = false;  // whether (before_t, before_f), the sample before prev, is defined
  double before_t = 0, before_f = 0;
  while (t < t_end) {
    if (prev.weight <= 0) {  // outside every support: jump to the next one
      const double next = f.next_entry();
      if (!(next < t_end)) break;
      t = std::max(t, next);
      f.drop_before(t);
      prev = f.at(t);
      have_before = false;
      continue;
    }
    const double r = prev.r_min;
    double h = kUndefinedStep * r;
    if (defined(prev)) {
      h = kDistanceFactor * std::abs(prev.f);
      // Where f falls towards zero, step just past the secant's zero, but no farther than 2 |f|
      // (where an approximate distance |f| puts the surface at 60 degrees' incidence).
      if (have_before && (before_f > 0) == (prev.f > 0) && std::abs(prev.f) < std::abs(before_f))
        h = std::max(h, std::min((t - before_t) * prev.f / (before_f - prev.f) + kOvershoot * r, 2 * std::abs(prev.f)));
      h = std::clamp(h, kMinStep * r, kMaxStep * r);
    }
    const double skip_to = f.one_sign_until(t, prev.f > 0);
    const double t_next = std::min(std::max(t + h, skip_to), t_end);
    const RayFunction::Sample cur = f.at(t_next);
    // f keeps prev's sign up to skip_to: where it has the other one there and the proxies do not
    // all keep prev's sign beyond (a touch), that is its zero.
    if (t_next == skip_to && defined(cur) && (prev.f > 0) != (cur.f > 0) &&
        f.one_sign_until(t_next, prev.f > 0) == t_next)
      return hit_at(t_next);
    if (defined(prev) && defined(cur) && (prev.f > 0) != (cur.f > 0))
      if (const auto zero = refine_zero(f, t, prev.f, t_next, cur.f, settings)) return hit_at(*zero);
    have_before = defined(prev) && defined(cur);
    before_t = t, before_f = prev.f;
    t = t_next;
    f.drop_before(t);
    prev = cur;
  }
  return std::nullopt;
}

std::optional<SurfaceHit> blended_hit(const ClusterTree& tree, std::span<const SupportSpan> spans, const Ray& ray,
                                      double t_min, double t_max, double min_weight) {
  struct ProxyHit {
    double t, w, radius;
    std::int32_t node;
  };
  std::vector<ProxyHit> hits;
  for (const SupportSpan& sp : spans) {
    const ClusterNode& n = tree.nodes[static_cast<std::size_t>(sp.node)];
    const auto t = n.proxy.intersect(ray, std::max(sp.t_enter, t_min), std::min(sp.t_exit, t_max));
    if (!t) continue;
    const double s = sp.s(*t);
    if (s >= 1) continue;
    const double om = 1 - s;
    hits.push_back({*t, om * om * om, n.support.radius, sp.node});
  }
  std::sort(hits.begin(), hits.end(),
            [](const ProxyHit& a, const ProxyHit& b) { return a.t < b.t || (a.t == b.t && a.node < b.node); });
  for (std::size_t k = 0; k < hits.size(); ++k) {
    const double window = 0.25 * hits[k].radius;
    double w_sum = 0, tw = 0, best_w = -1;
    std::int32_t best = -1;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (std::size_t j = k; j < hits.size() && hits[j].t - hits[k].t <= window; ++j) {
      const ClusterNode& n = tree.nodes[static_cast<std::size_t>(hits[j].node)];
      const Eigen::Vector3d g = n.proxy.gradient(ray.origin + hits[j].t * ray.direction);
      w_sum += hits[j].w;
      tw += hits[j].w * hits[j].t;
      if (g.norm() > 0) normal += hits[j].w * g.normalized();
      if (hits[j].w > best_w) best_w = hits[j].w, best = hits[j].node;
    }
    if (!(w_sum > min_weight)) continue;
    SurfaceHit hit;
    hit.t = tw / w_sum;
    hit.position = ray.origin + hit.t * ray.direction;
    hit.normal = normal.norm() > 0 ? Eigen::Vector3d(normal.normalized()) : Eigen::Vector3d(-ray.direction);
    hit.dominant = best;
    return hit;
  }
  return std::nullopt;
}

}  // namespace clustersurf::render
