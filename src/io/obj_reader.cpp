// OBJ reader: `v x y z [w | r g b]`, `vn` (used when there is one per `v`), `f` (fan-triangulated,
// `i`, `i/t`, `i//n`, `i/t/n` and negative indices); every other statement is ignored.

#include "io/readers.hpp"
#include "io/text_parse.hpp"

#include <clustersurf/core/errors.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace clustersurf::io {

ParsedFile read_obj(const std::filesystem::path& file, std::string_view bytes, bool want_faces) {
  TextCursor cur(bytes, file);
  std::vector<std::string_view> fields;
  std::vector<double> pos, nrm;
  std::vector<std::uint8_t> rgb;
  std::vector<std::int32_t> tri;
  std::vector<std::int64_t> poly;
  std::size_t colored = 0;
  // (point index, line) of the first non-finite `v` and `vn`, for the error message.
  std::optional<std::pair<std::size_t, std::uint64_t>> bad_v, bad_vn;
  std::string_view line;
  auto numbers = [&](std::size_t first, std::size_t count, double* out) {
    for (std::size_t k = 0; k < count; ++k)
      if (!parse_double(fields[first + k], out[k]))
        throw InputError(file, {cur.line(), {}},
                         "expected a number, found \"" + std::string(fields[first + k].substr(0, 40)) + "\"");
  };
  while (cur.next_line(line)) {
    split_fields(line, fields);
    if (fields.empty()) continue;
    const std::string_view kw = fields[0];
    if (kw == "v") {
      const std::size_t n = fields.size() - 1;
      if (n != 3 && n != 4 && n != 6)
        throw InputError(file, {cur.line(), {}},
                         "expected \"v x y z [w]\" or \"v x y z r g b\", found " + std::to_string(n) + " values");
      double v[6];
      numbers(1, n, v);
      if (!bad_v && !(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])))
        bad_v = std::pair{pos.size() / 3, cur.line()};
      pos.insert(pos.end(), v, v + 3);
      if (n == 6) {
        ++colored;
        for (int k = 3; k < 6; ++k)
          rgb.push_back(static_cast<std::uint8_t>(std::lround(std::clamp(v[k], 0.0, 1.0) * 255.0)));
      } else {
        rgb.insert(rgb.end(), 3, 0);
      }
    } else if (kw == "vn") {
      if (fields.size() != 4) throw InputError(file, {cur.line(), {}}, "expected \"vn x y z\"");
      double v[3];
      numbers(1, 3, v);
      if (!bad_vn && !(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])))
        bad_vn = std::pair{nrm.size() / 3, cur.line()};
      nrm.insert(nrm.end(), v, v + 3);
    } else if (kw == "f" && want_faces) {
      if (fields.size() < 4) throw InputError(file, {cur.line(), {}}, "a face needs at least 3 vertices");
      poly.clear();
      const auto nv = static_cast<std::int64_t>(pos.size() / 3);
      for (std::size_t k = 1; k < fields.size(); ++k) {
        std::string_view t = fields[k].substr(0, fields[k].find('/'));
        std::int64_t idx;
        if (!parse_int(t, idx) || idx == 0)
          throw InputError(file, {cur.line(), {}},
                           "expected a vertex index, found \"" + std::string(fields[k].substr(0, 40)) + "\"");
        idx = idx > 0 ? idx - 1 : nv + idx;
        if (idx < 0 || idx >= nv)
          throw InputError(
              file, {cur.line(), {}},
              "face refers to vertex " + std::string(t) + " but only " + std::to_string(nv) + " are defined before it");
        poly.push_back(idx);
      }
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
        tri.push_back(static_cast<std::int32_t>(poly[0]));
        tri.push_back(static_cast<std::int32_t>(poly[k]));
        tri.push_back(static_cast<std::int32_t>(poly[k + 1]));
      }
    }
  }
  const auto n = static_cast<Eigen::Index>(pos.size() / 3);
  ParsedFile out;
  out.cloud.positions = Eigen::Map<Points>(pos.data(), n, 3);
  const bool normals = n > 0 && nrm.size() == pos.size();
  if (normals) out.cloud.normals = Eigen::Map<Points>(nrm.data(), n, 3);
  if (normals && bad_vn && (!bad_v || bad_vn->first < bad_v->first)) bad_v = bad_vn;
  if (bad_v) out.first_non_finite = FileLocation{bad_v->second, std::nullopt};
  if (colored != 0 && colored == static_cast<std::size_t>(n)) out.cloud.colors = Eigen::Map<Colors>(rgb.data(), n, 3);
  out.triangles = Eigen::Map<Triangles>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
  return out;
}

}  // namespace clustersurf::io
