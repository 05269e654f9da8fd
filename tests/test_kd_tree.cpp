// KdTree: knn and radius queries against brute force on random and tie-heavy data, ordering
// (distance, then index), edge cases, and concurrent queries.

#include "test_support.hpp"

#include <clustersurf/spatial/kd_tree.hpp>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <random>
#include <vector>

namespace clustersurf {
namespace {

/// Squared distance computed like nanoflann's L2 adaptor (so ties compare exactly).
double dist2(const Points& p, Eigen::Index i, const Eigen::Vector3d& q) {
  double d = 0;
  for (int c = 0; c < 3; ++c) {
    const double t = p(i, c) - q[c];
    d += t * t;
  }
  return d;
}

bool closer(const Neighbor& a, const Neighbor& b) {
  return a.distance_squared < b.distance_squared || (a.distance_squared == b.distance_squared && a.index < b.index);
}

std::vector<Neighbor> brute_all(const Points& p, const Eigen::Vector3d& q) {
  std::vector<Neighbor> all;
  for (Eigen::Index i = 0; i < p.rows(); ++i) all.push_back({static_cast<std::uint32_t>(i), dist2(p, i, q)});
  std::sort(all.begin(), all.end(), closer);
  return all;
}

std::vector<Neighbor> first_k(const std::vector<Neighbor>& all, std::size_t k) {
  return {all.begin(), all.begin() + static_cast<std::ptrdiff_t>(std::min(k, all.size()))};
}
std::vector<Neighbor> within(const std::vector<Neighbor>& all, double r) {
  std::vector<Neighbor> out;
  for (const auto& n : all)
    if (n.distance_squared <= r * r) out.push_back(n);
  return out;
}
std::vector<Neighbor> brute_knn(const Points& p, const Eigen::Vector3d& q, std::size_t k) {
  return first_k(brute_all(p, q), k);
}
std::vector<Neighbor> brute_radius(const Points& p, const Eigen::Vector3d& q, double r) {
  return within(brute_all(p, q), r);
}

::testing::AssertionResult same(const std::vector<Neighbor>& got, const std::vector<Neighbor>& want) {
  if (got.size() != want.size()) return ::testing::AssertionFailure() << "size " << got.size() << " vs " << want.size();
  for (std::size_t i = 0; i < got.size(); ++i)
    if (got[i].index != want[i].index || got[i].distance_squared != want[i].distance_squared)
      return ::testing::AssertionFailure()
             << "at " << i << ": index " << got[i].index << " d2 " << got[i].distance_squared << " vs index "
             << want[i].index << " d2 " << want[i].distance_squared;
  return ::testing::AssertionSuccess();
}

/// Uniform points in the unit cube.
Points random_points(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Points p(n, 3);
  for (int i = 0; i < n; ++i) p.row(i) << u(rng), u(rng), u(rng);
  return p;
}

/// Points on a coarse grid of exact binary fractions (many exactly equal distances) with every
/// point present several times at scattered indices (duplicates).
Points tie_heavy_points(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> cell(0, 7);
  Points p(n, 3);
  for (int i = 0; i < n; ++i) p.row(i) << cell(rng) / 8.0, cell(rng) / 8.0, cell(rng) / 8.0;
  // Copy some rows elsewhere so exact duplicates are frequent and far apart in index.
  std::uniform_int_distribution<int> row(0, n - 1);
  for (int k = 0; k < n / 4; ++k) p.row(row(rng)) = p.row(row(rng)).eval();
  return p;
}

std::vector<Eigen::Vector3d> queries(const Points& p, int extra, unsigned seed, bool on_grid) {
  std::mt19937_64 rng(seed * 77 + 1);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  std::uniform_int_distribution<int> cell(-1, 8);
  std::vector<Eigen::Vector3d> q;
  for (Eigen::Index i = 0; i < p.rows(); i += 37) q.push_back(p.row(i).transpose());  // at data points
  for (int i = 0; i < extra; ++i)
    q.push_back(on_grid
                    ? Eigen::Vector3d(cell(rng) / 8.0, cell(rng) / 8.0, cell(rng) / 8.0) + Eigen::Vector3d(0.0625, 0, 0)
                    : Eigen::Vector3d(u(rng), u(rng), u(rng)));
  return q;
}

class KdTreeBruteForce : public ::testing::TestWithParam<std::tuple<unsigned, bool>> {};

TEST_P(KdTreeBruteForce, KnnAndRadiusMatch) {
  const auto [seed, ties] = GetParam();
  const Points p = ties ? tie_heavy_points(1500, seed) : random_points(3000, seed);
  const auto qs = queries(p, 150, seed, ties);
  std::vector<std::vector<Neighbor>> sorted;
  for (const auto& q : qs) sorted.push_back(brute_all(p, q));
  for (int leaf : {1, 10, 64}) {
    const KdTree tree(p, leaf);
    ASSERT_EQ(tree.size(), static_cast<std::size_t>(p.rows()));
    EXPECT_EQ(&tree.points(), &p);
    std::vector<Neighbor> reused;
    for (std::size_t j = 0; j < qs.size(); ++j) {
      const Eigen::Vector3d& q = qs[j];
      for (std::size_t k : {1, 5, 32}) {
        const auto want = first_k(sorted[j], k);
        ASSERT_TRUE(same(tree.knn(q, k), want)) << "leaf " << leaf << " query " << j << " k " << k;
        tree.knn(q, k, reused);
        ASSERT_TRUE(same(reused, want)) << "reused buffer, leaf " << leaf << " query " << j << " k " << k;
      }
      for (double r : {0.0, 0.05, 0.125, 0.2}) {
        const auto want = within(sorted[j], r);
        ASSERT_TRUE(same(tree.radius(q, r), want)) << "leaf " << leaf << " query " << j << " r " << r;
        // The unsorted variant finds the same set (same distances), in some order.
        tree.radius_unsorted(q, r, reused);
        std::sort(reused.begin(), reused.end(), closer);
        ASSERT_TRUE(same(reused, want)) << "unsorted, leaf " << leaf << " query " << j << " r " << r;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, KdTreeBruteForce, ::testing::Combine(::testing::Values(1u, 2u, 3u), ::testing::Bool()),
                         [](const auto& info) {
                           return "seed" + std::to_string(std::get<0>(info.param)) +
                                  (std::get<1>(info.param) ? "_ties" : "_random");
                         });

TEST(KdTree, DuplicatesResolveByIndexWhateverTheTree) {
  // 40 copies of one point among others: the k nearest of that point are the k lowest indices
  // among the copies, for every k and leaf size.
  Points p = random_points(400, 9);
  std::vector<std::uint32_t> copies;
  for (Eigen::Index i = 3; i < 400; i += 10) {
    p.row(i) << 0.5, 0.5, 0.5;
    copies.push_back(static_cast<std::uint32_t>(i));
  }
  for (int leaf : {1, 4, 10, 50}) {
    const KdTree tree(p, leaf);
    for (std::size_t k : {1, 2, 3, 5, 17, 40}) {
      const auto nb = tree.knn(Eigen::Vector3d(0.5, 0.5, 0.5), k);
      ASSERT_EQ(nb.size(), k);
      for (std::size_t j = 0; j < k; ++j) {
        EXPECT_EQ(nb[j].index, copies[j]) << "leaf " << leaf << " k " << k;
        EXPECT_EQ(nb[j].distance_squared, 0.0);
      }
    }
    const auto r = tree.radius(Eigen::Vector3d(0.5, 0.5, 0.5), 0.0);
    ASSERT_EQ(r.size(), copies.size());
    for (std::size_t j = 0; j < r.size(); ++j) EXPECT_EQ(r[j].index, copies[j]);
  }
}

TEST(KdTree, EquidistantNeighboursOrderedByIndex) {
  // The 6 axis neighbours of the origin at distance 1, plus farther points, in scrambled order.
  Points p(10, 3);
  p << 3, 0, 0,  //
      0, 0, -1,  //
      2, 2, 2,   //
      1, 0, 0,   //
      0, -1, 0,  //
      0, 5, 0,   //
      0, 1, 0,   //
      -1, 0, 0,  //
      0, 0, 1,   //
      -4, 0, 0;
  const KdTree tree(p, 1);
  const auto nb = tree.knn(Eigen::Vector3d::Zero(), 4);
  ASSERT_EQ(nb.size(), 4u);
  const std::uint32_t expected[] = {1, 3, 4, 6};
  for (int j = 0; j < 4; ++j) EXPECT_EQ(nb[static_cast<std::size_t>(j)].index, expected[j]);
  // Radius is inclusive: distance exactly 1.
  const auto r = tree.radius(Eigen::Vector3d::Zero(), 1.0);
  ASSERT_EQ(r.size(), 6u);
  const std::uint32_t in_radius[] = {1, 3, 4, 6, 7, 8};
  for (int j = 0; j < 6; ++j) EXPECT_EQ(r[static_cast<std::size_t>(j)].index, in_radius[j]);
  EXPECT_EQ(tree.radius(Eigen::Vector3d::Zero(), std::nextafter(1.0, 0.0)).size(), 0u);
}

TEST(KdTree, KLargerThanSizeReturnsEverythingSorted) {
  const Points p = random_points(12, 4);
  const KdTree tree(p);
  const Eigen::Vector3d q(0.3, 0.3, 0.3);
  const auto nb = tree.knn(q, 100);
  EXPECT_TRUE(same(nb, brute_knn(p, q, 12)));
  EXPECT_TRUE(same(tree.knn(q, 12), brute_knn(p, q, 12)));
  EXPECT_TRUE(same(tree.knn(q, 13), brute_knn(p, q, 12)));
  EXPECT_TRUE(same(tree.radius(q, 10.0), brute_knn(p, q, 12)));
}

TEST(KdTree, EmptyResults) {
  const Points p = random_points(50, 5);
  const KdTree tree(p);
  const Eigen::Vector3d q(0.5, 0.5, 0.5);
  EXPECT_TRUE(tree.knn(q, 0).empty());
  std::vector<Neighbor> out(3, Neighbor{1, 1.0});
  tree.knn(q, 0, out);
  EXPECT_TRUE(out.empty()) << "the output buffer is cleared";
  EXPECT_TRUE(tree.radius(Eigen::Vector3d(10, 10, 10), 1.0).empty());
  EXPECT_TRUE(tree.radius(q, 0.0).empty());
  EXPECT_TRUE(tree.radius(q, -1.0).empty());
  EXPECT_TRUE(tree.radius(q, std::numeric_limits<double>::quiet_NaN()).empty());
  out.assign(3, Neighbor{1, 1.0});
  tree.radius_unsorted(q, -1.0, out);
  EXPECT_TRUE(out.empty()) << "the output buffer is cleared";
  out.assign(3, Neighbor{1, 1.0});
  tree.radius_unsorted(Eigen::Vector3d(10, 10, 10), 1.0, out);
  EXPECT_TRUE(out.empty());

  const Points none(0, 3);
  const KdTree empty(none);
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_TRUE(empty.knn(q, 5).empty());
  EXPECT_TRUE(empty.radius(q, 100.0).empty());
  empty.radius_unsorted(q, 100.0, out);
  EXPECT_TRUE(out.empty());
}

TEST(KdTree, SinglePointAndMove) {
  Points p(1, 3);
  p << 1, 2, 3;
  KdTree tree(p);
  const auto nb = tree.knn(Eigen::Vector3d(1, 2, 4), 3);
  ASSERT_EQ(nb.size(), 1u);
  EXPECT_EQ(nb[0].index, 0u);
  EXPECT_EQ(nb[0].distance_squared, 1.0);
  KdTree moved(std::move(tree));
  EXPECT_EQ(moved.knn(Eigen::Vector3d(1, 2, 4), 1).size(), 1u);
  KdTree other(random_points(5, 1));
  other = std::move(moved);
  EXPECT_EQ(other.size(), 1u);
}

TEST(KdTree, ConcurrentQueriesGiveTheSameAnswers) {
  const Points p = tie_heavy_points(4000, 11);
  const KdTree tree(p);
  std::vector<Eigen::Vector3d> qs;
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> cell(0, 8);
  for (int i = 0; i < 3000; ++i) qs.emplace_back(cell(rng) / 8.0, cell(rng) / 8.0, cell(rng) / 8.0);
  std::vector<std::vector<Neighbor>> serial_knn(qs.size()), serial_radius(qs.size());
  for (std::size_t i = 0; i < qs.size(); ++i) {
    serial_knn[i] = tree.knn(qs[i], 1 + i % 40);
    serial_radius[i] = tree.radius(qs[i], 0.125);
  }
  std::vector<std::vector<Neighbor>> unsorted(qs.size());
  std::atomic<int> mismatches{0};
  for (int round = 0; round < 3; ++round) {
    std::vector<std::vector<Neighbor>> par_knn(qs.size()), par_radius(qs.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, qs.size(), 16), [&](const auto& r) {
      std::vector<Neighbor> buf;  // per-task reused buffer
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        tree.knn(qs[i], 1 + i % 40, buf);
        par_knn[i] = buf;
        par_radius[i] = tree.radius(qs[i], 0.125);
        // Deterministic for a given tree: the same traversal order from any thread.
        tree.radius_unsorted(qs[i], 0.125, buf);
        if (round == 0)
          unsorted[i] = buf;
        else if (buf.size() != unsorted[i].size() ||
                 !std::equal(buf.begin(), buf.end(), unsorted[i].begin(),
                             [](const Neighbor& a, const Neighbor& b) { return a.index == b.index; }))
          mismatches.fetch_add(1);
      }
    });
    for (std::size_t i = 0; i < qs.size(); ++i) {
      ASSERT_TRUE(same(par_knn[i], serial_knn[i])) << "query " << i;
      ASSERT_TRUE(same(par_radius[i], serial_radius[i])) << "query " << i;
    }
  }
  EXPECT_EQ(mismatches.load(), 0) << "radius_unsorted order differs between runs";
  // And both agree with brute force on a sample.
  for (std::size_t i = 0; i < qs.size(); i += 97) {
    EXPECT_TRUE(same(serial_knn[i], brute_knn(p, qs[i], 1 + i % 40)));
    EXPECT_TRUE(same(serial_radius[i], brute_radius(p, qs[i], 0.125)));
  }
}

}  // namespace
}  // namespace clustersurf
