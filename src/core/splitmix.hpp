#pragma once
// The splitmix64 finalizer: a fast bijective mix of 64-bit integers, for seeds and hashes that
// must be the same on every machine.

#include <cstdint>

namespace clustersurf::detail {

/// Mixes the bits of x (Steele, Lea & Flood 2014); consecutive inputs give unrelated outputs.
constexpr std::uint64_t splitmix64(std::uint64_t x) noexcept {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Whether point `index` belongs to the nested random subsample of level `level`: about 4^-level
/// of the points, each level inside the previous one (the same subsets everywhere they are used).
constexpr bool in_subsample(std::uint64_t index, unsigned level) noexcept {
  return (splitmix64(index) & ((std::uint64_t{1} << (2 * level)) - 1)) == 0;
}

}  // namespace clustersurf::detail
