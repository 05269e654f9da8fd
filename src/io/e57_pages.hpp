#pragma once
// E57's physical layer (ASTM E2807): the 48-byte file header and the paged address space, in
// which every page ends with a CRC-32C of the rest of it. Offsets stored in an E57 file are
// physical (CRC bytes included); content is read through logical offsets (CRC bytes removed).

#include <clustersurf/core/errors.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace clustersurf::io::e57 {

/// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78) of `n` bytes, as E57 pages carry it.
std::uint32_t crc32c(const unsigned char* data, std::size_t n) noexcept;

/// The fields of the file header, checked for consistency with the file (see PagedFile).
struct FileHeader {
  std::uint32_t major = 0;
  std::uint32_t minor = 0;
  std::uint64_t physical_length = 0;
  std::uint64_t xml_physical_offset = 0;
  std::uint64_t xml_logical_length = 0;
  std::uint64_t page_size = 0;
};

/// An E57 file's bytes as a logical address space. Construction checks the header (signature,
/// version, length equal to the file's, page size a power of two in [64, 1 MiB] dividing the
/// file, page 0's CRC); every read checks its range and the CRC of each page it touches.
class PagedFile {
 public:
  PagedFile(std::filesystem::path file, std::string_view bytes);

  const FileHeader& header() const noexcept { return header_; }
  const std::filesystem::path& file() const noexcept { return file_; }
  /// Bytes of content in the file: pages × (page size − 4).
  std::uint64_t logical_size() const noexcept { return pages_ * (header_.page_size - 4); }
  /// The logical offset of physical offset `physical`; throws (naming `what` and `where`, the
  /// byte holding that offset) when it lies past the end or on a page's CRC.
  std::uint64_t to_logical(std::uint64_t physical, const char* what, std::uint64_t where) const;
  /// The physical offset of logical offset `logical` (for messages).
  std::uint64_t to_physical(std::uint64_t logical) const noexcept;
  /// Copies `n` logical bytes starting at `logical` to `out`; throws when they reach past the
  /// end of the file or a page they touch fails its CRC.
  void read(std::uint64_t logical, std::size_t n, unsigned char* out) const;
  /// An InputError naming the file and physical byte offset `physical`.
  [[noreturn]] void fail(std::uint64_t physical, const std::string& message) const;

 private:
  void check_page(std::uint64_t page) const;

  std::filesystem::path file_;
  std::string_view bytes_;
  FileHeader header_;
  std::uint64_t pages_ = 0;
  mutable std::vector<bool> checked_;  // pages whose CRC was verified
};

}  // namespace clustersurf::io::e57
