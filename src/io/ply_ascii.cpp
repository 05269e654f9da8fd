// The ascii PLY data: whitespace-separated numbers, records located by line.

#include "io/ply_format.hpp"
#include "io/text_parse.hpp"

#include <cmath>

namespace clustersurf::io::ply {

namespace {

/// The records of an ascii PLY body, token by token, each failure located by line.
class AsciiBody {
 public:
  AsciiBody(const std::filesystem::path& file, std::string_view bytes, const Header& h)
      : file_(file), cur_(bytes.substr(h.data_offset), file, h.data_line), vertex_count_(declared_vertices(h)) {}

  /// Reads the `e.count` records of `e`: into `vertices` when given, their faces into `faces` when `face_prop` >= 0.
  void read_element(const Element& e, std::optional<VertexRecords>& vertices, int face_prop, FaceSink& faces) {
    values_.resize(e.properties.size());
    for (std::uint64_t i = 0; i < e.count; ++i) {
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (!p.is_list) {
          const double v = number(e, i, p);
          if (k == 0) record_line_ = cur_.line();
          values_[k] = v;
          continue;
        }
        const std::int64_t c = list_length(e, i, p);
        if (k == 0) record_line_ = cur_.line();
        if (static_cast<int>(k) == face_prop) faces.poly.clear();
        for (std::int64_t j = 0; j < c; ++j) {
          const double v = number(e, i, p);
          if (static_cast<int>(k) == face_prop) faces.poly.push_back(vertex_index(v));
        }
      }
      const FileLocation where{record_line_, std::nullopt};
      if (vertices)
        vertices->fill(
            static_cast<Eigen::Index>(i), [&](int k) { return values_[static_cast<std::size_t>(k)]; }, where);
      if (face_prop >= 0) faces.emit(vertex_count_, file_, where);
    }
  }

  /// Fails when text follows the last element.
  void expect_end() {
    if (const std::string_view extra = cur_.next_token(); !extra.empty())
      fail_line(file_, cur_.line(),
                "unexpected data \"" + std::string(extra.substr(0, 40)) +
                    "\" after the last element (counts in the header too small?)");
  }

 private:
  /// The next token as a number of property `p` (integral for integer types).
  double number(const Element& e, std::uint64_t i, const Property& p) {
    const std::string_view t = cur_.next_token();
    last_token_ = t.substr(0, 40);
    if (t.empty())
      fail_line(file_, cur_.line(), "file ends inside " + element_what(e, i) + " (property " + p.name + ")");
    double v;
    if (!parse_double(t, v))
      fail_line(file_, cur_.line(),
                "expected a number for property \"" + p.name + "\" of " + element_what(e, i) + ", found \"" +
                    std::string(last_token_) + "\"");
    if (is_integer_type(p.type) && (!std::isfinite(v) || v != std::floor(v)))
      fail_line(file_, cur_.line(),
                "expected an integer for property \"" + p.name + "\" of " + element_what(e, i) + ", found \"" +
                    std::string(last_token_) + "\"");
    return v;
  }

  /// The next token as the length of list property `p`.
  std::int64_t list_length(const Element& e, std::uint64_t i, const Property& p) {
    const std::string_view t = cur_.next_token();
    if (t.empty()) fail_line(file_, cur_.line(), "file ends inside " + element_what(e, i));
    std::int64_t c;
    if (!parse_int(t, c) || c < 0)
      fail_line(file_, cur_.line(),
                "expected a list length for \"" + p.name + "\" of " + element_what(e, i) + ", found \"" +
                    std::string(t.substr(0, 40)) + "\"");
    if (c > 1'000'000) fail_line(file_, cur_.line(), "list length " + std::to_string(c) + " is implausible");
    return c;
  }

  /// An integral face index; beyond any vertex count (and int64, where the cast would be undefined) it fails.
  std::int64_t vertex_index(double v) const {
    if (!(std::abs(v) <= 1e18))
      fail_line(file_, cur_.line(),
                "face refers to vertex " + std::string(last_token_) + " but there are " +
                    std::to_string(vertex_count_) + " vertices");
    return static_cast<std::int64_t>(v);
  }

  const std::filesystem::path& file_;
  TextCursor cur_;
  std::int64_t vertex_count_;
  std::uint64_t record_line_ = 0;
  std::string_view last_token_;  // the token number() parsed last, for messages
  std::vector<double> values_;
};

}  // namespace

ParsedFile read_ascii(const std::filesystem::path& file, std::string_view bytes, const Header& h, bool want_faces) {
  ParsedFile out;
  AsciiBody body(file, bytes, h);
  bool seen_vertex = false;
  FaceSink faces;
  for (const Element& e : h.elements) {
    std::optional<VertexRecords> vertices;
    if (e.name == "vertex" && !seen_vertex) {
      seen_vertex = true;
      vertices.emplace(file, e, out);
    }
    const int face_prop = want_faces && e.name == "face" ? face_index_property(file, e) : -1;
    if (!e.properties.empty()) body.read_element(e, vertices, face_prop, faces);  // no values take no text
  }
  body.expect_end();
  finish(file, seen_vertex, want_faces, faces, out);
  return out;
}

}  // namespace clustersurf::io::ply
