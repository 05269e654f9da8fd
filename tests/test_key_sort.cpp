// Sorting by key in linear time: the same order as a comparison sort of the (key, index) pairs.

#include "cluster/key_sort.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace clustersurf::detail;

namespace {

/// Keys as a split's projections are: a narrow band far from zero, many of them equal, and
/// indices in no order.
std::vector<KeyedIndex> projections(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(3.0, 0.01);
  std::vector<KeyedIndex> items(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double key = k % 7 == 0 ? 3.0 : g(rng);  // every seventh key the same
    items[k] = {key, static_cast<std::uint32_t>(rng() % (4 * n + 1))};
  }
  return items;
}

void expect_same_order_as_std_sort(std::vector<KeyedIndex> items) {
  std::vector<KeyedIndex> expected = items;
  std::sort(expected.begin(), expected.end());
  sort_by_key(items);
  ASSERT_EQ(items.size(), expected.size());
  for (std::size_t k = 0; k < items.size(); ++k) {
    ASSERT_EQ(items[k].second, expected[k].second) << "at " << k;
    ASSERT_EQ(items[k].first, expected[k].first) << "at " << k;
  }
}

}  // namespace

TEST(KeySort, SameOrderAsComparisonSortAtEverySize) {
  for (const std::size_t n : {0, 1, 2, 100, 2047, 2048, 2049, 5000, 70000})
    expect_same_order_as_std_sort(projections(n, n));
}

TEST(KeySort, EqualKeysGoByIndex) {
  std::vector<KeyedIndex> items;
  for (std::uint32_t k = 0; k < 5000; ++k) items.push_back({k % 3 == 0 ? -1.5 : 2.5, (k * 2654435761u) % 100003});
  expect_same_order_as_std_sort(items);
}

TEST(KeySort, SignsMagnitudesAndZeros) {
  std::mt19937_64 rng(3);
  const double special[] = {0.0,
                            -0.0,
                            std::numeric_limits<double>::denorm_min(),
                            -std::numeric_limits<double>::denorm_min(),
                            1e-300,
                            -1e-300,
                            1e300,
                            -1e300,
                            std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::lowest()};
  std::vector<KeyedIndex> items;
  for (std::uint32_t k = 0; k < 6000; ++k) {
    const double key =
        k % 5 == 0 ? special[rng() % std::size(special)]
                   : std::ldexp(static_cast<double>(rng() % 2001) - 1000.0, static_cast<int>(rng() % 200) - 100);
    items.push_back({key, static_cast<std::uint32_t>(rng())});
  }
  std::vector<KeyedIndex> sorted = items;
  sort_by_key(sorted);
  // −0 and +0 are one key, ordered by index among themselves, and −0 comes back as +0.
  for (std::size_t k = 1; k < sorted.size(); ++k) {
    const auto& [a, i] = sorted[k - 1];
    const auto& [b, j] = sorted[k];
    ASSERT_TRUE(a < b || (a == b && i < j) || (a == b && i == j)) << "at " << k;
  }
  for (const auto& [key, index] : sorted) EXPECT_FALSE(key == 0 && std::signbit(key)) << "index " << index;
  expect_same_order_as_std_sort(items);
}
