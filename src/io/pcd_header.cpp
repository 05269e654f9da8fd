// The PCD header, checked against the file's size, and its records read one at a time (ascii,
// binary, or binary_compressed through one LZF decoder per kept field); see pcd_format.hpp.

#include "io/pcd_format.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

namespace clustersurf::io::pcd {

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

Roles roles_of(const std::vector<Field>& fields) {
  Roles r;
  static constexpr std::array<const char*, 3> kXyz = {"x", "y", "z"}, kNormal = {"normal_x", "normal_y", "normal_z"},
                                              kRgb = {"red", "green", "blue"};
  for (int f = 0; f < static_cast<int>(fields.size()); ++f) {
    const std::string name = lower(fields[static_cast<std::size_t>(f)].name);
    for (int k = 0; k < 3; ++k) {
      if (name == kXyz[static_cast<std::size_t>(k)]) r.position[k] = f;
      if (name == kNormal[static_cast<std::size_t>(k)]) r.normal[k] = f;
      if (name == kRgb[static_cast<std::size_t>(k)]) r.rgb[k] = f;
    }
    if (name == "rgb" || name == "rgba") r.packed_rgb = f;
    if (name == "intensity") r.intensity = f;
    if (name == "classification" || name == "label") r.classification = f;
  }
  return r;
}

}  // namespace

std::array<std::uint8_t, 3> packed_color(double value, const Field& f) {
  std::uint32_t packed = 0;
  if (f.type == 'F' && f.size == 4) {
    constexpr double kMax = std::numeric_limits<float>::max();
    const float bits = std::isnan(value) ? std::numeric_limits<float>::quiet_NaN()
                                         : static_cast<float>(std::clamp(value, -kMax, kMax));
    std::memcpy(&packed, &bits, 4);
  } else {
    packed = std::isnan(value) ? 0u : static_cast<std::uint32_t>(std::clamp(value, 0.0, 4294967295.0));
  }
  return {static_cast<std::uint8_t>((packed >> 16) & 0xFF), static_cast<std::uint8_t>((packed >> 8) & 0xFF),
          static_cast<std::uint8_t>(packed & 0xFF)};
}

double decode(const char* bytes, char type, unsigned size) {
  auto get = [&](auto value) {
    std::memcpy(&value, bytes, sizeof(value));
    return static_cast<double>(value);
  };
  switch (type) {
    case 'F':
      return size == 4 ? get(float{}) : get(double{});
    case 'I':
      return size == 1   ? get(std::int8_t{})
             : size == 2 ? get(std::int16_t{})
             : size == 4 ? get(std::int32_t{})
                         : get(std::int64_t{});
    default:
      return size == 1   ? get(std::uint8_t{})
             : size == 2 ? get(std::uint16_t{})
             : size == 4 ? get(std::uint32_t{})
                         : get(std::uint64_t{});
  }
}

namespace {

/// What the header lines have said so far.
struct Header {
  Layout layout;
  std::int64_t width = -1, points = -1;
  std::string data;  ///< the DATA word, lower case; empty until the DATA line
};

/// One header line, split into `tokens` (its keyword first), read into `h`.
class HeaderLine {
 public:
  HeaderLine(const std::filesystem::path& file, std::uint64_t line, std::string_view text,
             const std::vector<std::string_view>& tokens)
      : file_(file), at_(line), text_(text), tokens_(tokens), keyword_(tokens[0]) {}

  void read(Header& h) const {
    const std::string key = lower(tokens_[0]);
    std::vector<Field>& fields = h.layout.fields;
    if (key == "version") return;
    if (fields.empty() && key != "fields" && key != "columns")
      fail("expected the PCD header (VERSION or FIELDS), found \"" + std::string(text_.substr(0, 40)) + "\"");
    if (key == "fields" || key == "columns") {
      if (tokens_.size() < 2 || tokens_.size() > 1025) fail("FIELDS needs 1 to 1024 names");
      fields.clear();
      for (std::size_t k = 1; k < tokens_.size(); ++k) fields.push_back({std::string(tokens_[k]), 'F', 4, 1, 0});
    } else if (key == "size") {
      need_values(fields.size());
      for (std::size_t k = 0; k < fields.size(); ++k) {
        const auto s = integer(k + 1, 1, 8);
        if (s != 1 && s != 2 && s != 4 && s != 8) fail("SIZE must be 1, 2, 4 or 8 bytes");
        fields[k].size = static_cast<unsigned>(s);
      }
    } else if (key == "type") {
      need_values(fields.size());
      for (std::size_t k = 0; k < fields.size(); ++k) {
        const std::string t = lower(tokens_[k + 1]);
        if (t != "f" && t != "i" && t != "u") fail("TYPE must be F, I or U, found \"" + t + "\"");
        fields[k].type = static_cast<char>(std::toupper(static_cast<unsigned char>(t[0])));
      }
    } else if (key == "count") {
      need_values(fields.size());
      for (std::size_t k = 0; k < fields.size(); ++k)
        fields[k].count = static_cast<std::uint64_t>(integer(k + 1, 1, 1 << 20));
    } else if (key == "width") {
      need_values(1);
      h.width = integer(1, 0, std::numeric_limits<std::int32_t>::max());
    } else if (key == "height") {
      need_values(1);
      h.layout.height = integer(1, 1, std::numeric_limits<std::int32_t>::max());
    } else if (key == "points") {
      need_values(1);
      h.points = integer(1, 0, std::numeric_limits<std::int64_t>::max() / 2);
    } else if (key == "viewpoint") {
      need_values(7);
      for (int k = 0; k < 7; ++k)
        if (!parse_double(tokens_[static_cast<std::size_t>(k) + 1], h.layout.viewpoint[k]) ||
            !std::isfinite(h.layout.viewpoint[k]))
          fail("VIEWPOINT needs 7 finite numbers");
    } else if (key == "data") {
      need_values(1);
      h.data = lower(tokens_[1]);
      if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed")
        fail("DATA must be ascii, binary or binary_compressed, found \"" + h.data + "\"");
    } else {
      fail("unknown PCD header line \"" + std::string(text_.substr(0, 40)) + "\"");
    }
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { throw InputError(file_, {at_, {}}, message); }
  void need_values(std::size_t n) const {
    if (n == 0 || tokens_.size() - 1 != n)
      fail(keyword_ + " needs " + (n ? std::to_string(n) : std::string("at least one")) + " value(s), found " +
           std::to_string(tokens_.size() - 1));
  }
  std::int64_t integer(std::size_t k, std::int64_t lo, std::int64_t hi) const {
    std::int64_t v = 0;
    if (!parse_int(tokens_[k], v) || v < lo || v > hi)
      fail(keyword_ + ": expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", found \"" +
           std::string(tokens_[k].substr(0, 40)) + "\"");
    return v;
  }

  const std::filesystem::path& file_;
  std::uint64_t at_;
  std::string_view text_;
  const std::vector<std::string_view>& tokens_;
  std::string keyword_;  ///< as the file spells it, for messages
};

/// The layout of a header read up to its DATA line (`data_line`; the body starts at byte
/// `body` of the file's `bytes`), checked against itself and against the file's size.
Layout checked_layout(const std::filesystem::path& file, std::string_view bytes, Header h, std::uint64_t data_line,
                      std::size_t body) {
  Layout out = std::move(h.layout);
  std::vector<Field>& fields = out.fields;
  out.data = h.data == "ascii" ? Data::Ascii : h.data == "binary" ? Data::Binary : Data::BinaryCompressed;
  out.data_line = data_line;
  out.roles = roles_of(fields);
  if (std::any_of(out.roles.position, out.roles.position + 3, [](int f) { return f < 0; }))
    throw InputError(file, {out.data_line, {}}, "PCD FIELDS name no x, y and z");
  if (h.width < 0) throw InputError(file, {out.data_line, {}}, "PCD header has no WIDTH");
  if (h.points < 0) h.points = h.width * out.height;
  if (h.points != h.width * out.height)
    throw InputError(file, {out.data_line, {}},
                     "POINTS (" + std::to_string(h.points) + ") is not WIDTH x HEIGHT (" + std::to_string(h.width) +
                         " x " + std::to_string(out.height) + ")");
  for (Field& f : fields) {
    if (f.type == 'F' && f.size != 4 && f.size != 8)
      throw InputError(
          file, {out.data_line, {}},
          "field " + f.name + " is a float of " + std::to_string(f.size) + " bytes (PCD floats have 4 or 8)");
    f.offset = out.record;
    out.record += f.size * f.count;
  }
  // An ascii line holds every element, each at least a digit and a separator: more columns
  // than a line can hold cannot be read (and must not be allocated for).
  if (out.data == Data::Ascii) {
    std::uint64_t columns = 0;
    for (const Field& f : fields) columns += f.count;
    if (columns > kMaxLineBytes / 2 + 1)
      throw InputError(file, {out.data_line, {}},
                       "the fields' COUNTs add up to " + std::to_string(columns) +
                           " values per point, more than an ascii line can hold");
  }
  out.points = static_cast<std::uint64_t>(h.points);
  out.body = body;
  const std::uint64_t remaining = bytes.size() - out.body;
  // Each point takes at least 2 bytes as text ("0\n") and `record` bytes in binary; LZF
  // expands at most 132 times (a 2-byte back reference copies up to 264 bytes).
  const std::uint64_t max_points = out.data == Data::Ascii    ? remaining / 2 + 1
                                   : out.data == Data::Binary ? remaining / out.record
                                                              : (remaining / out.record + 1) * 132;
  if (out.points > max_points)
    throw InputError(
        file, FileLocation{std::nullopt, out.body},
        "the header declares " + std::to_string(out.points) + " points, more than the rest of the file can hold");
  if (out.data == Data::Binary && out.points * out.record > remaining)
    throw InputError(file, FileLocation{std::nullopt, out.body}, "binary data ends before its points do");
  return out;
}

}  // namespace

Layout read_layout(const std::filesystem::path& file, std::string_view bytes) {
  TextCursor cur(bytes, file);
  std::vector<std::string_view> tokens;
  Header header;
  std::string_view line;
  while (header.data.empty()) {
    if (!cur.next_line(line)) throw InputError(file, {cur.line(), {}}, "PCD header ends before its DATA line");
    split_fields(line, tokens);
    if (tokens.empty() || tokens[0].front() == '#') continue;
    HeaderLine(file, cur.line(), line, tokens).read(header);
  }
  return checked_layout(file, bytes, std::move(header), cur.line(), cur.offset());
}

CompressedData compressed_data(const std::filesystem::path& file, std::string_view bytes, const Layout& layout) {
  const std::size_t body = layout.body;
  const std::uint64_t remaining = bytes.size() - body;
  if (remaining < 8)
    throw InputError(file, FileLocation{std::nullopt, body}, "binary_compressed data has no size header");
  std::uint32_t packed_size = 0, unpacked_size = 0;
  std::memcpy(&packed_size, bytes.data() + body, 4);
  std::memcpy(&unpacked_size, bytes.data() + body + 4, 4);
  if (packed_size > remaining - 8)
    throw InputError(file, FileLocation{std::nullopt, body},
                     "compressed size " + std::to_string(packed_size) + " runs past the end of the file");
  if (unpacked_size != layout.points * layout.record)
    throw InputError(file, FileLocation{std::nullopt, body + 4},
                     "uncompressed size " + std::to_string(unpacked_size) + " is not POINTS x record size (" +
                         std::to_string(layout.points * layout.record) + ")");
  return {bytes.substr(body + 8, packed_size), body + 8, unpacked_size};
}

namespace {

/// The fields whose values a reader keeps (every role), in ascending order.
std::vector<int> kept_fields(const Roles& r) {
  std::vector<int> out(r.position, r.position + 3);
  out.insert(out.end(), r.normal, r.normal + 3);
  out.insert(out.end(), r.rgb, r.rgb + 3);
  out.insert(out.end(), {r.packed_rgb, r.intensity, r.classification});
  std::erase(out, -1);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// The compressed pass reports how far it has read this often.
constexpr std::uint64_t kReportBytes = std::uint64_t{64} << 20;

}  // namespace

Records::Records(const std::filesystem::path& file, std::string_view bytes, const Layout& layout,
                 const std::function<void(std::size_t)>& consumed)
    : file_(file), bytes_(bytes), layout_(layout) {
  cursor_.emplace(bytes.substr(layout.body), file_, layout.data_line + 1);
  if (layout.data == Data::Ascii) {
    std::size_t columns = 0;
    for (const Field& f : layout.fields) first_.push_back(columns), columns += static_cast<std::size_t>(f.count);
    values_.resize(columns);  // at most a line's worth (read_layout())
  }
  if (layout.data != Data::BinaryCompressed) return;
  const CompressedData data = compressed_data(file, bytes, layout);
  packed_begin_ = data.begin;
  // One pass through the data checks it, and keeps a decoder where each kept field's values begin.
  LzfStream decoder(file, data.packed, packed_begin_);
  std::uint64_t reported = 0;
  const auto skip_to = [&](std::uint64_t target) {
    while (decoder.produced() < target) {
      decoder.read(nullptr, std::min<std::uint64_t>(target - decoder.produced(), std::uint64_t{1} << 20));
      if (consumed && decoder.consumed() - reported >= kReportBytes)
        reported = decoder.consumed(), consumed(packed_begin_ + reported);
    }
  };
  kept_ = kept_fields(layout.roles);
  for (const int f : kept_) {
    skip_to(layout.fields[static_cast<std::size_t>(f)].offset * layout.points);
    starts_.push_back(decoder);
  }
  skip_to(data.unpacked);
  decoder.require_finished();
  if (consumed) consumed(packed_begin_ + data.packed.size());
  slot_.assign(layout.fields.size(), -1);
  for (std::size_t k = 0; k < kept_.size(); ++k) slot_[static_cast<std::size_t>(kept_[k])] = static_cast<int>(k);
  record_.assign(8 * kept_.size(), 0);
  rewind();
}

void Records::rewind() {
  read_ = 0;
  cursor_.emplace(bytes_.substr(layout_.body), file_, layout_.data_line + 1);
  decoders_ = starts_;
  handed_.clear();
  for (const LzfStream& d : starts_) handed_.push_back(d.consumed());
}

bool Records::next() {
  if (read_ == layout_.points) return false;
  ++read_;
  if (layout_.data == Data::BinaryCompressed) {
    for (std::size_t k = 0; k < kept_.size(); ++k) {
      const Field& field = layout_.fields[static_cast<std::size_t>(kept_[k])];
      decoders_[k].read(record_.data() + 8 * k, field.size);
      decoders_[k].read(nullptr, field.size * (field.count - 1));
    }
    return true;
  }
  if (layout_.data != Data::Ascii) return true;
  std::string_view line;
  for (;;) {
    if (!cursor_->next_line(line))
      throw InputError(
          file_, {cursor_->line(), {}},
          "file ends after " + std::to_string(read_ - 1) + " of " + std::to_string(layout_.points) + " points");
    split_fields(line, tokens_);
    if (!tokens_.empty()) break;
  }
  if (tokens_.size() != values_.size())
    throw InputError(file_, {cursor_->line(), {}},
                     "expected " + std::to_string(values_.size()) + " values, found " + std::to_string(tokens_.size()));
  for (std::size_t k = 0; k < values_.size(); ++k)
    if (!parse_double(tokens_[k], values_[k]))
      throw InputError(file_, {cursor_->line(), {}},
                       "expected a number in column " + std::to_string(k + 1) + ", found \"" +
                           std::string(tokens_[k].substr(0, 40)) + "\"");
  return true;
}

double Records::value(int f) const {
  if (layout_.data == Data::Ascii) return values_[first_[static_cast<std::size_t>(f)]];
  const Field& field = layout_.fields[static_cast<std::size_t>(f)];
  if (layout_.data == Data::BinaryCompressed) {
    const int k = slot_[static_cast<std::size_t>(f)];
    return k < 0 ? std::numeric_limits<double>::quiet_NaN() : decode(record_.data() + 8 * k, field.type, field.size);
  }
  return decode(bytes_.data() + layout_.body + (read_ - 1) * layout_.record + field.offset, field.type, field.size);
}

FileLocation Records::location() const {
  if (layout_.data == Data::Ascii) return {cursor_->line(), std::nullopt};
  if (layout_.data == Data::BinaryCompressed)
    return {
        std::nullopt,
        packed_begin_ +
            decoders_[static_cast<std::size_t>(slot_[static_cast<std::size_t>(layout_.roles.position[0])])].consumed()};
  return {std::nullopt, layout_.body + (read_ - 1) * layout_.record};
}

std::size_t Records::offset() const {
  return layout_.data == Data::Ascii ? layout_.body + cursor_->offset()
                                     : layout_.body + static_cast<std::size_t>(read_ * layout_.record);
}

std::vector<std::pair<std::size_t, std::size_t>> Records::take_read_spans() {
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  if (layout_.data != Data::BinaryCompressed) return spans;
  for (std::size_t k = 0; k < decoders_.size(); ++k) {
    const std::size_t now = decoders_[k].consumed();
    if (now > handed_[k]) spans.emplace_back(packed_begin_ + handed_[k], packed_begin_ + now);
    handed_[k] = now;
  }
  return spans;
}

}  // namespace clustersurf::io::pcd
