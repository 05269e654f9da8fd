// The ascii PLY data: whitespace-separated numbers, records located by line.

#include "io/ply_format.hpp"
#include "io/text_parse.hpp"

#include <cmath>

namespace clustersurf::io::ply {

ParsedFile read_ascii(const std::filesystem::path& file, std::string_view bytes, const Header& h, bool want_faces) {
  ParsedFile out;
  TextCursor cur(bytes.substr(h.data_offset), file, h.data_line);
  bool seen_vertex = false;
  const std::int64_t vertex_count = declared_vertices(h);
  FaceSink faces;
  std::uint64_t record_line = 0;

  std::string_view last_token;  // the token number() parsed last, for messages
  auto number = [&](const Element& e, std::uint64_t i, const Property& p) {
    const std::string_view t = cur.next_token();
    last_token = t.substr(0, 40);
    if (t.empty()) fail_line(file, cur.line(), "file ends inside " + element_what(e, i) + " (property " + p.name + ")");
    double v;
    if (!parse_double(t, v))
      fail_line(file, cur.line(),
                "expected a number for property \"" + p.name + "\" of " + element_what(e, i) + ", found \"" +
                    std::string(t.substr(0, 40)) + "\"");
    if (is_integer_type(p.type) && (!std::isfinite(v) || v != std::floor(v)))
      fail_line(file, cur.line(),
                "expected an integer for property \"" + p.name + "\" of " + element_what(e, i) + ", found \"" +
                    std::string(t.substr(0, 40)) + "\"");
    return v;
  };
  auto list_length = [&](const Element& e, std::uint64_t i, const Property& p) {
    const std::string_view t = cur.next_token();
    if (t.empty()) fail_line(file, cur.line(), "file ends inside " + element_what(e, i));
    std::int64_t c;
    if (!parse_int(t, c) || c < 0)
      fail_line(file, cur.line(),
                "expected a list length for \"" + p.name + "\" of " + element_what(e, i) + ", found \"" +
                    std::string(t.substr(0, 40)) + "\"");
    if (c > 1'000'000) fail_line(file, cur.line(), "list length " + std::to_string(c) + " is implausible");
    return c;
  };

  std::vector<double> values;
  for (const Element& e : h.elements) {
    const bool is_vertex = e.name == "vertex" && !seen_vertex;
    const bool is_face = want_faces && e.name == "face";
    std::optional<VertexRecords> vertices;
    if (is_vertex) {
      seen_vertex = true;
      vertices.emplace(file, e, out);
      values.resize(e.properties.size());
    }
    const int face_prop = is_face ? face_index_property(file, e) : -1;
    if (e.properties.empty()) continue;  // records without values take no text
    for (std::uint64_t i = 0; i < e.count; ++i) {
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (!p.is_list) {
          const double v = number(e, i, p);
          if (k == 0) record_line = cur.line();
          if (is_vertex) values[k] = v;
          continue;
        }
        const std::int64_t c = list_length(e, i, p);
        if (k == 0) record_line = cur.line();
        if (static_cast<int>(k) == face_prop) faces.poly.clear();
        for (std::int64_t j = 0; j < c; ++j) {
          const double v = number(e, i, p);
          if (static_cast<int>(k) == face_prop) {
            // Integral but beyond any vertex count (and beyond int64: the cast would be undefined).
            if (!(std::abs(v) <= 1e18))
              fail_line(file, cur.line(),
                        "face refers to vertex " + std::string(last_token) + " but there are " +
                            std::to_string(vertex_count) + " vertices");
            faces.poly.push_back(static_cast<std::int64_t>(v));
          }
        }
      }
      if (vertices)
        vertices->fill(
            static_cast<Eigen::Index>(i), [&](int k) { return values[static_cast<std::size_t>(k)]; },
            FileLocation{record_line, std::nullopt});
      if (face_prop >= 0) faces.emit(vertex_count, file, FileLocation{record_line, std::nullopt});
    }
  }
  if (const std::string_view extra = cur.next_token(); !extra.empty())
    fail_line(file, cur.line(),
              "unexpected data \"" + std::string(extra.substr(0, 40)) +
                  "\" after the last element (counts in the header too small?)");
  finish(file, seen_vertex, want_faces, faces, out);
  return out;
}

}  // namespace clustersurf::io::ply
