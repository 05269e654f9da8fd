// XYZ / PTS / TXT / CSV reader: one point per line, fields separated by whitespace and/or commas,
// '#' starts a comment. Columns: 3 (x y z), 4 (x y z intensity), 6 (x y z nx ny nz, or x y z r g
// b), 7 (x y z intensity r g b, the PTS layout) or 9 (x y z r g b nx ny nz, or normals first). A
// first line holding a single integer is a point count (PTS) and must match.

#include "io/readers.hpp"
#include "io/text_parse.hpp"

#include <clustersurf/core/errors.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf::io {

XyzLines::XyzLines(const std::filesystem::path& file, std::string_view bytes) : file_(file), cursor_(bytes, file_) {}

std::size_t XyzLines::next(std::array<double, kMaxColumns>& v) {
  std::string_view line;
  while (cursor_.next_line(line)) {
    split_fields(line, fields_);
    if (fields_.empty()) continue;
    if (columns_ == 0 && declared_ < 0 && points_ == 0 && fields_.size() == 1) {
      if (!parse_int(fields_[0], declared_) || declared_ < 0)
        throw InputError(
            file_, {cursor_.line(), {}},
            "expected \"x y z\" or a point count, found \"" + std::string(fields_[0].substr(0, 40)) + "\"");
      declared_line_ = cursor_.line();
      continue;
    }
    if (columns_ == 0) {
      columns_ = fields_.size();
      columns_line_ = cursor_.line();
      if (columns_ != 3 && columns_ != 4 && columns_ != 6 && columns_ != 7 && columns_ != 9)
        throw InputError(file_, {cursor_.line(), {}},
                         "expected 3 (x y z), 4 (x y z i), 6 (x y z nx ny nz, or x y z r g b), 7 (x y z i r g b) or "
                         "9 (x y z r g b nx ny nz) values per line, found " +
                             std::to_string(columns_));
    } else if (fields_.size() != columns_) {
      throw InputError(file_, {cursor_.line(), {}},
                       "expected " + std::to_string(columns_) + " values as on line " + std::to_string(columns_line_) +
                           ", found " + std::to_string(fields_.size()));
    }
    for (std::size_t k = 0; k < columns_; ++k)
      if (!parse_double(fields_[k], v[k]))
        throw InputError(file_, {cursor_.line(), {}},
                         "expected a number in column " + std::to_string(k + 1) + ", found \"" +
                             std::string(fields_[k].substr(0, 40)) + "\"");
    for (std::size_t t = 0; t < 2; ++t)
      for (std::size_t k = 3 * (t + 1); k < std::min(columns_, 3 * (t + 2)); ++k) {
        byte_triple_[t] = byte_triple_[t] && v[k] >= 0 && v[k] <= 255 && v[k] == std::floor(v[k]);
        above_one_[t] = above_one_[t] || v[k] > 1;
      }
    ++points_;
    return columns_;
  }
  if (declared_ >= 0 && static_cast<std::uint64_t>(declared_) != points_)
    throw InputError(
        file_, {declared_line_, {}},
        "the count line says " + std::to_string(declared_) + " points but the file has " + std::to_string(points_));
  return 0;
}

XyzLayout XyzLines::layout() const noexcept {
  const auto colors_at = [&](std::size_t t) { return byte_triple_[t] && above_one_[t]; };
  XyzLayout l;
  switch (columns_) {
    case 4:
      l.intensity = 3;
      break;
    case 6:
      (colors_at(0) ? l.colors : l.normals) = 3;
      break;
    case 7:
      l.intensity = 3, l.colors = 4;
      break;
    case 9: {
      const bool normals_first = colors_at(1) && !colors_at(0);
      l.colors = normals_first ? 6 : 3;
      l.normals = normals_first ? 3 : 6;
      break;
    }
    default:
      break;
  }
  return l;
}

/// A color channel's byte from its value in the text (0 where it is not a number).
std::uint8_t text_color_byte(double value) {
  return std::isfinite(value) ? static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0))) : 0;
}

ParsedFile read_xyz(const std::filesystem::path& file, std::string_view bytes) {
  XyzLines lines(file, bytes);
  // Each line's values past x y z are kept until the whole file says what they are; so is the
  // first line where each triple of values is not finite.
  std::vector<double> pos, rest;
  std::array<double, XyzLines::kMaxColumns> v{};
  std::array<std::optional<std::uint64_t>, 3> not_finite;  // x y z, columns 4-6, columns 7-9
  std::size_t columns = 0;
  for (std::size_t c; (c = lines.next(v)) != 0;) {
    columns = c;
    pos.insert(pos.end(), v.begin(), v.begin() + 3);
    rest.insert(rest.end(), v.begin() + 3, v.begin() + static_cast<std::ptrdiff_t>(c));
    for (std::size_t t = 0; t < 3; ++t)
      if (!not_finite[t] && 3 * t + 3 <= c &&
          !std::all_of(v.begin() + static_cast<std::ptrdiff_t>(3 * t),
                       v.begin() + static_cast<std::ptrdiff_t>(3 * t + 3), [](double x) { return std::isfinite(x); }))
        not_finite[t] = lines.line();
  }
  const XyzLayout layout = lines.layout();
  const std::size_t extra = columns > 3 ? columns - 3 : 0;
  const auto n = static_cast<Eigen::Index>(pos.size() / 3);
  std::vector<double> nrm;
  std::vector<std::uint8_t> rgb;
  Eigen::VectorXf intensity(layout.intensity >= 0 ? n : 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* r = rest.data() + static_cast<std::size_t>(i) * extra;
    if (layout.intensity >= 0) intensity(i) = static_cast<float>(r[layout.intensity - 3]);
    if (layout.normals >= 0) nrm.insert(nrm.end(), r + layout.normals - 3, r + layout.normals);
    if (layout.colors >= 0)
      for (int k = 0; k < 3; ++k) rgb.push_back(text_color_byte(r[layout.colors - 3 + k]));
  }
  std::optional<std::uint64_t> first = not_finite[0];
  if (layout.normals >= 0)
    if (const auto& at = not_finite[static_cast<std::size_t>(layout.normals / 3)]; at && (!first || *at < *first))
      first = at;
  ParsedFile out;
  out.cloud.positions = Eigen::Map<Points>(pos.data(), n, 3);
  if (!nrm.empty()) out.cloud.normals = Eigen::Map<Points>(nrm.data(), n, 3);
  if (!rgb.empty()) out.cloud.colors = Eigen::Map<Colors>(rgb.data(), n, 3);
  if (layout.intensity >= 0) out.cloud.attributes.push_back({"intensity", std::move(intensity)});
  if (first) out.first_non_finite = FileLocation{*first, std::nullopt};
  return out;
}

}  // namespace clustersurf::io
