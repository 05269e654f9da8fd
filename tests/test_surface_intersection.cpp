// Where a ray meets the blended surface: the march finds the first zero of f that a fine
// uniform march finds, in a few evaluations of f, on a noisy torus whose proxies disagree.

#include "render/surface_intersection.hpp"

#include <clustersurf/surface/orientation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <vector>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// The first zero of f along the ray found by evaluating it every `step` over [t0, t1] and
/// bisecting the first sign change between two samples where f is defined.
std::optional<double> reference_zero(const ImplicitSurface& surface, const Ray& ray, double t0, double t1, double step,
                                     double min_weight) {
  const auto f = [&](double t) { return surface.value(ray.origin + t * ray.direction, min_weight); };
  std::optional<double> prev = f(t0);
  for (double t = t0; t < t1; t += step) {
    const std::optional<double> cur = f(t + step);
    if (prev && cur && (*prev > 0) != (*cur > 0)) {
      double a = t, b = t + step;
      const bool a_positive = *prev > 0;
      for (int it = 0; it < 60; ++it) {
        const double c = 0.5 * (a + b);
        const std::optional<double> fc = f(c);
        if (!fc) break;
        ((*fc > 0) == a_positive ? a : b) = c;
      }
      return 0.5 * (a + b);
    }
    prev = cur;
  }
  return std::nullopt;
}

}  // namespace

TEST(SurfaceIntersection, TheMarchFindsTheFineMarchsZeroInFewEvaluations) {
  PointCloud cloud = test::sample_torus(20000, 1.0, 0.2);
  test::add_normal_noise(cloud, 0.01, 3);
  ClusterTree tree = build_cluster_tree(cloud);
  orient_tree(tree, cloud);
  const render::SupportIndex index(tree, {});
  const ImplicitSurface surface(tree);
  const double diagonal = tree.bbox.diagonal();
  render::MarchSettings march;
  march.tolerance = 1e-6 * diagonal;  // as the renderer

  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  int rays = 0, hits = 0, agree = 0;
  std::size_t evaluations = 0;
  std::vector<render::SupportSpan> spans;
  for (int k = 0; k < 400; ++k) {
    // From a sphere around the torus towards a point near its core circle.
    Eigen::Vector3d eye(unit(rng), unit(rng), unit(rng));
    eye = 3.0 * eye.normalized();
    const double angle = 3.14159 * unit(rng);
    const Eigen::Vector3d target =
        Eigen::Vector3d(std::cos(angle), std::sin(angle), 0) + 0.3 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    const Ray ray{eye, (target - eye).normalized()};
    index.collect(ray, 0, 1e9, render::SupportSearch::Hierarchy, spans);
    if (spans.empty()) continue;
    double t0 = spans.front().t_enter, t1 = t0;
    for (const auto& sp : spans) t1 = std::max(t1, sp.t_exit);
    const auto hit = render::first_zero(tree, spans, ray, 0, 1e9, march, &evaluations);
    const auto expected = reference_zero(surface, ray, t0, t1, 2e-4 * diagonal, march.min_weight);
    ++rays;
    hits += hit.has_value();
    agree += hit.has_value() == expected.has_value() && (!hit || std::abs(hit->t - *expected) < 2e-6 * diagonal);
  }
  ASSERT_GT(rays, 300);
  EXPECT_GT(hits, rays / 2);
  EXPECT_GE(agree, rays - 2) << "of " << rays << " rays";
  const double per_ray = static_cast<double>(evaluations) / rays;
  EXPECT_LT(per_ray, 10.0) << "evaluations of f per ray";
  std::printf("%d rays, %d hits, %d agree, %.2f evaluations per ray\n", rays, hits, agree, per_ray);
}
