#pragma once
// Small helpers for the text readers: number parsing and a line-counting token cursor.

#include <clustersurf/core/errors.hpp>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace clustersurf::io {

/// Longest line the text readers accept (PLY header and ascii data, XYZ, OBJ). Real lines are
/// under a hundred bytes; the limit bounds the work and memory one line can cost, so a file
/// that is one endless line is refused as soon as the limit is crossed.
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

/// The error for a line longer than kMaxLineBytes.
[[noreturn]] inline void fail_long_line(const std::filesystem::path& file, std::uint64_t line) {
  throw InputError(file, FileLocation{line, std::nullopt},
                   "line is longer than " + std::to_string(kMaxLineBytes) +
                       " bytes (the limit for text files): not a valid file of this format");
}

/// Removes one leading '+' (a sign after it, as in "+-1", makes the token invalid); false if
/// nothing is left.
inline bool strip_plus(std::string_view& token) {
  if (!token.empty() && token.front() == '+') {
    token.remove_prefix(1);
    if (!token.empty() && token.front() == '-') return false;
  }
  return !token.empty();
}

/// Parses the whole token as a double (leading '+' allowed; "nan"/"inf" parse to non-finite
/// values so callers can name them). Returns false if the token is not entirely a number.
inline bool parse_double(std::string_view token, double& value) {
  if (!strip_plus(token)) return false;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size();
}

/// Parses the whole token as a signed 64-bit integer.
inline bool parse_int(std::string_view token, std::int64_t& value) {
  if (!strip_plus(token)) return false;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size();
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// Walks a text buffer, yielding whitespace-separated tokens and whole lines, and counting
/// lines (1-based) for error messages. Throws InputError naming `file` on a line longer than
/// kMaxLineBytes, having read at most that much of it.
class TextCursor {
 public:
  TextCursor(std::string_view text, const std::filesystem::path& file, std::uint64_t first_line = 1)
      : begin_(text.data()),
        p_(text.data()),
        end_(text.data() + text.size()),
        line_start_(p_),
        file_(file),
        line_(first_line) {}

  /// Next token, crossing line breaks; empty at end of input. line() is the token's line.
  std::string_view next_token() {
    for (;;) {
      const char* limit = line_limit();
      while (p_ != limit && is_space(*p_)) ++p_;
      if (p_ == end_) return {};
      if (*p_ == '\n') {
        ++line_;
        line_start_ = ++p_;
        continue;
      }
      if (p_ == limit) fail_long_line(file_, line_);
      const char* start = p_;
      while (p_ != limit && !is_space(*p_) && *p_ != '\n') ++p_;
      if (p_ == limit && p_ != end_ && !is_space(*p_) && *p_ != '\n') fail_long_line(file_, line_);
      return {start, static_cast<std::size_t>(p_ - start)};
    }
  }

  /// Next line without its terminator; returns false at end of input. line() is its number.
  bool next_line(std::string_view& out) {
    if (p_ == end_) return false;
    if (started_) ++line_;
    started_ = true;
    const char* start = p_;
    line_start_ = p_;
    const char* limit = line_limit();
    while (p_ != limit && *p_ != '\n') ++p_;
    if (p_ == limit && p_ != end_ && *p_ != '\n') fail_long_line(file_, line_);
    out = {start, static_cast<std::size_t>(p_ - start)};
    if (p_ != end_) ++p_;
    if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
    return true;
  }

  /// True if only whitespace remains.
  bool only_space_left() const {
    for (const char* q = p_; q != end_; ++q)
      if (!is_space(*q) && *q != '\n') return false;
    return true;
  }

  std::uint64_t line() const noexcept { return line_; }
  /// Byte offset of the cursor from the start of the text (after the last line read, its
  /// terminator included): where a binary section that follows a text header begins.
  std::size_t offset() const noexcept { return static_cast<std::size_t>(p_ - begin_); }

 private:
  /// Where the current line must end at the latest (or the end of the text).
  const char* line_limit() const {
    return static_cast<std::size_t>(end_ - line_start_) > kMaxLineBytes ? line_start_ + kMaxLineBytes : end_;
  }

  const char* begin_;
  const char* p_;
  const char* end_;
  const char* line_start_;
  const std::filesystem::path& file_;
  std::uint64_t line_;
  bool started_ = false;
};

/// Splits `line` into tokens separated by whitespace and/or commas; stops at '#'.
template <class Out>
void split_fields(std::string_view line, Out& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (is_space(line[i]) || line[i] == ',')) ++i;
    if (i >= line.size() || line[i] == '#') break;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i]) && line[i] != ',' && line[i] != '#') ++i;
    out.push_back(line.substr(start, i - start));
  }
}

}  // namespace clustersurf::io
