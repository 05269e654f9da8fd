// ImplicitSurface::BoxWalk: queries through a box's walk visit exactly the nodes, in the same
// order and with the same weights, as the walk from the root, so values and samples are the
// same to the bit; inside and on the box, outside it, and on the bounding spheres it cuts.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/surface/box_walk.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

using Visits = std::vector<std::pair<std::int32_t, double>>;

Visits from_root(const ImplicitSurface& f, const Eigen::Vector3d& x) {
  Visits v;
  f.for_each_support(x, [&](std::int32_t i, double s) { v.emplace_back(i, s); });
  return v;
}

Visits through(const ImplicitSurface::BoxWalk& near, const Eigen::Vector3d& x) {
  Visits v;
  near.for_each_support(x, [&](std::int32_t i, double s) { v.emplace_back(i, s); });
  return v;
}

BoundingBox box_of(const Eigen::Vector3d& center, const Eigen::Vector3d& half) {
  BoundingBox box;
  box.min = center - half;
  box.max = center + half;
  return box;
}

/// Points of `box`: random ones inside, its corners, and the points of every bounding sphere
/// of `f` that cuts the box, on the sphere to the last bit and one ulp either side, that lie in
/// it: where a test of the whole box could go wrong by rounding.
std::vector<Eigen::Vector3d> probes(const ImplicitSurface& f, const BoundingBox& box, std::mt19937_64& rng) {
  std::vector<Eigen::Vector3d> out;
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 300; ++k)
    out.push_back(box.min + (box.max - box.min).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng))));
  for (int c = 0; c < 8; ++c)
    out.push_back(Eigen::Vector3d(c & 1 ? box.max.x() : box.min.x(), c & 2 ? box.max.y() : box.min.y(),
                                  c & 4 ? box.max.z() : box.min.z()));
  std::normal_distribution<double> g(0, 1);
  const auto inside = [&](const Eigen::Vector3d& x) {
    return (x.array() >= box.min.array()).all() && (x.array() <= box.max.array()).all();
  };
  for (std::int32_t i = 0; i < static_cast<std::int32_t>(f.tree().nodes.size()); ++i) {
    // Its bounding sphere, and the support of a blended node (the sphere its visit tests).
    std::vector<Sphere> spheres = {f.bound(i)};
    if (f.in_cut(i)) spheres.push_back(Sphere{f.tree().nodes[static_cast<std::size_t>(i)].support.center, f.radius(i)});
    for (const Sphere& s : spheres) {
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d x = s.center + s.radius * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
        if (!inside(x)) continue;
        for (const double toward : {-1.0, 0.0, 1.0}) {
          Eigen::Vector3d y = x;
          if (toward != 0) y.x() = std::nextafter(y.x(), toward * 1e300);
          if (inside(y)) out.push_back(y);
        }
      }
    }
  }
  return out;
}

ClusterTree torus_tree() {
  const PointCloud c = test::sample_torus(20000);
  ClusterTree t = build_cluster_tree(c, {});
  orient_tree(t, c);
  return t;
}

}  // namespace

TEST(BoxWalk, VisitsWhatTheWalkFromTheRootVisits) {
  const ClusterTree t = torus_tree();
  const double diagonal = t.bbox.diagonal();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::size_t compared = 0;
  for (const ImplicitSurface& f : {ImplicitSurface(t), ImplicitSurface(t).with_margin(0.01 * diagonal),
                                   ImplicitSurface(t, LevelOfDetail{4, std::nullopt})}) {
    for (const double size : {0.005, 0.03, 0.2, 1.0}) {
      for (int b = 0; b < 6; ++b) {
        const Eigen::Vector3d center =
            t.bbox.min + (t.bbox.max - t.bbox.min).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
        const BoundingBox box = box_of(center, Eigen::Vector3d::Constant(size * diagonal / 2));
        const ImplicitSurface::BoxWalk near(f, box);
        for (const Eigen::Vector3d& x : probes(f, box, rng)) {
          ASSERT_TRUE(near.covers(x));
          ASSERT_EQ(through(near, x), from_root(f, x)) << "at " << x.transpose();
          ++compared;
        }
        // Just outside the box: the walk from the root.
        for (const Eigen::Vector3d& corner : {box.min, box.max}) {
          for (int a = 0; a < 3; ++a) {
            Eigen::Vector3d away = corner;
            away(a) = std::nextafter(away(a), corner == box.max ? 1e300 : -1e300);
            EXPECT_FALSE(near.covers(away));
            EXPECT_EQ(through(near, away), from_root(f, away));
          }
        }
      }
    }
  }
  EXPECT_GT(compared, 10000u);
}

TEST(BoxWalk, BoxesTouchingABoundingSphereFromInsideAndOutside) {
  // A box with its farthest corner on a node's bounding sphere (the whole box inside it, but
  // for rounding), and one with its nearest corner there (outside it, but for rounding): the
  // boxes a whole-box test judges wrongly when it leaves no room for rounding.
  const ClusterTree t = torus_tree();
  const ImplicitSurface f(t);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::int32_t i = 0; i < static_cast<std::int32_t>(t.nodes.size()); i += 7) {
    const Sphere& s = f.bound(i);
    const Eigen::Vector3d dir = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector3d corner = s.center + s.radius * dir;
    const Eigen::Vector3d step = 0.05 * s.radius * dir.cwiseSign();
    for (const double side : {-1.0, 1.0}) {  // towards the center: inside; away: outside
      const Eigen::Vector3d other = corner + side * step;
      BoundingBox box;
      box.extend(corner);
      box.extend(other);
      const ImplicitSurface::BoxWalk near(f, box);
      std::vector<Eigen::Vector3d> xs = {corner};
      for (int a = 0; a < 3; ++a)
        for (const double toward : {-1e300, 1e300}) {
          Eigen::Vector3d y = corner;
          y(a) = std::nextafter(y(a), toward);
          xs.push_back(y);
        }
      for (int k = 0; k < 20; ++k)
        xs.push_back(box.min + (box.max - box.min).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng))));
      for (const Eigen::Vector3d& x : xs)
        ASSERT_EQ(through(near, x), from_root(f, x)) << "node " << i << " at " << x.transpose();
    }
  }
}

TEST(BoxWalk, GivesTheSameValuesAndSamplesToTheBit) {
  const ClusterTree t = torus_tree();
  const ImplicitSurface f(t);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  const double diagonal = t.bbox.diagonal();
  int defined = 0;
  for (int b = 0; b < 20; ++b) {
    const Eigen::Vector3d center =
        t.bbox.min + (t.bbox.max - t.bbox.min).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    const BoundingBox box = box_of(center, Eigen::Vector3d::Constant(0.02 * diagonal));
    const ImplicitSurface::BoxWalk near(f, box);
    for (int k = 0; k < 200; ++k) {
      const Eigen::Vector3d x = box.min + (box.max - box.min).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
      ASSERT_EQ(f.value(x, kMinWeight, near), f.value(x, kMinWeight));
      const SurfaceSample a = f.sample(x, near), b2 = f.sample(x);
      ASSERT_EQ(a.defined, b2.defined);
      ASSERT_EQ(a.value, b2.value);
      ASSERT_EQ(a.weight, b2.weight);
      ASSERT_EQ(a.gradient, b2.gradient);
      defined += a.defined;
    }
  }
  EXPECT_GT(defined, 100);  // the boxes reach the surface
}

TEST(BoxWalk, KeepsOnlyTheNodesNearASmallBox) {
  const ClusterTree t = torus_tree();
  const ImplicitSurface f(t);
  // A box around a point of the torus' outer equator (R = 1, r = 0.35).
  const BoundingBox box = box_of(Eigen::Vector3d(1.35, 0, 0), Eigen::Vector3d::Constant(0.01));
  const ImplicitSurface::BoxWalk near(f, box);
  EXPECT_GT(near.size(), 0u);
  EXPECT_LT(near.size() * 20, t.nodes.size());
  EXPECT_TRUE(near.covers(Eigen::Vector3d(1.35, 0, 0)));
  EXPECT_TRUE(f.value(Eigen::Vector3d(1.35, 0, 0), 0, near).has_value());
}

TEST(BoxWalk, AnEmptyBoxOrTreeWalksFromTheRoot) {
  const ClusterTree t = torus_tree();
  const ImplicitSurface f(t);
  const ImplicitSurface::BoxWalk empty_box(f, BoundingBox{});
  EXPECT_EQ(empty_box.size(), 0u);
  const Eigen::Vector3d x(1.35, 0, 0);
  EXPECT_FALSE(empty_box.covers(x));
  EXPECT_EQ(through(empty_box, x), from_root(f, x));
  EXPECT_FALSE(from_root(f, x).empty());

  const ClusterTree none;
  const ImplicitSurface g(none);
  const ImplicitSurface::BoxWalk near(g, box_of(x, Eigen::Vector3d::Constant(1.0)));
  EXPECT_EQ(near.size(), 0u);
  EXPECT_TRUE(through(near, x).empty());
  EXPECT_FALSE(g.value(x, 0, near).has_value());
}

TEST(BoxWalk, ServesOnlyItsOwnSurface) {
  const ClusterTree t = torus_tree();
  const ImplicitSurface f(t), g = f.with_margin(0.1);
  const ImplicitSurface::BoxWalk near(f, box_of(Eigen::Vector3d(1.35, 0, 0), Eigen::Vector3d::Constant(0.01)));
  EXPECT_THROW((void)g.value(Eigen::Vector3d(1.35, 0, 0), 0, near), OptionError);
  EXPECT_THROW((void)g.sample(Eigen::Vector3d(1.35, 0, 0), near), OptionError);
}
