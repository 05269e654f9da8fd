#pragma once
// Sorting points by a scalar key (their projection on a split direction) in linear time.

#include <cstdint>
#include <utility>
#include <vector>

namespace clustersurf::detail {

/// A point's key and its index.
using KeyedIndex = std::pair<double, std::uint32_t>;

/// Sorts `items` by key, ties by index: the order std::sort gives the pairs, for keys that are
/// not NaN (−0 and +0 are one key, and a −0 comes back as +0). A least-significant-digit radix
/// sort of the keys' bits, linear in the size (runs of equal keys are then ordered by index by a
/// comparison sort); short vectors go to std::sort.
void sort_by_key(std::vector<KeyedIndex>& items);

}  // namespace clustersurf::detail
