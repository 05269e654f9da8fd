// The banded deflate: any zlib reader inflates it to the input, bit for bit, for lengths at and
// around the band boundaries; its bytes do not depend on the thread count; it compresses an
// image's scanlines about as well as a one-piece deflate.

#include "render/banded_deflate.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <zlib.h>

#include <cstddef>
#include <random>
#include <vector>

using clustersurf::render::banded_deflate;

namespace {

constexpr std::size_t kBand = std::size_t{1} << 19;  // the band length of banded_deflate.cpp

/// Bytes that compress like a picture's filtered scanlines: long runs broken by noise.
std::vector<unsigned char> picture_like(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<unsigned char> out(n);
  unsigned char value = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (rng() % 64 == 0) value = static_cast<unsigned char>(rng());
    out[i] = rng() % 8 == 0 ? static_cast<unsigned char>(rng()) : value;
  }
  return out;
}

std::vector<unsigned char> inflate_all(const std::vector<unsigned char>& stream, std::size_t expected) {
  std::vector<unsigned char> out(expected + 1);
  uLongf size = static_cast<uLongf>(out.size());
  EXPECT_EQ(uncompress(out.data(), &size, stream.data(), static_cast<uLong>(stream.size())), Z_OK);
  out.resize(size);
  return out;
}

}  // namespace

TEST(BandedDeflate, InflatesToTheInputAtEveryBandBoundary) {
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, kBand - 1, kBand, kBand + 1, 3 * kBand + 7}) {
    const auto data = picture_like(n, static_cast<unsigned>(n));
    for (const int level : {1, 6, 9}) {
      const auto stream = banded_deflate(data, level);
      EXPECT_EQ(inflate_all(stream, n), data) << n << " bytes at level " << level;
    }
  }
}

TEST(BandedDeflate, IncompressibleDataRoundTrips) {
  std::mt19937 rng(7);
  std::vector<unsigned char> data(2 * kBand + 123);
  for (auto& b : data) b = static_cast<unsigned char>(rng());
  EXPECT_EQ(inflate_all(banded_deflate(data, 6), data.size()), data);
}

TEST(BandedDeflate, SameBytesForAnyThreadCount) {
  const auto data = picture_like(5 * kBand + 11, 3);
  std::vector<unsigned char> one, many;
  tbb::task_arena(1).execute([&] { one = banded_deflate(data, 6); });
  tbb::task_arena(4).execute([&] { many = banded_deflate(data, 6); });
  EXPECT_EQ(one, many);
}

TEST(BandedDeflate, CompressesAsWellAsOneDeflate) {
  const auto data = picture_like(6 * kBand, 5);
  uLongf size = compressBound(static_cast<uLong>(data.size()));
  std::vector<unsigned char> whole(size);
  ASSERT_EQ(compress2(whole.data(), &size, data.data(), static_cast<uLong>(data.size()), 6), Z_OK);
  const auto banded = banded_deflate(data, 6);
  // The dictionary priming keeps each band's start as well compressed as within one stream.
  EXPECT_LT(static_cast<double>(banded.size()), 1.002 * static_cast<double>(size));
}
