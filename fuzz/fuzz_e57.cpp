// libFuzzer target: the E57 reader. Each input is tried as it is (the page CRCs reject almost
// every mutation) and made consistent again (padded to whole pages, the header's file length
// and every page's CRC-32C rewritten), so that the fuzzer reaches the XML, section, packet and
// bytestream checks.

#include "fuzz_checks.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace {

/// CRC-32C, bit by bit (independent of the reader's).
std::uint32_t crc32c(const char* p, std::size_t n) {
  std::uint32_t c = 0xFFFFFFFFU;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= static_cast<unsigned char>(p[i]);
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ ((c & 1U) != 0 ? 0x82F63B78U : 0U);
  }
  return c ^ 0xFFFFFFFFU;
}

/// The page size the header claims, when the reader accepts it and it is at most 16 KiB (else 0).
std::size_t page_size(const std::string& s) {
  if (s.size() < 48) return 0;
  std::uint64_t ps = 0;
  for (int i = 7; i >= 0; --i) ps = (ps << 8) | static_cast<unsigned char>(s[40 + static_cast<std::size_t>(i)]);
  if (ps < 64 || ps > 16384 || (ps & (ps - 1)) != 0) return 0;  // inputs are at most 16 KiB
  return static_cast<std::size_t>(ps);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using clustersurf::FileFormat;
  clustersurf::fuzz::parse_everything(data, size, FileFormat::E57, "fuzz.e57", false);
  std::string fixed(reinterpret_cast<const char*>(data), size);
  const std::size_t ps = page_size(fixed);
  if (ps == 0) return 0;
  // Whole pages, the header's file length and every page's CRC made consistent.
  fixed.resize((fixed.size() + ps - 1) / ps * ps, '\0');
  for (std::size_t i = 0; i < 8; ++i) fixed[16 + i] = static_cast<char>((fixed.size() >> (8 * i)) & 0xFF);
  for (std::size_t p = 0; p < fixed.size(); p += ps) {
    const std::uint32_t c = crc32c(fixed.data() + p, ps - 4);
    for (std::size_t i = 0; i < 4; ++i) fixed[p + ps - 4 + i] = static_cast<char>(c >> (24 - 8 * i));
  }
  return clustersurf::fuzz::parse_everything(reinterpret_cast<const std::uint8_t*>(fixed.data()), fixed.size(),
                                             FileFormat::E57, "fuzz.e57", false);
}
