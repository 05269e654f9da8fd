// Normals estimated from positions alone (src/spatial/normal_estimation.cpp): exact on a plane,
// close to the true normal on a noisy sphere, zero where the neighbours span no plane, and the
// same whatever the thread count.

#include <clustersurf/spatial/normal_estimation.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <tbb/global_control.h>

#include <cmath>
#include <random>

using namespace clustersurf;

namespace {

/// `n` points on the unit sphere, with Gaussian noise of standard deviation `sigma` on every
/// coordinate.
Points noisy_sphere(int n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, 1), noise(0, sigma);
  Points p(n, 3);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d d(g(rng), g(rng), g(rng));
    d.normalize();
    p.row(i) = (d + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))).transpose();
  }
  return p;
}

}  // namespace

TEST(NormalEstimation, TiltedPlaneGivesItsNormalInTheCanonicalSign) {
  const Eigen::Vector3d normal = Eigen::Vector3d(1, -2, -3).normalized();
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> s(-1, 1);
  Points p(500, 3);
  for (Eigen::Index i = 0; i < p.rows(); ++i) p.row(i) = (s(rng) * u + s(rng) * v + 0.5 * normal).transpose();
  const KdTree index(p);
  const Points n = estimate_unoriented_normals(index, 30, static_cast<std::size_t>(p.rows()));
  ASSERT_EQ(n.rows(), p.rows());
  for (Eigen::Index i = 0; i < n.rows(); ++i) {
    // The largest component (z's, −3) is made positive: the normal comes out as −normal.
    EXPECT_NEAR(n.row(i).dot(-normal), 1.0, 1e-9) << "point " << i;
  }
}

TEST(NormalEstimation, NoisySphereNormalsAreRadial) {
  const Points p = noisy_sphere(20000, 0.002, 2);
  const KdTree index(p);
  const Points n = estimate_unoriented_normals(index, 30, static_cast<std::size_t>(p.rows()));
  double sum = 0;
  for (Eigen::Index i = 0; i < n.rows(); ++i) {
    const double c = std::abs(n.row(i).dot(p.row(i).normalized()));
    sum += std::acos(std::min(1.0, c));
  }
  const double mean_degrees = sum / static_cast<double>(n.rows()) * 180 / M_PI;
  // 30 neighbours span about 0.08 radians of the sphere: noise 0.002 tilts their plane by a
  // few degrees at most.
  EXPECT_LT(mean_degrees, 3.0);
}

TEST(NormalEstimation, PointsOnALineOrTooFewGetZero) {
  Points line(10, 3);
  for (Eigen::Index i = 0; i < line.rows(); ++i) line.row(i) << static_cast<double>(i), 2.0 * static_cast<double>(i), 0;
  const KdTree on_line(line);
  EXPECT_EQ(estimate_unoriented_normals(on_line, 30, 10), Points::Zero(10, 3));
  Points two(2, 3);
  two << 0, 0, 0, 1, 0, 0;
  const KdTree few(two);
  std::vector<Neighbor> scratch;
  EXPECT_EQ(unoriented_normal(few, Eigen::Vector3d::Zero(), 30, scratch), Eigen::Vector3d::Zero());
}

TEST(NormalEstimation, SameNormalsForOneAndTwoThreads) {
  const Points p = noisy_sphere(30000, 0.01, 3);
  const KdTree index(p);
  Points one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = estimate_unoriented_normals(index, 30, 20000);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = estimate_unoriented_normals(index, 30, 20000);
  }
  ASSERT_EQ(one.rows(), 20000);
  EXPECT_EQ(one, two);
}
