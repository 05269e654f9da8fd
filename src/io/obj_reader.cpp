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

namespace {

/// The statements of an OBJ file gathered line by line, each failure located by line.
class ObjStatements {
 public:
  ObjStatements(const std::filesystem::path& file, const TextCursor& cur) : file_(file), cur_(cur) {}

  /// `v x y z [w]` or `v x y z r g b`.
  void vertex(const std::vector<std::string_view>& fields) {
    const std::size_t n = fields.size() - 1;
    if (n != 3 && n != 4 && n != 6)
      fail("expected \"v x y z [w]\" or \"v x y z r g b\", found " + std::to_string(n) + " values");
    double v[6];
    numbers(fields, n, v);
    if (!bad_v_ && !(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])))
      bad_v_ = std::pair{pos_.size() / 3, cur_.line()};
    pos_.insert(pos_.end(), v, v + 3);
    if (n == 6) {
      ++colored_;
      for (int k = 3; k < 6; ++k)
        rgb_.push_back(static_cast<std::uint8_t>(std::lround(std::clamp(v[k], 0.0, 1.0) * 255.0)));
    } else {
      rgb_.insert(rgb_.end(), 3, 0);
    }
  }

  /// `vn x y z`.
  void normal(const std::vector<std::string_view>& fields) {
    if (fields.size() != 4) fail("expected \"vn x y z\"");
    double v[3];
    numbers(fields, 3, v);
    if (!bad_vn_ && !(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])))
      bad_vn_ = std::pair{nrm_.size() / 3, cur_.line()};
    nrm_.insert(nrm_.end(), v, v + 3);
  }

  /// `f i j k ...` over the vertices defined so far, fan-triangulated.
  void face(const std::vector<std::string_view>& fields) {
    if (fields.size() < 4) fail("a face needs at least 3 vertices");
    poly_.clear();
    const auto nv = static_cast<std::int64_t>(pos_.size() / 3);
    for (std::size_t k = 1; k < fields.size(); ++k) {
      const std::string_view t = fields[k].substr(0, fields[k].find('/'));
      std::int64_t idx;
      if (!parse_int(t, idx) || idx == 0)
        fail("expected a vertex index, found \"" + std::string(fields[k].substr(0, 40)) + "\"");
      idx = idx > 0 ? idx - 1 : nv + idx;
      if (idx < 0 || idx >= nv)
        fail("face refers to vertex " + std::string(t) + " but only " + std::to_string(nv) + " are defined before it");
      poly_.push_back(idx);
    }
    for (std::size_t k = 1; k + 1 < poly_.size(); ++k) {
      tri_.push_back(static_cast<std::int32_t>(poly_[0]));
      tri_.push_back(static_cast<std::int32_t>(poly_[k]));
      tri_.push_back(static_cast<std::int32_t>(poly_[k + 1]));
    }
  }

  /// The cloud (normals when there is one per vertex, colors when every vertex has them) and the triangles.
  ParsedFile result() {
    const auto n = static_cast<Eigen::Index>(pos_.size() / 3);
    ParsedFile out;
    out.cloud.positions = Eigen::Map<Points>(pos_.data(), n, 3);
    const bool normals = n > 0 && nrm_.size() == pos_.size();
    if (normals) out.cloud.normals = Eigen::Map<Points>(nrm_.data(), n, 3);
    if (normals && bad_vn_ && (!bad_v_ || bad_vn_->first < bad_v_->first)) bad_v_ = bad_vn_;
    if (bad_v_) out.first_non_finite = FileLocation{bad_v_->second, std::nullopt};
    if (colored_ != 0 && colored_ == static_cast<std::size_t>(n))
      out.cloud.colors = Eigen::Map<Colors>(rgb_.data(), n, 3);
    out.triangles = Eigen::Map<Triangles>(tri_.data(), static_cast<Eigen::Index>(tri_.size() / 3), 3);
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { throw InputError(file_, {cur_.line(), {}}, message); }

  /// fields[1 .. count] as numbers.
  void numbers(const std::vector<std::string_view>& fields, std::size_t count, double* out) const {
    for (std::size_t k = 0; k < count; ++k)
      if (!parse_double(fields[1 + k], out[k]))
        fail("expected a number, found \"" + std::string(fields[1 + k].substr(0, 40)) + "\"");
  }

  const std::filesystem::path& file_;
  const TextCursor& cur_;
  std::vector<double> pos_, nrm_;
  std::vector<std::uint8_t> rgb_;
  std::vector<std::int32_t> tri_;
  std::vector<std::int64_t> poly_;
  std::size_t colored_ = 0;
  // (point index, line) of the first non-finite `v` and `vn`, for the error message.
  std::optional<std::pair<std::size_t, std::uint64_t>> bad_v_, bad_vn_;
};

}  // namespace

ParsedFile read_obj(const std::filesystem::path& file, std::string_view bytes, bool want_faces) {
  TextCursor cur(bytes, file);
  ObjStatements statements(file, cur);
  std::vector<std::string_view> fields;
  std::string_view line;
  while (cur.next_line(line)) {
    split_fields(line, fields);
    if (fields.empty()) continue;
    const std::string_view kw = fields[0];
    if (kw == "v")
      statements.vertex(fields);
    else if (kw == "vn")
      statements.normal(fields);
    else if (kw == "f" && want_faces)
      statements.face(fields);
  }
  return statements.result();
}

}  // namespace clustersurf::io
