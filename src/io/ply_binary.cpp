// The binary PLY data (little or big endian): records walked byte by byte, every count checked
// against the bytes left.

#include "io/ply_format.hpp"
#include "io/text_parse.hpp"

#include <bit>
#include <cstring>
#include <vector>

namespace clustersurf::io::ply {

namespace {

/// The data of a binary PLY file walked element by element from the header's data offset.
class BinaryData {
 public:
  BinaryData(const std::filesystem::path& file, std::string_view bytes, const Header& h)
      : file_(file),
        base_(bytes.data()),
        size_(bytes.size()),
        off_(h.data_offset),
        swap_((h.encoding == Encoding::BinaryBig) != (std::endian::native == std::endian::big)) {}

  /// The vertex element's records into `out` (VertexRecords).
  void read_vertices(const Element& e, ParsedFile& out) {
    VertexRecords vertices(file_, e, out);
    // Offsets of each scalar property inside a record (records have no lists in practice; with
    // lists they are found per record).
    std::vector<std::size_t> offsets(e.properties.size());
    std::size_t record = 0;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      offsets[k] = record;
      record += scalar_size(e.properties[k].type);
    }
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(e.count); ++i) {
      if (e.has_lists()) record = listed_offsets(e, static_cast<std::uint64_t>(i), offsets);
      need(record, e, static_cast<std::uint64_t>(i));
      const char* rec = base_ + off_;
      vertices.fill(
          i,
          [&](int idx) {
            const auto k = static_cast<std::size_t>(idx);
            return load_scalar(rec + offsets[k], e.properties[k].type, swap_);
          },
          FileLocation{std::nullopt, off_});
      off_ += record;
    }
  }

  /// Any other element walked over; the lists of property `face_prop` (≥ 0) go to `faces`.
  void skip(const Element& e, int face_prop, std::int64_t vertex_count, FaceSink& faces) {
    if (!e.has_lists()) {
      const std::uint64_t rec = e.min_binary_record();
      if (rec != 0 && e.count > (size_ - off_) / rec)
        fail_byte(file_, off_ + ((size_ - off_) / rec) * rec,
                  "file ends inside " + element_what(e, (size_ - off_) / rec));
      off_ += rec * e.count;
      return;
    }
    for (std::uint64_t i = 0; i < e.count; ++i) {
      const std::size_t rec_start = off_;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (!p.is_list) {
          need(scalar_size(p.type), e, i);
          off_ += scalar_size(p.type);
          continue;
        }
        const std::size_t items = list_length(p, e, i, off_);
        off_ += scalar_size(p.count_type);
        if (items > (size_ - off_) / scalar_size(p.type)) need(items * scalar_size(p.type), e, i);
        if (static_cast<int>(k) == face_prop) {
          faces.poly.clear();
          for (std::size_t j = 0; j < items; ++j)
            faces.poly.push_back(
                static_cast<std::int64_t>(load_scalar(base_ + off_ + j * scalar_size(p.type), p.type, swap_)));
        }
        off_ += items * scalar_size(p.type);
      }
      if (face_prop >= 0) faces.emit(vertex_count, file_, FileLocation{std::nullopt, rec_start});
    }
  }

  /// Throws unless only blanks (or nothing) follow the last element.
  void check_end() const {
    bool blank = true;
    for (std::size_t k = off_; k < size_; ++k)
      blank = blank && (is_space(base_[k]) || base_[k] == '\n' || base_[k] == '\0');
    if (!blank)
      fail_byte(
          file_, off_,
          std::to_string(size_ - off_) + " unexpected bytes after the last element (counts in the header too small?)");
  }

 private:
  void need(std::size_t n, const Element& e, std::uint64_t i) const {
    if (n > size_ - off_)
      fail_byte(file_, off_,
                "file ends inside " + element_what(e, i) + " (needs " + std::to_string(n) + " more bytes, " +
                    std::to_string(size_ - off_) + " left)");
  }
  /// The length of list property `p` whose count starts at byte `at` of record i of `e`.
  std::size_t list_length(const Property& p, const Element& e, std::uint64_t i, std::size_t at) const {
    if (scalar_size(p.count_type) > size_ - at) need(at - off_ + scalar_size(p.count_type), e, i);
    const double c = load_scalar(base_ + at, p.count_type, swap_);
    if (c < 0) fail_byte(file_, at, "negative list length in " + element_what(e, i));
    return static_cast<std::size_t>(c);
  }
  /// The offsets of record i's properties (it has lists), and the record's size.
  std::size_t listed_offsets(const Element& e, std::uint64_t i, std::vector<std::size_t>& offsets) const {
    std::size_t record = 0;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const Property& p = e.properties[k];
      need(record + scalar_size(p.is_list ? p.count_type : p.type), e, i);
      offsets[k] = record;
      record += p.is_list ? scalar_size(p.count_type) + list_length(p, e, i, off_ + record) * scalar_size(p.type)
                          : scalar_size(p.type);
    }
    return record;
  }

  const std::filesystem::path& file_;
  const char* base_;
  std::size_t size_;
  std::size_t off_;
  bool swap_;
};

}  // namespace

ParsedFile read_binary(const std::filesystem::path& file, std::string_view bytes, const Header& h, bool want_faces) {
  ParsedFile out;
  BinaryData data(file, bytes, h);
  bool seen_vertex = false;
  const std::int64_t vertex_count = declared_vertices(h);
  FaceSink faces;
  for (const Element& e : h.elements) {
    if (e.name == "vertex" && !seen_vertex) {
      seen_vertex = true;
      data.read_vertices(e, out);
    } else {
      data.skip(e, want_faces && e.name == "face" ? face_index_property(file, e) : -1, vertex_count, faces);
    }
  }
  data.check_end();
  finish(file, seen_vertex, want_faces, faces, out);
  return out;
}

}  // namespace clustersurf::io::ply
