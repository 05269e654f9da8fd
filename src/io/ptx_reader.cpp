// PTX (Leica, FARO): one or more gridded scans, each a header (columns, rows, the scanner's
// registered position and axes, a 4x4 transform whose last row is the translation) followed by
// columns x rows lines "x y z intensity [r g b]" in the scanner's frame. A line of zeros is a
// grid cell without a return and is skipped; every other point is transformed by its scan's
// matrix, and the scan's position becomes the point's scanner.

#include "io/readers.hpp"
#include "io/text_parse.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace clustersurf::io {

namespace {

/// Reads the next non-empty line as exactly `count` numbers, or throws naming the line.
void read_numbers(TextCursor& cur, const std::filesystem::path& file, std::vector<std::string_view>& fields,
                  std::size_t count, double* out, const char* what) {
  std::string_view line;
  do {
    if (!cur.next_line(line))
      throw InputError(file, {cur.line(), {}}, std::string("file ends where the scan header's ") + what + " was expected");
    split_fields(line, fields);
  } while (fields.empty());
  if (fields.size() != count)
    throw InputError(file, {cur.line(), {}},
                     std::string("expected ") + std::to_string(count) + " numbers (" + what + "), found " +
                         std::to_string(fields.size()));
  for (std::size_t k = 0; k < count; ++k)
    if (!parse_double(fields[k], out[k]) || !std::isfinite(out[k]))
      throw InputError(file, {cur.line(), {}},
                       std::string("expected a finite number in the ") + what + ", found \"" +
                           std::string(fields[k].substr(0, 40)) + "\"");
}

}  // namespace

ParsedFile read_ptx(const std::filesystem::path& file, std::string_view bytes) {
  TextCursor cur(bytes, file);
  std::vector<std::string_view> fields;
  std::vector<double> pos;
  std::vector<std::uint8_t> rgb;
  std::vector<float> intensity;
  std::vector<std::uint32_t> scan_of;
  std::vector<double> scanners;
  std::optional<bool> colored;  // every scan must agree
  std::optional<FileLocation> first_non_finite;
  std::string_view line;
  for (std::uint32_t scan = 0;; ++scan) {
    // The next scan's header begins at the next non-empty line, or the file ends.
    std::uint64_t header_line = 0;
    do {
      if (!cur.next_line(line)) line = {};
      else header_line = cur.line();
      split_fields(line, fields);
    } while (fields.empty() && !line.empty());
    if (fields.empty()) break;
    std::int64_t columns = 0, rows = 0;
    if (fields.size() != 1 || !parse_int(fields[0], columns) || columns <= 0)
      throw InputError(file, {header_line, {}}, "expected the scan's column count (a positive integer) to start scan " +
                                                    std::to_string(scan + 1));
    double value[16];
    read_numbers(cur, file, fields, 1, value, "row count");
    if (!(value[0] >= 1 && value[0] <= 2147483648.0) || value[0] != std::floor(value[0]))
      throw InputError(file, {cur.line(), {}}, "expected the scan's row count (a positive integer up to 2^31)");
    rows = static_cast<std::int64_t>(value[0]);
    double position[3], axes[9];
    read_numbers(cur, file, fields, 3, position, "scanner position");
    for (int a = 0; a < 3; ++a) read_numbers(cur, file, fields, 3, axes + 3 * a, "scanner axis");
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      read_numbers(cur, file, fields, 4, value, "transform row");
      for (int c = 0; c < 4; ++c) m(r, c) = value[c];
    }
    // Row vectors: world = [p 1] * M, the translation in the last row.
    const Eigen::Matrix3d linear = m.topLeftCorner<3, 3>();
    const Eigen::RowVector3d translation = m.block<1, 3>(3, 0);
    // Each grid line needs at least 6 bytes ("0 0 0\n"): a grid larger than the rest of the
    // file cannot be read and is refused before anything is reserved for it.
    const std::uint64_t cells = static_cast<std::uint64_t>(columns) * static_cast<std::uint64_t>(rows);
    if (columns > (std::int64_t{1} << 31) || rows > (std::int64_t{1} << 31) || cells > bytes.size() / 6)
      throw InputError(file, {header_line, {}},
                       "scan " + std::to_string(scan + 1) + " declares " + std::to_string(columns) + " x " +
                           std::to_string(rows) + " points, more than the file can hold");
    scanners.insert(scanners.end(), translation.data(), translation.data() + 3);
    for (std::uint64_t cell = 0; cell < cells; ++cell) {
      do {
        if (!cur.next_line(line))
          throw InputError(file, {cur.line(), {}},
                           "scan " + std::to_string(scan + 1) + " ends after " + std::to_string(cell) + " of " +
                               std::to_string(cells) + " points (" + std::to_string(columns) + " columns x " +
                               std::to_string(rows) + " rows)");
        split_fields(line, fields);
      } while (fields.empty());
      const std::size_t n_fields = fields.size();
      if (n_fields != 3 && n_fields != 4 && n_fields != 7)
        throw InputError(file, {cur.line(), {}},
                         "expected 3 (x y z), 4 (x y z intensity) or 7 (x y z intensity r g b) values, found " +
                             std::to_string(n_fields));
      const bool has_rgb = n_fields == 7;
      if (!colored) colored = has_rgb;
      else if (*colored != has_rgb)
        throw InputError(file, {cur.line(), {}}, has_rgb ? "a point has a color where earlier points have none"
                                                         : "a point has no color where earlier points have one");
      for (std::size_t k = 0; k < n_fields; ++k)
        if (!parse_double(fields[k], value[k]))
          throw InputError(file, {cur.line(), {}},
                           "expected a number in column " + std::to_string(k + 1) + ", found \"" +
                               std::string(fields[k].substr(0, 40)) + "\"");
      if (value[0] == 0 && value[1] == 0 && value[2] == 0) continue;  // no return
      const Eigen::RowVector3d p = Eigen::RowVector3d(value[0], value[1], value[2]) * linear + translation;
      if (!first_non_finite && !p.allFinite()) first_non_finite = FileLocation{cur.line(), std::nullopt};
      pos.insert(pos.end(), p.data(), p.data() + 3);
      // Intensities are small numbers; a value beyond float's range is clamped to it (NaN kept).
      constexpr double kMaxFloat = std::numeric_limits<float>::max();
      intensity.push_back(n_fields > 3 && !std::isnan(value[3]) ? static_cast<float>(std::clamp(value[3], -kMaxFloat, kMaxFloat))
                                                                 : n_fields > 3 ? std::numeric_limits<float>::quiet_NaN() : 0.0f);
      scan_of.push_back(scan);
      if (has_rgb)
        for (int k = 4; k < 7; ++k) rgb.push_back(static_cast<std::uint8_t>(std::lround(std::clamp(value[k], 0.0, 255.0))));
    }
  }
  if (scanners.empty()) throw InputError(file, {1, {}}, "file holds no scan (expected a PTX header: columns, rows, ...)");
  const auto n = static_cast<Eigen::Index>(pos.size() / 3);
  ParsedFile out;
  out.cloud.positions = Eigen::Map<Points>(pos.data(), n, 3);
  if (!rgb.empty()) out.cloud.colors = Eigen::Map<Colors>(rgb.data(), n, 3);
  out.cloud.attributes.push_back({"intensity", Eigen::Map<Eigen::VectorXf>(intensity.data(), n)});
  out.cloud.scanner_positions = Eigen::Map<Points>(scanners.data(), static_cast<Eigen::Index>(scanners.size() / 3), 3);
  out.cloud.scanner_of_point = std::move(scan_of);
  out.first_non_finite = first_non_finite;
  return out;
}

}  // namespace clustersurf::io
