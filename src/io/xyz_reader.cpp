// XYZ / PTS / TXT / CSV reader: one point per line, fields separated by whitespace and/or commas,
// '#' starts a comment. Columns: 3 (x y z), 4 (x y z intensity), 6 (x y z nx ny nz) or
// 7 (x y z intensity r g b, the PTS layout). A first line holding a single integer is a point
// count (PTS) and must match.

#include "io/readers.hpp"
#include "io/text_parse.hpp"

#include <clustersurf/errors.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf::io {

ParsedFile read_xyz(const std::filesystem::path& file, std::string_view bytes) {
  TextCursor cur(bytes, file);
  std::vector<std::string_view> fields;
  std::vector<double> pos, nrm;
  std::vector<std::uint8_t> rgb;
  std::size_t columns = 0;
  std::uint64_t columns_line = 0;
  std::int64_t declared = -1;
  std::uint64_t declared_line = 0;
  std::string_view line;
  double v[7];
  std::optional<FileLocation> first_non_finite;
  while (cur.next_line(line)) {
    split_fields(line, fields);
    if (fields.empty()) continue;
    if (columns == 0 && declared < 0 && pos.empty() && fields.size() == 1) {
      if (!parse_int(fields[0], declared) || declared < 0)
        throw InputError(file, {cur.line(), {}}, "expected \"x y z\" or a point count, found \"" + std::string(fields[0].substr(0, 40)) + "\"");
      declared_line = cur.line();
      continue;
    }
    if (columns == 0) {
      columns = fields.size();
      columns_line = cur.line();
      if (columns != 3 && columns != 4 && columns != 6 && columns != 7)
        throw InputError(file, {cur.line(), {}},
                         "expected 3 (x y z), 4 (x y z i), 6 (x y z nx ny nz) or 7 (x y z i r g b) values per line, found " +
                             std::to_string(columns));
    } else if (fields.size() != columns) {
      throw InputError(file, {cur.line(), {}},
                       "expected " + std::to_string(columns) + " values as on line " + std::to_string(columns_line) +
                           ", found " + std::to_string(fields.size()));
    }
    for (std::size_t k = 0; k < columns; ++k)
      if (!parse_double(fields[k], v[k]))
        throw InputError(file, {cur.line(), {}},
                         "expected a number in column " + std::to_string(k + 1) + ", found \"" +
                             std::string(fields[k].substr(0, 40)) + "\"");
    pos.insert(pos.end(), v, v + 3);
    if (columns == 6) nrm.insert(nrm.end(), v + 3, v + 6);
    if (!first_non_finite && !std::all_of(v, v + (columns == 6 ? 6 : 3), [](double x) { return std::isfinite(x); }))
      first_non_finite = FileLocation{cur.line(), std::nullopt};
    if (columns == 7)
      for (int k = 4; k < 7; ++k) rgb.push_back(static_cast<std::uint8_t>(std::lround(std::clamp(v[k], 0.0, 255.0))));
  }
  const auto n = static_cast<Eigen::Index>(pos.size() / 3);
  if (declared >= 0 && declared != n)
    throw InputError(file, {declared_line, {}},
                     "the count line says " + std::to_string(declared) + " points but the file has " + std::to_string(n));
  ParsedFile out;
  out.cloud.positions = Eigen::Map<Points>(pos.data(), n, 3);
  if (!nrm.empty()) out.cloud.normals = Eigen::Map<Points>(nrm.data(), n, 3);
  if (!rgb.empty()) out.cloud.colors = Eigen::Map<Colors>(rgb.data(), n, 3);
  out.first_non_finite = first_non_finite;
  return out;
}

}  // namespace clustersurf::io
