// The binary PLY data (little or big endian): records walked byte by byte, every count checked
// against the bytes left.

#include "io/ply_format.hpp"
#include "io/text_parse.hpp"

#include <bit>
#include <cstring>

namespace clustersurf::io::ply {

ParsedFile read_binary(const std::filesystem::path& file, std::string_view bytes, const Header& h, bool want_faces) {
  const bool swap = (h.encoding == Encoding::BinaryBig) != (std::endian::native == std::endian::big);
  ParsedFile out;
  const char* const base = bytes.data();
  std::size_t off = h.data_offset;
  const std::size_t size = bytes.size();
  bool seen_vertex = false;
  const std::int64_t vertex_count = declared_vertices(h);
  FaceSink faces;

  auto need = [&](std::size_t n, const Element& e, std::uint64_t i) {
    if (n > size - off)
      fail_byte(file, off,
                "file ends inside " + element_what(e, i) + " (needs " + std::to_string(n) + " more bytes, " +
                    std::to_string(size - off) + " left)");
  };

  for (const Element& e : h.elements) {
    const bool is_vertex = e.name == "vertex" && !seen_vertex;
    const bool is_face = want_faces && e.name == "face";
    if (is_vertex) {
      seen_vertex = true;
      VertexRecords vertices(file, e, out);
      const auto n = static_cast<Eigen::Index>(e.count);
      // Offsets of each scalar property inside a record (records have no lists in practice; with
      // lists we compute them per record).
      std::vector<std::size_t> offsets(e.properties.size());
      const bool fixed = !e.has_lists();
      std::size_t record = 0;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        offsets[k] = record;
        record += scalar_size(e.properties[k].type);
      }
      auto get = [&](const char* rec, int idx) {
        const auto k = static_cast<std::size_t>(idx);
        return load_scalar(rec + offsets[k], e.properties[k].type, swap);
      };
      for (Eigen::Index i = 0; i < n; ++i) {
        if (!fixed) {
          record = 0;
          for (std::size_t k = 0; k < e.properties.size(); ++k) {
            need(record + scalar_size(e.properties[k].is_list ? e.properties[k].count_type : e.properties[k].type), e,
                 static_cast<std::uint64_t>(i));
            offsets[k] = record;
            if (e.properties[k].is_list) {
              const double c = load_scalar(base + off + record, e.properties[k].count_type, swap);
              if (c < 0)
                fail_byte(file, off + record,
                          "negative list length in " + element_what(e, static_cast<std::uint64_t>(i)));
              record += scalar_size(e.properties[k].count_type) +
                        static_cast<std::size_t>(c) * scalar_size(e.properties[k].type);
            } else {
              record += scalar_size(e.properties[k].type);
            }
          }
        }
        need(record, e, static_cast<std::uint64_t>(i));
        const char* rec = base + off;
        vertices.fill(
            i, [&](int k) { return get(rec, k); }, FileLocation{std::nullopt, off});
        off += record;
      }
      continue;
    }
    // Any other element: walk it (faces are collected when asked for).
    const int face_prop = is_face ? face_index_property(file, e) : -1;
    if (!e.has_lists()) {
      const std::uint64_t rec = e.min_binary_record();
      if (rec != 0 && e.count > (size - off) / rec)
        fail_byte(file, off + ((size - off) / rec) * rec, "file ends inside " + element_what(e, (size - off) / rec));
      off += rec * e.count;
      continue;
    }
    for (std::uint64_t i = 0; i < e.count; ++i) {
      const std::size_t rec_start = off;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (!p.is_list) {
          need(scalar_size(p.type), e, i);
          off += scalar_size(p.type);
          continue;
        }
        need(scalar_size(p.count_type), e, i);
        const double c = load_scalar(base + off, p.count_type, swap);
        if (c < 0) fail_byte(file, off, "negative list length in " + element_what(e, i));
        off += scalar_size(p.count_type);
        const auto items = static_cast<std::size_t>(c);
        if (items > (size - off) / scalar_size(p.type)) need(items * scalar_size(p.type), e, i);
        if (static_cast<int>(k) == face_prop) {
          faces.poly.clear();
          for (std::size_t j = 0; j < items; ++j)
            faces.poly.push_back(
                static_cast<std::int64_t>(load_scalar(base + off + j * scalar_size(p.type), p.type, swap)));
        }
        off += items * scalar_size(p.type);
      }
      if (face_prop >= 0) faces.emit(vertex_count, file, FileLocation{std::nullopt, rec_start});
    }
  }
  if (off != size) {
    bool blank = true;
    for (std::size_t k = off; k < size; ++k) blank = blank && (is_space(base[k]) || base[k] == '\n' || base[k] == '\0');
    if (!blank)
      fail_byte(
          file, off,
          std::to_string(size - off) + " unexpected bytes after the last element (counts in the header too small?)");
  }
  finish(file, seen_vertex, want_faces, faces, out);
  return out;
}

}  // namespace clustersurf::io::ply
