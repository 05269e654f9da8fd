#pragma once
// LZF data (the compression of PCD's binary_compressed) decoded a few bytes at a time, from any
// point whose state was kept: liblzf decodes a whole buffer at once, and a binary_compressed
// file stores each field's values one after another, so reading its points in order takes one
// decoder per field, each resumed where that field's values begin.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

namespace clustersurf::io {

/// A resumable LZF decoder over `packed` (the compressed bytes); `file` and `packed` must outlive
/// it. A copy is an independent decoder at the same position. Errors are InputErrors naming
/// `file` and the byte offset in the file (`packed` starts at byte `file_offset`).
class LzfStream {
 public:
  LzfStream(const std::filesystem::path& file, std::string_view packed, std::size_t file_offset);

  /// The next `n` decompressed bytes into `out` (null: decoded and dropped). InputError where a
  /// back reference points before the data's start or the data ends mid-instruction or before
  /// `n` bytes.
  void read(char* out, std::uint64_t n);
  /// Decompressed bytes produced so far.
  std::uint64_t produced() const noexcept { return produced_; }
  /// Compressed bytes consumed so far.
  std::size_t consumed() const noexcept { return in_; }
  /// Whether every compressed byte has been decoded (no instruction left).
  bool finished() const noexcept { return in_ == packed_.size() && pending_ == 0; }
  /// InputError unless finished(): the data goes on past the bytes produced so far.
  void require_finished() const;

 private:
  /// LZF's back references reach at most this far behind the output.
  static constexpr std::size_t kWindow = 8192;
  /// The longest instruction: a back reference of 7 + 255 + 2 bytes.
  static constexpr std::size_t kMaxInstruction = 264;

  /// Starts the next instruction: a literal run or a back reference.
  void start_instruction();
  /// Appends `length` bytes to the output (`out`, advanced, unless null) and the window.
  void emit(const char* bytes, std::uint32_t length, char*& out);

  const std::filesystem::path* file_;
  std::string_view packed_;
  std::size_t file_offset_;
  std::size_t in_ = 0;                  // next compressed byte
  std::uint64_t produced_ = 0;          // bytes written so far
  std::uint32_t pending_ = 0;           // bytes of the current instruction still to write
  bool literal_ = false;                // the current instruction copies input bytes (else a reference)
  std::uint32_t distance_ = 0;          // a reference: how far behind the output it copies from
  std::array<char, kWindow> window_{};  // the last kWindow bytes written, at produced % kWindow
};

}  // namespace clustersurf::io
