// Supports along rays: the cone cull keeps every support a ray of the cone crosses and drops
// those far from it; ordering a set along a cone permutes it by where the axis enters each.

#include "render/ray_support.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

using namespace clustersurf;

namespace {

/// A unit vector at angle `angle` from the unit `axis`, turned by `turn` around it.
Eigen::Vector3d tilted(const Eigen::Vector3d& axis, double angle, double turn) {
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  return std::cos(angle) * axis + std::sin(angle) * (std::cos(turn) * u + std::sin(turn) * v);
}

}  // namespace

TEST(RaySupport, TheConeCullKeepsEverySupportARayOfTheConeCrosses) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0, 1), box(-3, 3);
  const double half = 0.03;
  const render::RayCone cone =
      render::RayCone::of_half_angle(Eigen::Vector3d(0.1, -0.2, 5), Eigen::Vector3d(0.05, 0.02, -1).normalized(), half);
  render::SupportSet all;
  for (std::int32_t i = 0; i < 20000; ++i) {
    const double r = 0.01 + 0.2 * unit(rng);
    all.nodes.push_back(i);
    all.x.push_back(box(rng)), all.y.push_back(box(rng)), all.z.push_back(box(rng)), all.r2.push_back(r * r);
  }
  render::SupportSet kept;
  render::cull_to_cone(all, cone, kept);
  ASSERT_EQ(kept.nodes.size(), kept.r2.size());
  EXPECT_TRUE(std::is_sorted(kept.nodes.begin(), kept.nodes.end()));  // the order of the input
  // Rays on the cone's rim and inside it: every sphere one of them crosses is kept.
  std::size_t crossed = 0;
  for (int k = 0; k < 4000; ++k) {
    const double angle = k % 2 == 0 ? half : half * std::sqrt(unit(rng));
    const Ray ray{cone.apex, tilted(cone.axis, angle, 2 * std::numbers::pi * unit(rng))};
    for (std::size_t i = 0; i < all.nodes.size(); ++i) {
      const Sphere sphere{Eigen::Vector3d(all.x[i], all.y[i], all.z[i]), std::sqrt(all.r2[i])};
      const auto span = render::ray_sphere(ray, sphere);
      if (!span || span->second <= 0) continue;
      ++crossed;
      EXPECT_TRUE(std::binary_search(kept.nodes.begin(), kept.nodes.end(), all.nodes[i]))
          << "support " << i << " crossed by a ray " << angle << " rad off the axis was culled";
    }
  }
  EXPECT_GT(crossed, 0u);
  // A narrow cone meets a small share of spheres spread through the box.
  EXPECT_LT(kept.nodes.size(), all.nodes.size() / 10);
  EXPECT_GT(kept.nodes.size(), 0u);
}

TEST(RaySupport, TheConeCullKeepsASphereHoldingTheApexAndDropsOneBehindIt) {
  const render::RayCone cone = render::RayCone::of_half_angle(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.1);
  render::SupportSet all;
  all.nodes = {0, 1, 2};
  all.x = {0.3, 0, 0}, all.y = {0, 0, 0}, all.z = {-0.2, -2, 3}, all.r2 = {1, 0.01, 0.01};
  render::SupportSet kept;
  render::cull_to_cone(all, cone, kept);
  EXPECT_EQ(kept.nodes, (std::vector<std::int32_t>{0, 2}));
}

TEST(RaySupport, OrderingAlongTheConeKeepsEverySupportAndSortsThemByEntry) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0, 1), box(-3, 3);
  const render::RayCone cone =
      render::RayCone::of_half_angle(Eigen::Vector3d(0.2, 0.1, 6), Eigen::Vector3d(-0.03, 0.04, -1).normalized(), 0.2);
  render::SupportSet set;
  for (std::int32_t i = 0; i < 500; ++i) {
    const double r = 0.01 + 0.5 * unit(rng);
    set.nodes.push_back(i);
    set.x.push_back(box(rng)), set.y.push_back(box(rng)), set.z.push_back(box(rng)), set.r2.push_back(r * r);
  }
  const render::SupportSet before = set;
  render::order_along(cone, set);
  ASSERT_EQ(set.nodes.size(), before.nodes.size());
  std::vector<double> entry;
  for (std::size_t k = 0; k < set.nodes.size(); ++k) {
    const auto i = static_cast<std::size_t>(set.nodes[k]);  // the support's place before
    EXPECT_EQ(set.x[k], before.x[i]);
    EXPECT_EQ(set.y[k], before.y[i]);
    EXPECT_EQ(set.z[k], before.z[i]);
    EXPECT_EQ(set.r2[k], before.r2[i]);
    entry.push_back((Eigen::Vector3d(set.x[k], set.y[k], set.z[k]) - cone.apex).dot(cone.axis) - std::sqrt(set.r2[k]));
  }
  std::vector<std::int32_t> nodes = set.nodes;
  std::sort(nodes.begin(), nodes.end());
  EXPECT_EQ(nodes, before.nodes);  // a permutation
  EXPECT_TRUE(std::is_sorted(entry.begin(), entry.end()));
}
