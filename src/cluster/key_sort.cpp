#include "cluster/key_sort.hpp"

#include <algorithm>
#include <array>
#include <bit>

namespace clustersurf::detail {

namespace {

/// Below this size a comparison sort is as fast.
constexpr std::size_t kRadixMin = 2048;
/// The largest scratch a thread keeps between sorts: the sweeps sort at most 65,536 points.
constexpr std::size_t kMaxKeptScratch = std::size_t{1} << 16;
constexpr int kDigitBits = 11;
constexpr int kDigits = (64 + kDigitBits - 1) / kDigitBits;
constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;

/// The bits of a key as an unsigned integer of the same order: the sign bit set for positive
/// keys, every bit flipped for negative ones.
std::uint64_t ordered_bits(double key) {
  const auto u = std::bit_cast<std::uint64_t>(key + 0.0);  // −0 + 0 is +0
  return u >> 63 ? ~u : u | std::uint64_t{1} << 63;
}

double key_of(std::uint64_t bits) {
  return std::bit_cast<double>(bits >> 63 ? bits & ~(std::uint64_t{1} << 63) : ~bits);
}

struct Item {
  std::uint64_t bits;
  std::uint32_t index;
};

}  // namespace

void sort_by_key(std::vector<KeyedIndex>& items) {
  const std::size_t n = items.size();
  if (n < kRadixMin) {
    std::sort(items.begin(), items.end());
    return;
  }
  // Scratch reused by the thread's later sorts: a large fresh allocation costs more in page
  // faults than the sort itself.
  thread_local std::vector<Item> a, b;
  a.resize(n);
  b.resize(n);
  std::array<std::array<std::uint32_t, kBuckets>, kDigits> counts{};
  for (std::size_t k = 0; k < n; ++k) {
    a[k] = {ordered_bits(items[k].first), items[k].second};
    for (int d = 0; d < kDigits; ++d) ++counts[d][(a[k].bits >> (d * kDigitBits)) & (kBuckets - 1)];
  }
  // One stable counting pass per digit, least significant first; a digit that every key
  // shares moves nothing and is skipped.
  for (int d = 0; d < kDigits; ++d) {
    auto& count = counts[d];
    if (count[(a[0].bits >> (d * kDigitBits)) & (kBuckets - 1)] == n) continue;
    std::uint32_t offset = 0;
    for (auto& c : count) offset += std::exchange(c, offset);
    for (const Item& item : a) b[count[(item.bits >> (d * kDigitBits)) & (kBuckets - 1)]++] = item;
    a.swap(b);
  }
  // Equal keys keep their input order: order each run of them by index.
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin + 1;
    while (end < n && a[end].bits == a[begin].bits) ++end;
    if (end - begin > 1)
      std::sort(a.begin() + static_cast<std::ptrdiff_t>(begin), a.begin() + static_cast<std::ptrdiff_t>(end),
                [](const Item& x, const Item& y) { return x.index < y.index; });
    begin = end;
  }
  for (std::size_t k = 0; k < n; ++k) items[k] = {key_of(a[k].bits), a[k].index};
  // Larger sorts (a sweep's rare fallback to every point) free theirs.
  if (a.capacity() > kMaxKeptScratch) a = {}, b = {};
}

}  // namespace clustersurf::detail
