// select / subsample / voxel_downsample: counts, determinism, order, and voxel means checked on
// hand-built and random clouds.

#include "test_support.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/resample.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <tuple>
#include <vector>

namespace clustersurf {
namespace {

/// A cloud whose point i is (i, 2i, -i) with a distinct normal and color, so that an output
/// row tells which input row it came from.
PointCloud indexed_cloud(int n) {
  PointCloud c;
  c.positions.resize(n, 3);
  c.normals.resize(n, 3);
  c.colors.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    c.positions.row(i) << i, 2.0 * i, -i;
    c.normals.row(i) = Eigen::Vector3d(std::cos(i), std::sin(i), 0).transpose();
    c.colors.row(i) << static_cast<std::uint8_t>(i % 256), static_cast<std::uint8_t>((i / 256) % 256), 7;
  }
  return c;
}

/// The input indices of the rows of `sub` (taken from x = i).
std::vector<Eigen::Index> source_indices(const PointCloud& sub) {
  std::vector<Eigen::Index> idx;
  for (Eigen::Index r = 0; r < sub.size(); ++r) idx.push_back(static_cast<Eigen::Index>(sub.positions(r, 0)));
  return idx;
}

TEST(Select, RowsOfEveryAttributeInTheGivenOrder) {
  const PointCloud c = indexed_cloud(10);
  const PointCloud s = select(c, {7, 2, 2, 9});
  ASSERT_EQ(s.size(), 4);
  const std::vector<Eigen::Index> want = {7, 2, 2, 9};
  for (Eigen::Index r = 0; r < 4; ++r) {
    const Eigen::Index i = want[static_cast<std::size_t>(r)];
    EXPECT_EQ(s.positions.row(r), c.positions.row(i));
    EXPECT_EQ(s.normals.row(r), c.normals.row(i));
    EXPECT_EQ(s.colors.row(r), c.colors.row(i));
  }
  PointCloud bare;
  bare.positions = c.positions;
  const PointCloud b = select(bare, {1});
  EXPECT_FALSE(b.has_normals());
  EXPECT_FALSE(b.has_colors());
  EXPECT_TRUE(select(c, {}).empty());
}

TEST(Subsample, ExactCountSubsetInInputOrderWithAttributes) {
  const PointCloud c = indexed_cloud(1000);
  for (std::size_t count : {1, 2, 10, 250, 999}) {
    for (std::uint64_t seed : {1, 2, 12345}) {
      SCOPED_TRACE("count " + std::to_string(count) + " seed " + std::to_string(seed));
      const PointCloud s = subsample(c, count, seed);
      ASSERT_EQ(s.size(), static_cast<Eigen::Index>(count));
      const auto idx = source_indices(s);
      EXPECT_TRUE(std::is_sorted(idx.begin(), idx.end()));
      EXPECT_EQ(std::adjacent_find(idx.begin(), idx.end()), idx.end()) << "no repeats";
      for (Eigen::Index r = 0; r < s.size(); ++r) {
        const Eigen::Index i = idx[static_cast<std::size_t>(r)];
        ASSERT_GE(i, 0);
        ASSERT_LT(i, c.size());
        EXPECT_EQ(s.positions.row(r), c.positions.row(i));
        EXPECT_EQ(s.normals.row(r), c.normals.row(i));
        EXPECT_EQ(s.colors.row(r), c.colors.row(i));
      }
    }
  }
}

TEST(Subsample, DeterministicPerSeed) {
  const PointCloud c = indexed_cloud(5000);
  const PointCloud a = subsample(c, 100, 42), b = subsample(c, 100, 42), d = subsample(c, 100, 43);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.colors, b.colors);
  EXPECT_NE(source_indices(a), source_indices(d));
  // The default seed is a fixed one too.
  EXPECT_EQ(subsample(c, 100).positions, subsample(c, 100).positions);
}

TEST(Subsample, CountAtLeastSizeKeepsEverythingAndZeroKeepsNothing) {
  const PointCloud c = indexed_cloud(30);
  for (std::size_t count : {30, 31, 1000000}) {
    const PointCloud s = subsample(c, count, 9);
    EXPECT_EQ(s.positions, c.positions);
    EXPECT_EQ(s.normals, c.normals);
    EXPECT_EQ(s.colors, c.colors);
  }
  EXPECT_TRUE(subsample(c, 0, 9).empty());
  EXPECT_TRUE(subsample(PointCloud{}, 5, 9).empty());
}

TEST(Subsample, EveryPointEquallyLikely) {
  // 100 points, keep 10, 3000 seeds: each index is expected 300 times (sd ~16.4).
  const PointCloud c = indexed_cloud(100);
  std::vector<int> hits(100, 0);
  for (std::uint64_t seed = 1; seed <= 3000; ++seed)
    for (Eigen::Index i : source_indices(subsample(c, 10, seed))) ++hits[static_cast<std::size_t>(i)];
  for (int i = 0; i < 100; ++i) {
    EXPECT_GT(hits[static_cast<std::size_t>(i)], 300 - 100) << "index " << i;
    EXPECT_LT(hits[static_cast<std::size_t>(i)], 300 + 100) << "index " << i;
  }
}

// ---------------------------------------------------------------------------------------------

struct Pt {
  Eigen::Vector3d p, n;
  std::array<int, 3> c;
};

PointCloud make_cloud(const std::vector<Pt>& pts) {
  PointCloud c;
  const auto n = static_cast<Eigen::Index>(pts.size());
  c.positions.resize(n, 3);
  c.normals.resize(n, 3);
  c.colors.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Pt& q = pts[static_cast<std::size_t>(i)];
    c.positions.row(i) = q.p.transpose();
    c.normals.row(i) = q.n.transpose();
    for (int k = 0; k < 3; ++k) c.colors(i, k) = static_cast<std::uint8_t>(q.c[static_cast<std::size_t>(k)]);
  }
  return c;
}

TEST(VoxelDownsample, MeanOfEachVoxelOnAConstructedCase) {
  // Voxel size 1, grid anchored at the bbox minimum (0, 0, 0) (the first point).
  const std::vector<Pt> pts = {
      {{0, 0, 0}, {1, 0, 0}, {10, 20, 30}},           // voxel (0,0,0)
      {{1.5, 0.5, 0.5}, {0, 0, 1}, {100, 100, 100}},  // voxel (1,0,0)
      {{0.5, 0.5, 0.5}, {0, 1, 0}, {11, 21, 31}},     // voxel (0,0,0)
      {{0.5, 1.5, 0.25}, {0, 0, -2}, {0, 0, 0}},      // voxel (0,1,0), normal not unit
      {{0.25, 0.75, 0.5}, {0, 1, 0}, {12, 22, 32}},   // voxel (0,0,0)
      {{1.25, 0.25, 0.75}, {0, 0, 1}, {200, 0, 50}},  // voxel (1,0,0)
      {{0.5, 0.5, 2.5}, {1, 0, 0}, {1, 2, 3}},        // voxel (0,0,2)
      {{1.0, 0.0, 0.0}, {0, 0, 1}, {0, 0, 0}},        // on the boundary: voxel (1,0,0)
  };
  const PointCloud out = voxel_downsample(make_cloud(pts), 1.0);
  ASSERT_EQ(out.size(), 4);
  ASSERT_TRUE(out.has_normals());
  ASSERT_TRUE(out.has_colors());
  // Ordered by voxel with x fastest: (0,0,0), (1,0,0), (0,1,0), (0,0,2).
  const Points want = (Points(4, 3) << (0 + 0.5 + 0.25) / 3, (0 + 0.5 + 0.75) / 3, (0 + 0.5 + 0.5) / 3,  //
                       (1.5 + 1.25 + 1.0) / 3, (0.5 + 0.25 + 0) / 3, (0.5 + 0.75 + 0) / 3,               //
                       0.5, 1.5, 0.25,                                                                   //
                       0.5, 0.5, 2.5)
                          .finished();
  for (Eigen::Index r = 0; r < 4; ++r)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.positions(r, k), want(r, k), 1e-15) << r << "," << k;
  // Normals: normalized sums.
  const Eigen::Vector3d n0 = Eigen::Vector3d(1, 2, 0).normalized();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.normals(0, k), n0[k], 1e-15);
  EXPECT_NEAR(out.normals(1, 2), 1.0, 1e-15);
  EXPECT_NEAR(out.normals(2, 2), -1.0, 1e-15) << "a single non-unit normal is normalized";
  for (Eigen::Index r = 0; r < 4; ++r) EXPECT_NEAR(out.normals.row(r).norm(), 1.0, 1e-14);
  // Colors: rounded means.
  EXPECT_EQ(out.colors(0, 0), 11);
  EXPECT_EQ(out.colors(0, 1), 21);
  EXPECT_EQ(out.colors(0, 2), 31);
  EXPECT_EQ(out.colors(1, 0), 100);  // (100 + 200 + 0) / 3
  EXPECT_EQ(out.colors(1, 1), 33);   // 33.33
  EXPECT_EQ(out.colors(1, 2), 50);
  EXPECT_EQ(out.colors(3, 2), 3);
}

TEST(VoxelDownsample, IndependentOfInputOrder) {
  PointCloud c = test::sample_torus(3000);
  c.colors.resize(c.size(), 3);
  for (Eigen::Index i = 0; i < c.size(); ++i) c.colors.row(i) << static_cast<std::uint8_t>(i % 251), 3, 250;
  std::vector<Eigen::Index> perm(static_cast<std::size_t>(c.size()));
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937_64(3));
  const PointCloud a = voxel_downsample(c, 0.1);
  const PointCloud b = voxel_downsample(select(c, perm), 0.1);
  ASSERT_EQ(a.size(), b.size());
  // Sums run in a different order, so positions agree to rounding only.
  EXPECT_LT((a.positions - b.positions).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((a.normals - b.normals).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(a.colors, b.colors);
}

TEST(VoxelDownsample, RandomCloudAgainstBruteForce) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-3.0, 5.0);
  const int n = 5000;
  PointCloud c;
  c.positions.resize(n, 3);
  c.normals.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    c.positions.row(i) << u(rng), u(rng) * 0.5, u(rng) * 0.1;
    c.normals.row(i) = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized().transpose();
  }
  const double size = 0.7;
  const BoundingBox box = bounding_box(c.positions);
  using Key = std::tuple<std::int64_t, std::int64_t, std::int64_t>;  // (z, y, x)
  std::map<Key, std::pair<Eigen::Vector3d, int>> voxels;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = c.positions.row(i).transpose();
    const Eigen::Vector3d cell = ((p - box.min) / size).array().floor();
    auto& v = voxels[Key{static_cast<std::int64_t>(cell.z()), static_cast<std::int64_t>(cell.y()),
                         static_cast<std::int64_t>(cell.x())}];
    if (v.second == 0) v.first.setZero();
    v.first += p;
    ++v.second;
  }
  const PointCloud out = voxel_downsample(c, size);
  ASSERT_EQ(out.size(), static_cast<Eigen::Index>(voxels.size()));
  EXPECT_FALSE(out.has_colors());
  Eigen::Index r = 0;
  for (const auto& [key, v] : voxels) {
    const Eigen::Vector3d mean = v.first / v.second;
    EXPECT_LT((out.positions.row(r).transpose() - mean).norm(), 1e-12) << "voxel " << r;
    // The mean lies in its voxel.
    const Eigen::Vector3d lo =
        box.min + size * Eigen::Vector3d(static_cast<double>(std::get<2>(key)), static_cast<double>(std::get<1>(key)),
                                         static_cast<double>(std::get<0>(key)));
    EXPECT_TRUE(((mean - lo).array() >= -1e-12).all() && ((mean - lo).array() <= size + 1e-12).all());
    EXPECT_NEAR(out.normals.row(r).norm(), 1.0, 1e-12);
    ++r;
  }
}

TEST(VoxelDownsample, OpposingNormalsStayFiniteAndOneVoxelForALargeSize) {
  const std::vector<Pt> pts = {{{0, 0, 0}, {1, 0, 0}, {0, 0, 0}}, {{0.1, 0, 0}, {-1, 0, 0}, {0, 0, 0}}};
  const PointCloud out = voxel_downsample(make_cloud(pts), 1.0);
  ASSERT_EQ(out.size(), 1);
  EXPECT_TRUE(out.normals.allFinite());
  EXPECT_NEAR(out.positions(0, 0), 0.05, 1e-15);
  const PointCloud big = voxel_downsample(indexed_cloud(100), 1e9);
  ASSERT_EQ(big.size(), 1);
  EXPECT_NEAR(big.positions(0, 0), 49.5, 1e-9);
  EXPECT_TRUE(voxel_downsample(PointCloud{}, 1.0).empty());
}

TEST(VoxelDownsample, InvalidSizeThrowsOptionError) {
  const PointCloud c = indexed_cloud(10);
  for (double s : {0.0, -1.0, -0.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity()}) {
    EXPECT_THROW((void)voxel_downsample(c, s), OptionError) << s;
  }
  // A size so small the grid cannot be indexed.
  PointCloud wide;
  wide.positions.resize(2, 3);
  wide.positions << 0, 0, 0, 1e6, 1e6, 1e6;
  EXPECT_THROW((void)voxel_downsample(wide, 1e-9), OptionError);
}

}  // namespace
}  // namespace clustersurf
