#pragma once
// Atomic file output: write to a temporary file next to the target, rename over it on commit.

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string_view>

namespace clustersurf::io {

/// Buffered writer whose bytes appear at `target` only when commit() succeeds; if the object is
/// destroyed before (an exception, a cancel), the temporary file is removed and `target` is left
/// as it was. Throws IoError on any failure.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const void* data, std::size_t size);
  void write(std::string_view text) { write(text.data(), text.size()); }
  /// Flushes, syncs and renames the temporary file onto the target.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::FILE* file_ = nullptr;
};

}  // namespace clustersurf::io
