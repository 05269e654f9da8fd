// E57 file header, CRC-32C and paged (logical <-> physical) reads; see e57_pages.hpp.

#include "io/e57_pages.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

namespace clustersurf::io::e57 {

namespace {

/// The 256-entry table of the reflected CRC-32C polynomial, built at compile time.
constexpr std::array<std::uint32_t, 256> make_crc_table() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ ((c & 1U) != 0 ? 0x82F63B78U : 0U);
    table[i] = c;
  }
  return table;
}
constexpr auto kCrcTable = make_crc_table();

/// The little-endian unsigned integer of sizeof(T) bytes at `p`.
template <class T>
T load_le(const char* p) {
  T v = 0;
  for (std::size_t i = sizeof(T); i-- > 0;) v = static_cast<T>((v << 8) | static_cast<unsigned char>(p[i]));
  return v;
}

constexpr std::uint64_t kHeaderBytes = 48;

}  // namespace

std::uint32_t crc32c(const unsigned char* data, std::size_t n) noexcept {
  std::uint32_t crc = 0xFFFFFFFFU;
  for (std::size_t i = 0; i < n; ++i) crc = (crc >> 8) ^ kCrcTable[(crc ^ data[i]) & 0xFFU];
  return crc ^ 0xFFFFFFFFU;
}

PagedFile::PagedFile(std::filesystem::path file, std::string_view bytes) : file_(std::move(file)), bytes_(bytes) {
  if (bytes.size() < kHeaderBytes)
    fail(0, "file is " + std::to_string(bytes.size()) + " bytes long, shorter than the 48-byte E57 header");
  if (bytes.substr(0, 8) != "ASTM-E57") fail(0, "not an E57 file (no \"ASTM-E57\" signature)");
  const char* h = bytes.data();
  header_ = {load_le<std::uint32_t>(h + 8),  load_le<std::uint32_t>(h + 12), load_le<std::uint64_t>(h + 16),
             load_le<std::uint64_t>(h + 24), load_le<std::uint64_t>(h + 32), load_le<std::uint64_t>(h + 40)};
  if (header_.major != 1)
    fail(8, "unsupported E57 major version " + std::to_string(header_.major) + " (this reader reads 1)");
  if (header_.physical_length != bytes.size())
    fail(16, "header says the file is " + std::to_string(header_.physical_length) + " bytes long but it is " +
                 std::to_string(bytes.size()) + " (truncated or corrupted)");
  const std::uint64_t ps = header_.page_size;
  if (ps < 64 || ps > (1U << 20) || !std::has_single_bit(ps))
    fail(40, "page size " + std::to_string(ps) + " is not a power of two between 64 and 1048576");
  if (bytes.size() % ps != 0)
    fail(16, "file length " + std::to_string(bytes.size()) + " is not a whole number of " + std::to_string(ps) +
                 "-byte pages");
  pages_ = bytes.size() / ps;
  checked_.assign(pages_, false);
  check_page(0);
}

std::uint64_t PagedFile::to_logical(std::uint64_t physical, const char* what, std::uint64_t where) const {
  const std::uint64_t ps = header_.page_size;
  if (physical >= bytes_.size())
    fail(where, std::string(what) + " " + std::to_string(physical) + " is past the end of the file (" +
                    std::to_string(bytes_.size()) + " bytes)");
  if (physical % ps >= ps - 4)
    fail(where, std::string(what) + " " + std::to_string(physical) + " points into a page's CRC");
  return physical / ps * (ps - 4) + physical % ps;
}

std::uint64_t PagedFile::to_physical(std::uint64_t logical) const noexcept {
  const std::uint64_t data = header_.page_size - 4;
  return logical / data * header_.page_size + logical % data;
}

void PagedFile::read(std::uint64_t logical, std::size_t n, unsigned char* out) const {
  if (logical > logical_size() || n > logical_size() - logical)
    fail(to_physical(std::min(logical, logical_size())),
         std::to_string(n) + " bytes at logical offset " + std::to_string(logical) + " reach past the end of the file");
  const std::uint64_t data = header_.page_size - 4;
  while (n > 0) {
    const std::uint64_t page = logical / data, in_page = logical % data;
    check_page(page);
    const std::size_t chunk = static_cast<std::size_t>(std::min<std::uint64_t>(n, data - in_page));
    std::memcpy(out, bytes_.data() + page * header_.page_size + in_page, chunk);
    out += chunk;
    logical += chunk;
    n -= chunk;
  }
}

void PagedFile::check_page(std::uint64_t page) const {
  if (checked_[page]) return;
  const std::uint64_t ps = header_.page_size, start = page * ps;
  const auto* p = reinterpret_cast<const unsigned char*>(bytes_.data() + start);
  const std::uint32_t stored = (std::uint32_t{p[ps - 4]} << 24) | (std::uint32_t{p[ps - 3]} << 16) |
                               (std::uint32_t{p[ps - 2]} << 8) | std::uint32_t{p[ps - 1]};
  if (crc32c(p, ps - 4) != stored)
    fail(start, "page " + std::to_string(page) + " (bytes " + std::to_string(start) + " to " +
                    std::to_string(start + ps - 1) + ") fails its CRC-32C check: the file is corrupted");
  checked_[page] = true;
}

void PagedFile::fail(std::uint64_t physical, const std::string& message) const {
  throw InputError(file_, FileLocation{std::nullopt, physical}, message);
}

}  // namespace clustersurf::io::e57
