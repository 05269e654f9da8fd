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
      throw InputError(file, {cur.line(), {}},
                       std::string("file ends where the scan header's ") + what + " was expected");
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

PtxLines::PtxLines(const std::filesystem::path& file, std::string_view bytes)
    : file_(file), cursor_(bytes, file_), bytes_(bytes.size()) {}

bool PtxLines::open_scan() {
  // The next scan's header begins at the next non-empty line, or the file ends.
  std::string_view line;
  std::uint64_t header_line = 0;
  bool more = true;
  do {
    more = cursor_.next_line(line);
    header_line = cursor_.line();
    split_fields(more ? line : std::string_view{}, fields_);
  } while (fields_.empty() && more);
  if (fields_.empty()) {
    if (scanners_.empty())
      throw InputError(file_, {1, {}}, "file holds no scan (expected a PTX header: columns, rows, ...)");
    return false;
  }
  const auto scan = scanners_.size() / 3;
  std::int64_t columns = 0, rows = 0;
  if (fields_.size() != 1 || !parse_int(fields_[0], columns) || columns <= 0)
    throw InputError(file_, {header_line, {}},
                     "expected the scan's column count (a positive integer) to start scan " + std::to_string(scan + 1));
  double value[16];
  read_numbers(cursor_, file_, fields_, 1, value, "row count");
  if (!(value[0] >= 1 && value[0] <= 2147483648.0) || value[0] != std::floor(value[0]))
    throw InputError(file_, {cursor_.line(), {}}, "expected the scan's row count (a positive integer up to 2^31)");
  rows = static_cast<std::int64_t>(value[0]);
  double position[3], axes[9];
  read_numbers(cursor_, file_, fields_, 3, position, "scanner position");
  for (int a = 0; a < 3; ++a) read_numbers(cursor_, file_, fields_, 3, axes + 3 * a, "scanner axis");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    read_numbers(cursor_, file_, fields_, 4, value, "transform row");
    for (int c = 0; c < 4; ++c) m(r, c) = value[c];
  }
  // Row vectors: world = [p 1] * M, the translation in the last row.
  linear_ = m.topLeftCorner<3, 3>();
  translation_ = m.block<1, 3>(3, 0);
  // Each grid line needs at least 6 bytes ("0 0 0\n"): a grid larger than the rest of the
  // file cannot be read and is refused before anything is reserved for it.
  const std::uint64_t cells = static_cast<std::uint64_t>(columns) * static_cast<std::uint64_t>(rows);
  if (columns > (std::int64_t{1} << 31) || rows > (std::int64_t{1} << 31) || cells > bytes_ / 6)
    throw InputError(file_, {header_line, {}},
                     "scan " + std::to_string(scan + 1) + " declares " + std::to_string(columns) + " x " +
                         std::to_string(rows) + " points, more than the file can hold");
  scanners_.insert(scanners_.end(), translation_.data(), translation_.data() + 3);
  columns_ = columns, rows_ = rows, cells_ = cells, cell_ = 0;
  return true;
}

bool PtxLines::next(PtxPoint& out) {
  std::string_view line;
  double value[7];
  for (;;) {
    while (cell_ == cells_)
      if (!open_scan()) return false;
    const auto scan = static_cast<std::uint32_t>(scanners_.size() / 3 - 1);
    do {
      if (!cursor_.next_line(line))
        throw InputError(file_, {cursor_.line(), {}},
                         "scan " + std::to_string(scan + 1) + " ends after " + std::to_string(cell_) + " of " +
                             std::to_string(cells_) + " points (" + std::to_string(columns_) + " columns x " +
                             std::to_string(rows_) + " rows)");
      split_fields(line, fields_);
    } while (fields_.empty());
    ++cell_;
    const std::size_t n_fields = fields_.size();
    if (n_fields != 3 && n_fields != 4 && n_fields != 7)
      throw InputError(file_, {cursor_.line(), {}},
                       "expected 3 (x y z), 4 (x y z intensity) or 7 (x y z intensity r g b) values, found " +
                           std::to_string(n_fields));
    const bool has_rgb = n_fields == 7;
    if (!colored_)
      colored_ = has_rgb;
    else if (*colored_ != has_rgb)
      throw InputError(file_, {cursor_.line(), {}},
                       has_rgb ? "a point has a color where earlier points have none"
                               : "a point has no color where earlier points have one");
    for (std::size_t k = 0; k < n_fields; ++k)
      if (!parse_double(fields_[k], value[k]))
        throw InputError(file_, {cursor_.line(), {}},
                         "expected a number in column " + std::to_string(k + 1) + ", found \"" +
                             std::string(fields_[k].substr(0, 40)) + "\"");
    if (value[0] == 0 && value[1] == 0 && value[2] == 0) continue;  // no return
    out.position = (Eigen::RowVector3d(value[0], value[1], value[2]) * linear_ + translation_).transpose();
    // Intensities are small numbers; a value beyond float's range is clamped to it (NaN kept).
    constexpr double kMaxFloat = std::numeric_limits<float>::max();
    out.intensity = n_fields > 3 && !std::isnan(value[3])
                        ? static_cast<float>(std::clamp(value[3], -kMaxFloat, kMaxFloat))
                    : n_fields > 3 ? std::numeric_limits<float>::quiet_NaN()
                                   : 0.0f;
    if (has_rgb)
      for (int k = 0; k < 3; ++k)
        out.rgb[static_cast<std::size_t>(k)] =
            static_cast<std::uint8_t>(std::lround(std::clamp(value[4 + k], 0.0, 255.0)));
    out.scan = scan;
    return true;
  }
}

ParsedFile read_ptx(const std::filesystem::path& file, std::string_view bytes) {
  PtxLines ptx(file, bytes);
  std::vector<double> pos;
  std::vector<std::uint8_t> rgb;
  std::vector<float> intensity;
  std::vector<std::uint32_t> scan_of;
  std::optional<FileLocation> first_non_finite;
  PtxPoint p;
  while (ptx.next(p)) {
    if (!first_non_finite && !p.position.allFinite()) first_non_finite = FileLocation{ptx.line(), std::nullopt};
    pos.insert(pos.end(), p.position.data(), p.position.data() + 3);
    intensity.push_back(p.intensity);
    scan_of.push_back(p.scan);
    if (ptx.colored().value_or(false)) rgb.insert(rgb.end(), p.rgb.begin(), p.rgb.end());
  }
  const auto n = static_cast<Eigen::Index>(pos.size() / 3);
  ParsedFile out;
  out.cloud.positions = Eigen::Map<Points>(pos.data(), n, 3);
  if (!rgb.empty()) out.cloud.colors = Eigen::Map<Colors>(rgb.data(), n, 3);
  out.cloud.attributes.push_back({"intensity", Eigen::Map<Eigen::VectorXf>(intensity.data(), n)});
  const std::vector<double>& scanners = ptx.scanners();
  out.cloud.scanner_positions =
      Eigen::Map<const Points>(scanners.data(), static_cast<Eigen::Index>(scanners.size() / 3), 3);
  out.cloud.scanner_of_point = std::move(scan_of);
  out.first_non_finite = first_non_finite;
  return out;
}

}  // namespace clustersurf::io
