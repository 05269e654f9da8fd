// XYZ / PTS / TXT / CSV reader: one point per line, fields separated by whitespace and/or commas,
// '#' starts a comment. Columns: 3 (x y z), 4 (x y z intensity), 6 (x y z nx ny nz) or
// 7 (x y z intensity r g b, the PTS layout). A first line holding a single integer is a point
// count (PTS) and must match.

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

std::size_t XyzLines::next(std::array<double, 7>& v) {
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
      if (columns_ != 3 && columns_ != 4 && columns_ != 6 && columns_ != 7)
        throw InputError(
            file_, {cursor_.line(), {}},
            "expected 3 (x y z), 4 (x y z i), 6 (x y z nx ny nz) or 7 (x y z i r g b) values per line, found " +
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
    ++points_;
    return columns_;
  }
  if (declared_ >= 0 && static_cast<std::uint64_t>(declared_) != points_)
    throw InputError(
        file_, {declared_line_, {}},
        "the count line says " + std::to_string(declared_) + " points but the file has " + std::to_string(points_));
  return 0;
}

ParsedFile read_xyz(const std::filesystem::path& file, std::string_view bytes) {
  XyzLines lines(file, bytes);
  std::vector<double> pos, nrm;
  std::vector<std::uint8_t> rgb;
  std::array<double, 7> v{};
  std::optional<FileLocation> first_non_finite;
  for (std::size_t columns; (columns = lines.next(v)) != 0;) {
    pos.insert(pos.end(), v.begin(), v.begin() + 3);
    if (columns == 6) nrm.insert(nrm.end(), v.begin() + 3, v.begin() + 6);
    if (!first_non_finite &&
        !std::all_of(v.begin(), v.begin() + (columns == 6 ? 6 : 3), [](double x) { return std::isfinite(x); }))
      first_non_finite = FileLocation{lines.line(), std::nullopt};
    if (columns == 7)
      for (int k = 4; k < 7; ++k)
        rgb.push_back(static_cast<std::uint8_t>(std::lround(std::clamp(v[static_cast<std::size_t>(k)], 0.0, 255.0))));
  }
  const auto n = static_cast<Eigen::Index>(pos.size() / 3);
  ParsedFile out;
  out.cloud.positions = Eigen::Map<Points>(pos.data(), n, 3);
  if (!nrm.empty()) out.cloud.normals = Eigen::Map<Points>(nrm.data(), n, 3);
  if (!rgb.empty()) out.cloud.colors = Eigen::Map<Colors>(rgb.data(), n, 3);
  out.first_non_finite = first_non_finite;
  return out;
}

}  // namespace clustersurf::io
