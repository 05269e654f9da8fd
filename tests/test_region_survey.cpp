// A region's survey: the scale its points give the cloud, read as the whole cloud reads it.

#include <clustersurf/cluster/noise.hpp>
#include <clustersurf/regions/regions.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>

#include <gtest/gtest.h>

#include <vector>

#include "test_support.hpp"

using namespace clustersurf;

TEST(RegionSurvey, SmallRegionsReadTheWholeCloudsNoise) {
  // 400 k points on a unit sphere are about 3 mm apart; under 20 mm of noise the whole cloud's
  // estimate coarsens its sample three times before its neighbourhoods are wide enough. Regions
  // of at most 25 k points must read the noise at that scale too, not at their own count's.
  PointCloud c = test::sample_sphere(400000, 1.0);
  test::add_normal_noise(c, 0.02, 11);
  const auto total = static_cast<std::uint64_t>(c.size());
  const double whole = estimate_noise(c.positions);
  EXPECT_NEAR(whole, 0.02, 0.0015);

  RegionOptions small;
  small.max_points = 25000;
  small.halo_spacings = 0;
  const RegionPlan plan = plan_regions(c.positions, total, bounding_box(c.positions), 0.003, small);
  ASSERT_GE(plan.regions(), 16u);
  EXPECT_EQ(plan.points, total);
  std::vector<std::vector<Eigen::Index>> rows(plan.regions());
  for (Eigen::Index i = 0; i < c.size(); ++i)
    rows[static_cast<std::size_t>(plan.region_of(c.positions.row(i).transpose()))].push_back(i);
  std::vector<RegionSurvey> surveys;
  for (const std::vector<Eigen::Index>& own : rows) {
    RegionCloud region;
    region.points.positions = c.positions(own, Eigen::all);
    region.own = own.size();
    surveys.push_back(survey_region(region, plan.points));
  }
  const CloudScale scale = combine_surveys(surveys);
  EXPECT_EQ(scale.points, total);
  EXPECT_NEAR(scale.noise_sigma, whole, 0.05 * whole);
}
