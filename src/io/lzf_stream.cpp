// The resumable LZF decoder (see lzf_stream.hpp). LZF instructions (liblzf's lzf_d.c format):
// a control byte c < 32 copies the next c + 1 input bytes; otherwise length = c >> 5 (7: plus
// the next byte) + 2 bytes are copied from ((c & 31) << 8) + next byte + 1 bytes behind the
// output, byte by byte (a reference may overlap what it writes).

#include "io/lzf_stream.hpp"

#include <clustersurf/core/errors.hpp>

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>

namespace clustersurf::io {

LzfStream::LzfStream(const std::filesystem::path& file, std::string_view packed, std::size_t file_offset)
    : file_(&file), packed_(packed), file_offset_(file_offset) {}

void LzfStream::start_instruction() {
  const std::size_t at = in_;
  const auto byte = [&]() -> std::uint32_t {
    if (in_ >= packed_.size())
      throw InputError(*file_, FileLocation{std::nullopt, file_offset_ + at},
                       "LZF data is corrupt: it ends in the middle of an instruction");
    return static_cast<unsigned char>(packed_[in_++]);
  };
  const std::uint32_t control = byte();
  if (control < 32) {
    literal_ = true;
    pending_ = control + 1;
    if (pending_ > packed_.size() - in_)
      throw InputError(*file_, FileLocation{std::nullopt, file_offset_ + at},
                       "LZF data is corrupt: a literal run goes past its end");
    return;
  }
  std::uint32_t length = control >> 5;
  if (length == 7) length += byte();
  distance_ = ((control & 31) << 8) + byte() + 1;
  if (distance_ > produced_)
    throw InputError(
        *file_, FileLocation{std::nullopt, file_offset_ + at},
        "LZF data is corrupt: a back reference points " + std::to_string(distance_) + " bytes back, before its start");
  literal_ = false;
  pending_ = length + 2;
}

void LzfStream::require_finished() const {
  if (!finished())
    throw InputError(*file_, FileLocation{std::nullopt, file_offset_ + in_},
                     "LZF data is corrupt: it goes on past the declared " + std::to_string(produced_) + " bytes");
}

void LzfStream::emit(const char* bytes, std::uint32_t length, char*& out) {
  if (out != nullptr) std::memcpy(out, bytes, length), out += length;
  const std::size_t at = produced_ % kWindow, first = std::min<std::size_t>(length, kWindow - at);
  std::memcpy(window_.data() + at, bytes, first);
  std::memcpy(window_.data(), bytes + first, length - first);
  produced_ += length;
}

void LzfStream::read(char* out, std::uint64_t n) {
  std::array<char, kMaxInstruction> copied;
  while (n > 0) {
    if (pending_ == 0) {
      if (in_ >= packed_.size())
        throw InputError(*file_, FileLocation{std::nullopt, file_offset_ + in_},
                         "LZF data is corrupt: it ends after " + std::to_string(produced_) +
                             " decompressed bytes, fewer than declared");
      start_instruction();
    }
    const auto step = static_cast<std::uint32_t>(std::min<std::uint64_t>(n, pending_));
    if (literal_) {
      emit(packed_.data() + in_, step, out);
      in_ += step;
    } else {
      // A reference shorter than its distance copies earlier bytes; a longer one repeats them.
      for (std::uint32_t k = 0; k < step; ++k)
        copied[k] = k < distance_ ? window_[(produced_ - distance_ + k) % kWindow] : copied[k - distance_];
      emit(copied.data(), step, out);
    }
    pending_ -= step;
    n -= step;
  }
}

}  // namespace clustersurf::io
