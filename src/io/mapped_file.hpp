#pragma once
// Read-only view of a whole file's bytes (memory-mapped; empty files give an empty view).

#include <cstddef>
#include <filesystem>
#include <string_view>

namespace clustersurf::io {

/// Maps a file read-only for the lifetime of the object. Throws IoError when the file cannot be
/// opened or mapped.
class MappedFile {
 public:
  explicit MappedFile(const std::filesystem::path& file);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  const char* data() const noexcept { return data_; }
  std::size_t size() const noexcept { return size_; }
  std::string_view view() const noexcept { return {data_, size_}; }
  /// Lets the kernel drop the pages of bytes [begin, end) from memory (they are read again from
  /// the file if touched): a sequential reader keeps only what it still needs resident.
  void release(std::size_t begin, std::size_t end) const noexcept;

 private:
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace clustersurf::io
