// LAS 1.0-1.4 (ASPRS), point data record formats 0-10. Coordinates are integers times the
// header's scale plus its offset, in double precision; RGB comes with formats 2, 3, 5, 7, 8
// and 10; intensity and classification are kept as attributes; extra bytes are skipped.
// Every count and offset (VLRs, EVLRs, the point records) is checked against the file's size
// before anything is allocated. LAZ (compressed) is refused.

#include "io/readers.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

namespace clustersurf::io {

namespace {

/// Little-endian field `T` at byte `at` of `bytes` (the caller has checked the bounds).
template <class T>
T field(std::string_view bytes, std::uint64_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

/// Where the parts of a point record are: formats 0-5 share one layout, 6-10 another.
struct RecordLayout {
  std::uint16_t length = 0;  // the smallest record length the format allows
  std::uint16_t classification = 0;
  std::uint8_t classification_mask = 0xFF;
  std::optional<std::uint16_t> rgb;  // offset of red, green, blue (16 bits each)
};

RecordLayout layout_of(unsigned format) {
  static constexpr std::uint16_t kLegacyLength[] = {20, 28, 26, 34, 57, 63};
  static constexpr std::uint16_t kLength[] = {30, 36, 38, 59, 67};
  RecordLayout l;
  if (format <= 5) {
    l.length = kLegacyLength[format];
    l.classification = 15;
    l.classification_mask = 0x1F;  // the other bits are flags
    if (format == 2) l.rgb = 20;
    if (format == 3 || format == 5) l.rgb = 28;
  } else {
    l.length = kLength[format - 6];
    l.classification = 16;
    if (format == 7 || format == 8 || format == 10) l.rgb = 30;
  }
  return l;
}

}  // namespace

std::array<std::uint16_t, 3> LasPoints::color(std::string_view bytes, std::uint64_t i) const {
  const std::uint64_t at = first + i * record + *rgb;
  return {field<std::uint16_t>(bytes, at), field<std::uint16_t>(bytes, at + 2), field<std::uint16_t>(bytes, at + 4)};
}

std::uint16_t LasPoints::color_maximum(std::string_view bytes) const {
  std::uint16_t top = 0;
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::array<std::uint16_t, 3> c = color(bytes, i);
    top = std::max({top, c[0], c[1], c[2]});
  }
  return top;
}

Eigen::Vector3d LasPoints::position(std::string_view bytes, std::uint64_t i) const {
  const std::uint64_t r = first + i * record;
  Eigen::Vector3d x;
  for (int k = 0; k < 3; ++k)
    x(k) = static_cast<double>(field<std::int32_t>(bytes, r + 4 * static_cast<unsigned>(k))) * scale(k) + offset(k);
  return x;
}

namespace {

/// An error at byte `at` of `file`.
InputError byte_error(const std::filesystem::path& file, std::uint64_t at, const std::string& message) {
  return InputError(file, FileLocation{std::nullopt, at}, message);
}

/// Checks the chain of variable-length records between the header (`header_size` bytes) and
/// the point data at `point_offset`.
void check_records(const std::filesystem::path& file, std::string_view bytes, std::uint64_t header_size,
                   std::uint64_t point_offset, std::uint32_t vlr_count) {
  const auto size = static_cast<std::uint64_t>(bytes.size());
  const auto fail = [&](std::uint64_t at, const std::string& message) { return byte_error(file, at, message); };
  if (point_offset < header_size || point_offset > size)
    throw fail(96, "offset to point data (" + std::to_string(point_offset) + ") lies outside [header size " +
                       std::to_string(header_size) + ", file size " + std::to_string(size) + "]");
  std::uint64_t at = header_size;
  for (std::uint32_t v = 0; v < vlr_count; ++v) {
    if (at + 54 > point_offset)
      throw fail(at, "variable-length record " + std::to_string(v + 1) + " of " + std::to_string(vlr_count) +
                         " would start past the point data (byte " + std::to_string(point_offset) +
                         "): the header's VLR count is wrong");
    at += 54 + field<std::uint16_t>(bytes, at + 20);
    if (at > point_offset)
      throw fail(at, "variable-length record " + std::to_string(v + 1) + " of " + std::to_string(vlr_count) +
                         " runs past the start of the point data (byte " + std::to_string(point_offset) +
                         "): its length or the header's VLR count is wrong");
  }
}

/// Checks LAS 1.4's extended variable-length records: after the points, each with a 60-byte
/// header, all within the file.
void check_extended_records(const std::filesystem::path& file, std::string_view bytes) {
  const auto size = static_cast<std::uint64_t>(bytes.size());
  const auto fail = [&](std::uint64_t at, const std::string& message) { return byte_error(file, at, message); };
  std::uint64_t evlr = field<std::uint64_t>(bytes, 235);
  const auto evlr_count = field<std::uint32_t>(bytes, 243);
  for (std::uint32_t v = 0; v < evlr_count; ++v) {
    if (evlr > size || size - evlr < 60)
      throw fail(235, "extended variable-length record " + std::to_string(v + 1) + " of " + std::to_string(evlr_count) +
                          " starts past the end of the file (byte " + std::to_string(evlr) + ")");
    const auto length = field<std::uint64_t>(bytes, evlr + 20);
    if (length > size - evlr - 60)
      throw fail(evlr + 20,
                 "extended variable-length record " + std::to_string(v + 1) + " runs past the end of the file");
    evlr += 60 + length;
  }
}

}  // namespace

LasPoints las_points(const std::filesystem::path& file, std::string_view bytes) {
  const auto size = static_cast<std::uint64_t>(bytes.size());
  const auto fail = [&](std::uint64_t at, const std::string& message) { return byte_error(file, at, message); };
  if (bytes.substr(0, 4) != "LASF") throw fail(0, "not a LAS file (no \"LASF\" signature)");
  if (size < 227)
    throw fail(size,
               "LAS header is truncated: the file has " + std::to_string(size) + " bytes, the header at least 227");
  const unsigned major = static_cast<unsigned char>(bytes[24]), minor = static_cast<unsigned char>(bytes[25]);
  if (major != 1 || minor > 4)
    throw fail(24, "unsupported LAS version " + std::to_string(major) + "." + std::to_string(minor) +
                       " (expected 1.0 to 1.4)");
  const auto header_size = field<std::uint16_t>(bytes, 94);
  const auto point_offset = field<std::uint32_t>(bytes, 96);
  const auto vlr_count = field<std::uint32_t>(bytes, 100);
  const unsigned format_byte = static_cast<unsigned char>(bytes[104]);
  const auto record_length = field<std::uint16_t>(bytes, 105);
  std::uint64_t count = field<std::uint32_t>(bytes, 107);
  const Eigen::Vector3d scale(field<double>(bytes, 131), field<double>(bytes, 139), field<double>(bytes, 147));
  const Eigen::Vector3d offset(field<double>(bytes, 155), field<double>(bytes, 163), field<double>(bytes, 171));

  if (format_byte & 0xC0)
    throw fail(104, "this is a compressed (LAZ) point format (" + std::to_string(format_byte) +
                        "): LAZ is not supported; decompress it to LAS first (e.g. laszip or PDAL)");
  const unsigned format = format_byte;
  if (format > 10)
    throw fail(104, "unknown LAS point data record format " + std::to_string(format) + " (expected 0 to 10)");
  if (format > 5 && minor < 4)
    throw fail(104,
               "point format " + std::to_string(format) + " needs LAS 1.4, the file says 1." + std::to_string(minor));
  if (header_size < 227 || header_size > size)
    throw fail(94, "LAS header size " + std::to_string(header_size) +
                       " is impossible (at least 227, at most the file's " + std::to_string(size) + " bytes)");
  if (minor >= 4) {
    if (header_size < 375)
      throw fail(94, "a LAS 1.4 header has at least 375 bytes, this one says " + std::to_string(header_size));
    const auto count64 = field<std::uint64_t>(bytes, 247);
    if (count != 0 && count64 != count)
      throw fail(247, "the 64-bit point count (" + std::to_string(count64) + ") contradicts the legacy count (" +
                          std::to_string(count) + ")");
    count = count64;
  }
  if (!scale.allFinite() || (scale.array() == 0).any() || !offset.allFinite())
    throw fail(131, "coordinate scale factors must be finite and non-zero, offsets finite");

  check_records(file, bytes, header_size, point_offset, vlr_count);
  if (minor >= 4) check_extended_records(file, bytes);

  const RecordLayout layout = layout_of(format);
  if (record_length < layout.length)
    throw fail(105, "point record length " + std::to_string(record_length) + " is shorter than point format " +
                        std::to_string(format) + " needs (" + std::to_string(layout.length) + ")");
  if (count > (size - point_offset) / record_length)
    throw fail(107, "the header declares " + std::to_string(count) + " points of " + std::to_string(record_length) +
                        " bytes from byte " + std::to_string(point_offset) + ", but the file ends at byte " +
                        std::to_string(size));

  return {count, point_offset, record_length, format, scale, offset, layout.rgb};
}

ParsedFile read_las(const std::filesystem::path& file, std::string_view bytes) {
  const LasPoints las = las_points(file, bytes);
  const RecordLayout layout = layout_of(las.format);
  const auto n = static_cast<Eigen::Index>(las.count);
  ParsedFile parsed;
  PointCloud& cloud = parsed.cloud;
  cloud.positions.resize(n, 3);
  Eigen::VectorXf intensity(n), classification(n);
  // LAS colours are 16-bit; writers that stored 8-bit values in them (all of them at most
  // 255) are read as they are, and fields left 0 in every record are no colors.
  const std::uint16_t top = las.has_colors() ? las.color_maximum(bytes) : 0;
  const bool colored = top > 0, eight_bit = top <= 255;
  if (colored) cloud.colors.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::uint64_t r = las.first + static_cast<std::uint64_t>(i) * las.record;
    cloud.positions.row(i) = las.position(bytes, static_cast<std::uint64_t>(i)).transpose();
    intensity(i) = field<std::uint16_t>(bytes, r + 12);
    classification(i) =
        static_cast<float>(static_cast<unsigned char>(bytes[r + layout.classification]) & layout.classification_mask);
    if (colored) {
      const std::array<std::uint16_t, 3> c = las.color(bytes, static_cast<std::uint64_t>(i));
      for (int k = 0; k < 3; ++k) cloud.colors(i, k) = wide_color_byte(c[static_cast<std::size_t>(k)], eight_bit);
    }
  }
  cloud.attributes.push_back({"intensity", std::move(intensity)});
  cloud.attributes.push_back({"classification", std::move(classification)});
  return parsed;
}

}  // namespace clustersurf::io
