// PCD (the Point Cloud Library's format, versions 0.5-0.7): a text header (FIELDS, SIZE, TYPE,
// COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA), then the points as ascii lines (separated by
// spaces, tabs or commas), packed binary records, or binary_compressed (LZF, fields stored one
// after another). Fields: x y z (any case), normal_x/y/z, rgb/rgba (packed) or red/green/blue,
// intensity and classification (kept as attributes); others are skipped. A point whose
// position is NaN is PCL's "no point" and is skipped. The viewpoint is the scanner when it is
// not the default one or the cloud is organized (HEIGHT > 1).

#include "io/readers.hpp"
#include "io/text_parse.hpp"

#include <lzf.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace clustersurf::io {

namespace {

/// One declared field: its name, element type ('F', 'I' or 'U') and size, element count, and
/// where its first element sits in a binary record.
struct Field {
  std::string name;
  char type = 'F';
  unsigned size = 4;
  std::uint64_t count = 1;
  std::uint64_t offset = 0;
};

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

/// `x` as a float, NaN kept and magnitudes beyond float's range clamped to it (a plain cast
/// of such a double is undefined).
float to_float(double x) {
  constexpr double kMax = std::numeric_limits<float>::max();
  return std::isnan(x) ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(std::clamp(x, -kMax, kMax));
}

/// `x` rounded into [0, hi] (NaN: 0).
std::uint32_t to_unsigned(double x, double hi) { return std::isnan(x) ? 0u : static_cast<std::uint32_t>(std::clamp(x, 0.0, hi)); }

/// The value of element `bytes` (little-endian) of a field of `type` and `size`.
double decode(const char* bytes, char type, unsigned size) {
  auto get = [&](auto value) {
    std::memcpy(&value, bytes, sizeof(value));
    return static_cast<double>(value);
  };
  switch (type) {
    case 'F': return size == 4 ? get(float{}) : get(double{});
    case 'I':
      return size == 1 ? get(std::int8_t{}) : size == 2 ? get(std::int16_t{}) : size == 4 ? get(std::int32_t{}) : get(std::int64_t{});
    default:
      return size == 1 ? get(std::uint8_t{}) : size == 2 ? get(std::uint16_t{}) : size == 4 ? get(std::uint32_t{}) : get(std::uint64_t{});
  }
}

/// Which declared field supplies each quantity the reader keeps (-1: none).
struct Roles {
  int position[3] = {-1, -1, -1};
  int normal[3] = {-1, -1, -1};
  int packed_rgb = -1;
  int rgb[3] = {-1, -1, -1};
  int intensity = -1;
  int classification = -1;
};

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

/// Collects the points; `value(f)` gives the first element of field f of the current point.
class PointSink {
 public:
  PointSink(const std::vector<Field>& fields, const Roles& roles, std::size_t expected) : fields_(fields), roles_(roles) {
    has_normals_ = std::all_of(roles.normal, roles.normal + 3, [](int f) { return f >= 0; });
    has_rgb_ = roles.packed_rgb >= 0 || std::all_of(roles.rgb, roles.rgb + 3, [](int f) { return f >= 0; });
    pos_.reserve(3 * expected);
  }

  /// Adds the current point unless its position is NaN (PCL's "no point").
  template <class Value>
  void add(Value&& value) {
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = value(roles_.position[k]);
    if (std::isnan(p[0]) || std::isnan(p[1]) || std::isnan(p[2])) return;
    pos_.insert(pos_.end(), p, p + 3);
    if (has_normals_)
      for (int k = 0; k < 3; ++k) nrm_.push_back(value(roles_.normal[k]));
    if (has_rgb_) {
      if (roles_.packed_rgb >= 0) {
        // Packed 0x00RRGGBB in the bytes of a float or an unsigned int.
        const Field& f = fields_[static_cast<std::size_t>(roles_.packed_rgb)];
        std::uint32_t packed = 0;
        if (f.type == 'F' && f.size == 4) std::memcpy(&packed, &(packed_float_ = to_float(value(roles_.packed_rgb))), 4);
        else packed = to_unsigned(value(roles_.packed_rgb), 4294967295.0);
        for (int k = 0; k < 3; ++k) wide_rgb_.push_back(static_cast<std::uint16_t>((packed >> (16 - 8 * k)) & 0xFF));
      } else {
        for (int k = 0; k < 3; ++k)
          wide_rgb_.push_back(static_cast<std::uint16_t>(to_unsigned(value(roles_.rgb[k]), 65535.0)));
      }
    }
    if (roles_.intensity >= 0) intensity_.push_back(to_float(value(roles_.intensity)));
    if (roles_.classification >= 0) classification_.push_back(to_float(value(roles_.classification)));
  }

  void finish(PointCloud& cloud) {
    const auto n = static_cast<Eigen::Index>(pos_.size() / 3);
    cloud.positions = Eigen::Map<Points>(pos_.data(), n, 3);
    if (has_normals_) cloud.normals = Eigen::Map<Points>(nrm_.data(), n, 3);
    if (has_rgb_ && n > 0) {
      // 16-bit red/green/blue fields (PDAL writes them) are scaled unless they hold 8-bit values.
      const auto wide = Eigen::Map<Eigen::Matrix<std::uint16_t, Eigen::Dynamic, 3, Eigen::RowMajor>>(wide_rgb_.data(), n, 3);
      cloud.colors = wide.maxCoeff() <= 255 ? Colors(wide.cast<std::uint8_t>())
                                            : Colors((wide.cast<double>().array() / 257.0).round().cast<std::uint8_t>());
    }
    if (roles_.intensity >= 0) cloud.attributes.push_back({"intensity", Eigen::Map<Eigen::VectorXf>(intensity_.data(), n)});
    if (roles_.classification >= 0)
      cloud.attributes.push_back({"classification", Eigen::Map<Eigen::VectorXf>(classification_.data(), n)});
  }

 private:
  const std::vector<Field>& fields_;
  const Roles& roles_;
  bool has_normals_ = false, has_rgb_ = false;
  float packed_float_ = 0;
  std::vector<double> pos_, nrm_;
  std::vector<std::uint16_t> wide_rgb_;
  std::vector<float> intensity_, classification_;
};

}  // namespace

ParsedFile read_pcd(const std::filesystem::path& file, std::string_view bytes) {
  TextCursor cur(bytes, file);
  std::vector<std::string_view> tokens;
  std::vector<Field> fields;
  std::vector<std::uint64_t> sizes, counts;
  std::vector<char> types;
  std::int64_t width = -1, height = 1, points = -1;
  double viewpoint[7] = {0, 0, 0, 1, 0, 0, 0};
  std::string data;
  std::string_view line;
  while (data.empty()) {
    if (!cur.next_line(line)) throw InputError(file, {cur.line(), {}}, "PCD header ends before its DATA line");
    split_fields(line, tokens);
    if (tokens.empty() || tokens[0].front() == '#') continue;
    const std::string key = lower(tokens[0]);
    const std::string keyword(tokens[0]);  // as the file spells it, for messages
    const std::uint64_t at = cur.line();
    auto need_values = [&](std::size_t n) {
      if (n == 0 || tokens.size() - 1 != n)
        throw InputError(file, {at, {}}, keyword + " needs " + (n ? std::to_string(n) : std::string("at least one")) +
                                              " value(s), found " + std::to_string(tokens.size() - 1));
    };
    auto integer = [&](std::size_t k, std::int64_t lo, std::int64_t hi) {
      std::int64_t v = 0;
      if (!parse_int(tokens[k], v) || v < lo || v > hi)
        throw InputError(file, {at, {}}, keyword + ": expected an integer from " + std::to_string(lo) + " to " +
                                              std::to_string(hi) + ", found \"" + std::string(tokens[k].substr(0, 40)) + "\"");
      return v;
    };
    if (key == "version") continue;
    if (fields.empty() && key != "fields" && key != "columns")
      throw InputError(file, {at, {}}, "expected the PCD header (VERSION or FIELDS), found \"" + std::string(line.substr(0, 40)) + "\"");
    if (key == "fields" || key == "columns") {
      if (tokens.size() < 2 || tokens.size() > 1025) throw InputError(file, {at, {}}, "FIELDS needs 1 to 1024 names");
      fields.clear();
      for (std::size_t k = 1; k < tokens.size(); ++k) fields.push_back({std::string(tokens[k]), 'F', 4, 1, 0});
    } else if (key == "size") {
      need_values(fields.size());
      for (std::size_t k = 0; k < fields.size(); ++k) {
        const auto s = integer(k + 1, 1, 8);
        if (s != 1 && s != 2 && s != 4 && s != 8) throw InputError(file, {at, {}}, "SIZE must be 1, 2, 4 or 8 bytes");
        fields[k].size = static_cast<unsigned>(s);
      }
    } else if (key == "type") {
      need_values(fields.size());
      for (std::size_t k = 0; k < fields.size(); ++k) {
        const std::string t = lower(tokens[k + 1]);
        if (t != "f" && t != "i" && t != "u") throw InputError(file, {at, {}}, "TYPE must be F, I or U, found \"" + t + "\"");
        fields[k].type = static_cast<char>(std::toupper(static_cast<unsigned char>(t[0])));
      }
    } else if (key == "count") {
      need_values(fields.size());
      for (std::size_t k = 0; k < fields.size(); ++k) fields[k].count = static_cast<std::uint64_t>(integer(k + 1, 1, 1 << 20));
    } else if (key == "width") {
      need_values(1);
      width = integer(1, 0, std::numeric_limits<std::int32_t>::max());
    } else if (key == "height") {
      need_values(1);
      height = integer(1, 1, std::numeric_limits<std::int32_t>::max());
    } else if (key == "points") {
      need_values(1);
      points = integer(1, 0, std::numeric_limits<std::int64_t>::max() / 2);
    } else if (key == "viewpoint") {
      need_values(7);
      for (int k = 0; k < 7; ++k)
        if (!parse_double(tokens[static_cast<std::size_t>(k) + 1], viewpoint[k]) || !std::isfinite(viewpoint[k]))
          throw InputError(file, {at, {}}, "VIEWPOINT needs 7 finite numbers");
    } else if (key == "data") {
      need_values(1);
      data = lower(tokens[1]);
      if (data != "ascii" && data != "binary" && data != "binary_compressed")
        throw InputError(file, {at, {}}, "DATA must be ascii, binary or binary_compressed, found \"" + data + "\"");
    } else {
      throw InputError(file, {at, {}}, "unknown PCD header line \"" + std::string(line.substr(0, 40)) + "\"");
    }
  }
  const std::uint64_t data_line = cur.line();
  const Roles roles = roles_of(fields);
  if (std::any_of(roles.position, roles.position + 3, [](int f) { return f < 0; }))
    throw InputError(file, {data_line, {}}, "PCD FIELDS name no x, y and z");
  if (width < 0) throw InputError(file, {data_line, {}}, "PCD header has no WIDTH");
  if (points < 0) points = width * height;
  if (points != width * height)
    throw InputError(file, {data_line, {}}, "POINTS (" + std::to_string(points) + ") is not WIDTH x HEIGHT (" +
                                                std::to_string(width) + " x " + std::to_string(height) + ")");
  std::uint64_t record = 0;
  for (Field& f : fields) {
    if (f.type == 'F' && f.size != 4 && f.size != 8)
      throw InputError(file, {data_line, {}}, "field " + f.name + " is a float of " + std::to_string(f.size) +
                                                  " bytes (PCD floats have 4 or 8)");
    f.offset = record;
    record += f.size * f.count;
  }
  const auto n = static_cast<std::uint64_t>(points);
  const std::size_t body = cur.offset();
  const std::uint64_t remaining = bytes.size() - body;
  // Each point takes at least 2 bytes as text ("0\n") and `record` bytes in binary; LZF
  // expands at most 132 times (a 2-byte back reference copies up to 264 bytes).
  const std::uint64_t max_points = data == "ascii" ? remaining / 2 + 1
                                   : data == "binary" ? remaining / record
                                                      : (remaining / record + 1) * 132;
  if (n > max_points)
    throw InputError(file, FileLocation{std::nullopt, body},
                     "the header declares " + std::to_string(n) + " points, more than the rest of the file can hold");

  ParsedFile out;
  PointSink sink(fields, roles, static_cast<std::size_t>(n));
  if (data == "ascii") {
    std::vector<double> values;
    std::vector<std::size_t> first(fields.size());
    std::size_t columns = 0;
    for (std::size_t f = 0; f < fields.size(); ++f) first[f] = columns, columns += static_cast<std::size_t>(fields[f].count);
    std::uint64_t read = 0;
    while (read < n) {
      if (!cur.next_line(line))
        throw InputError(file, {cur.line(), {}}, "file ends after " + std::to_string(read) + " of " + std::to_string(n) + " points");
      split_fields(line, tokens);
      if (tokens.empty()) continue;
      if (tokens.size() != columns)
        throw InputError(file, {cur.line(), {}}, "expected " + std::to_string(columns) + " values, found " + std::to_string(tokens.size()));
      values.resize(columns);
      for (std::size_t k = 0; k < columns; ++k)
        if (!parse_double(tokens[k], values[k]))
          throw InputError(file, {cur.line(), {}}, "expected a number in column " + std::to_string(k + 1) + ", found \"" +
                                                       std::string(tokens[k].substr(0, 40)) + "\"");
      sink.add([&](int f) { return values[first[static_cast<std::size_t>(f)]]; });
      ++read;
    }
  } else {
    std::string_view records = bytes.substr(body);
    std::vector<char> unpacked;
    if (data == "binary_compressed") {
      if (remaining < 8) throw InputError(file, FileLocation{std::nullopt, body}, "binary_compressed data has no size header");
      std::uint32_t packed_size = 0, unpacked_size = 0;
      std::memcpy(&packed_size, bytes.data() + body, 4);
      std::memcpy(&unpacked_size, bytes.data() + body + 4, 4);
      if (packed_size > remaining - 8)
        throw InputError(file, FileLocation{std::nullopt, body},
                         "compressed size " + std::to_string(packed_size) + " runs past the end of the file");
      if (unpacked_size != n * record)
        throw InputError(file, FileLocation{std::nullopt, body + 4},
                         "uncompressed size " + std::to_string(unpacked_size) + " is not POINTS x record size (" +
                             std::to_string(n * record) + ")");
      unpacked.resize(unpacked_size);
      if (unpacked_size != 0 &&
          lzf_decompress(bytes.data() + body + 8, packed_size, unpacked.data(), unpacked_size) != unpacked_size)
        throw InputError(file, FileLocation{std::nullopt, body + 8}, "LZF data is corrupt or shorter than declared");
    } else if (n * record > remaining) {
      throw InputError(file, FileLocation{std::nullopt, body}, "binary data ends before its points do");
    }
    const bool columns_first = data == "binary_compressed";  // field-major after decompression
    const char* base = columns_first ? unpacked.data() : records.data();
    for (std::uint64_t i = 0; i < n; ++i)
      sink.add([&](int fi) {
        const Field& f = fields[static_cast<std::size_t>(fi)];
        const std::uint64_t at = columns_first ? f.offset * n + i * f.size * f.count : i * record + f.offset;
        return decode(base + at, f.type, f.size);
      });
  }
  sink.finish(out.cloud);
  // Infinite coordinates are errors (NaN is PCL's "no point" and was skipped); the dispatcher
  // names them by point.
  if (!out.cloud.positions.allFinite() || (out.cloud.has_normals() && !out.cloud.normals.allFinite()))
    out.first_non_finite = FileLocation{data_line, std::nullopt};
  const bool default_viewpoint = viewpoint[0] == 0 && viewpoint[1] == 0 && viewpoint[2] == 0;
  if ((!default_viewpoint || height > 1) && out.cloud.size() > 0) {
    out.cloud.scanner_positions = Points(1, 3);
    out.cloud.scanner_positions << viewpoint[0], viewpoint[1], viewpoint[2];
    out.cloud.scanner_of_point.assign(static_cast<std::size_t>(out.cloud.size()), 0);
  }
  return out;
}

}  // namespace clustersurf::io
