// halves_drops(): noise alone leaves drops within halves_drop_bound(), a misfit a quadratic per
// half follows exceeds it along the axis it varies on, the weights scale both, and the halves'
// spread across the plane is measured.

#include "cluster/halves_test.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// n points uniform over [0, 1]², z = height(x), Gaussian noise sigma on every coordinate.
Points sheet(int n, double sigma, const std::function<double(double)>& height, std::uint64_t seed) {
  return test::noisy_heightfield(
             n, sigma, [&](double x, double) { return height(x); }, seed)
      .positions;
}

}  // namespace

TEST(HalvesTest, NoiseAloneStaysWithinTheBound) {
  constexpr double kSigma = 0.01;
  const double bound = detail::halves_drop_bound(kSigma);
  int over = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Points p = sheet(
        400, kSigma, [](double) { return 0.0; }, seed);
    for (const detail::HalvesDrop& d : detail::halves_drops(p, test::all_rows(p.rows()), {}, Frame{})) {
      EXPECT_GE(d.drop, 0);
      over += d.drop > bound;
    }
  }
  EXPECT_LE(over, 4);  // 40 tests at a 2-deviation quantile: about one expected
}

TEST(HalvesTest, AMisfitTheHalvesFollowExceedsTheBoundAlongItsAxis) {
  // A cubic in x, 0.3 σ (RMS) from the best quadratic: no residual's spread shows it over 400
  // points (the margin is 2 √(2/400) = 0.14 of the variance, 0.37 σ).
  constexpr double kSigma = 0.01;
  const Points p = sheet(
      400, kSigma, [](double x) { return 0.16 * std::pow(x - 0.5, 3); }, 3);
  const auto drops = detail::halves_drops(p, test::all_rows(p.rows()), {}, Frame{});
  EXPECT_GT(drops[0].drop, detail::halves_drop_bound(kSigma));
  EXPECT_LT(drops[1].drop, detail::halves_drop_bound(kSigma));
  // Halves of the unit square along x: variance 1/48 along x, 1/12 along y.
  EXPECT_NEAR(drops[0].spread, 1.0 / 48, 0.004);
}

TEST(HalvesTest, WeightsScaleTheDropAndTheBound) {
  constexpr double kSigma = 0.01;
  const Points p = sheet(
      400, kSigma, [](double) { return 0.0; }, 5);
  const std::vector<double> halves_weight(400, 0.5);
  const auto unit = detail::halves_drops(p, test::all_rows(p.rows()), {}, Frame{});
  const auto half = detail::halves_drops(p, test::all_rows(p.rows()), halves_weight, Frame{});
  EXPECT_NEAR(half[0].drop, 0.5 * unit[0].drop, 1e-12);
  EXPECT_DOUBLE_EQ(detail::halves_drop_bound(kSigma, 0.5), 0.5 * detail::halves_drop_bound(kSigma));
  const std::vector<std::uint32_t> one{0};
  EXPECT_EQ(detail::halves_drops(p, one, {}, Frame{})[0].drop, 0);
}
