// PLY reader: ascii and binary (little/big endian), every PLY scalar type, list properties,
// arbitrary extra elements (skipped), faces (optional). Counts are checked against the file size
// before anything is allocated.

#include "io/readers.hpp"
#include "io/text_parse.hpp"

#include <clustersurf/errors.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf::io {

namespace {

enum class Encoding { Ascii, BinaryLittle, BinaryBig };
enum class Scalar : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

constexpr std::size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::Int8:
    case Scalar::UInt8: return 1;
    case Scalar::Int16:
    case Scalar::UInt16: return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32: return 4;
    case Scalar::Float64: return 8;
  }
  return 0;
}

std::optional<Scalar> scalar_from_name(std::string_view name) {
  if (name == "char" || name == "int8") return Scalar::Int8;
  if (name == "uchar" || name == "uint8") return Scalar::UInt8;
  if (name == "short" || name == "int16") return Scalar::Int16;
  if (name == "ushort" || name == "uint16") return Scalar::UInt16;
  if (name == "int" || name == "int32") return Scalar::Int32;
  if (name == "uint" || name == "uint32") return Scalar::UInt32;
  if (name == "float" || name == "float32") return Scalar::Float32;
  if (name == "double" || name == "float64") return Scalar::Float64;
  return std::nullopt;
}

struct Property {
  std::string name;
  Scalar type = Scalar::Float32;
  bool is_list = false;
  Scalar count_type = Scalar::UInt8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t header_line = 0;
  std::vector<Property> properties;

  bool has_lists() const {
    for (const auto& p : properties)
      if (p.is_list) return true;
    return false;
  }
  /// Bytes of one record in binary (lists count their length field only: a lower bound).
  std::uint64_t min_binary_record() const {
    std::uint64_t n = 0;
    for (const auto& p : properties) n += p.is_list ? scalar_size(p.count_type) : scalar_size(p.type);
    return n;
  }
  int find(std::initializer_list<std::string_view> names) const {
    for (std::string_view name : names)
      for (std::size_t i = 0; i < properties.size(); ++i)
        if (properties[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
  std::size_t data_offset = 0;  // first byte after "end_header\n"
  std::uint64_t data_line = 0;  // line number of the first data line (ascii)
};

[[noreturn]] void fail_line(const std::filesystem::path& file, std::uint64_t line, const std::string& msg) {
  throw InputError(file, FileLocation{line, std::nullopt}, msg);
}
[[noreturn]] void fail_byte(const std::filesystem::path& file, std::uint64_t offset, const std::string& msg) {
  throw InputError(file, FileLocation{std::nullopt, offset}, msg);
}

Header parse_header(const std::filesystem::path& file, std::string_view bytes) {
  constexpr std::size_t kMaxHeader = 16u << 20;
  Header header;
  std::size_t pos = 0;
  std::uint64_t line_no = 0;
  bool have_format = false;
  std::vector<std::string_view> tok;
  auto next_line = [&](std::string_view& line) -> bool {
    if (pos >= bytes.size() || pos > kMaxHeader) return false;
    const std::size_t nl = bytes.substr(0, pos + kMaxLineBytes + 1).find('\n', pos);
    if (nl == std::string_view::npos && bytes.size() - pos > kMaxLineBytes) fail_long_line(file, line_no + 1);
    if (nl == std::string_view::npos) return false;
    line = bytes.substr(pos, nl - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = nl + 1;
    ++line_no;
    return true;
  };
  std::string_view line;
  if (!next_line(line) || line != "ply")
    fail_line(file, 1, "not a PLY file: expected the first line to be \"ply\"");
  for (;;) {
    if (!next_line(line))
      fail_line(file, line_no + 1, "PLY header has no \"end_header\" line (file truncated or not PLY)");
    tok.clear();
    split_fields(line, tok);
    // split_fields treats ',' and '#' as separators; PLY keywords never contain them, comments
    // are handled by keyword below.
    if (line.rfind("comment", 0) == 0 || line.rfind("obj_info", 0) == 0) continue;
    if (tok.empty()) continue;
    const std::string_view kw = tok[0];
    if (kw == "end_header") break;
    if (kw == "format") {
      if (tok.size() != 3) fail_line(file, line_no, "expected \"format <ascii|binary_little_endian|binary_big_endian> 1.0\"");
      if (tok[1] == "ascii") header.encoding = Encoding::Ascii;
      else if (tok[1] == "binary_little_endian") header.encoding = Encoding::BinaryLittle;
      else if (tok[1] == "binary_big_endian") header.encoding = Encoding::BinaryBig;
      else fail_line(file, line_no, "unknown PLY format \"" + std::string(tok[1]) + "\"");
      if (tok[2] != "1.0") fail_line(file, line_no, "unsupported PLY version \"" + std::string(tok[2]) + "\" (expected 1.0)");
      have_format = true;
    } else if (kw == "element") {
      std::int64_t count = 0;
      if (tok.size() != 3 || !parse_int(tok[2], count) || count < 0)
        fail_line(file, line_no, "expected \"element <name> <non-negative count>\"");
      header.elements.push_back(Element{std::string(tok[1]), static_cast<std::uint64_t>(count), line_no, {}});
    } else if (kw == "property") {
      if (header.elements.empty()) fail_line(file, line_no, "property before any element");
      Property prop;
      if (tok.size() == 5 && tok[1] == "list") {
        const auto ct = scalar_from_name(tok[2]);
        const auto it = scalar_from_name(tok[3]);
        if (!ct || !it) fail_line(file, line_no, "unknown scalar type in list property");
        if (*ct == Scalar::Float32 || *ct == Scalar::Float64)
          fail_line(file, line_no, "list count type must be an integer type");
        prop = Property{std::string(tok[4]), *it, true, *ct};
      } else if (tok.size() == 3) {
        const auto t = scalar_from_name(tok[1]);
        if (!t) fail_line(file, line_no, "unknown scalar type \"" + std::string(tok[1]) + "\"");
        prop = Property{std::string(tok[2]), *t, false, Scalar::UInt8};
      } else {
        fail_line(file, line_no, "expected \"property <type> <name>\" or \"property list <count type> <type> <name>\"");
      }
      header.elements.back().properties.push_back(std::move(prop));
    } else {
      fail_line(file, line_no, "unexpected PLY header line \"" + std::string(line.substr(0, 60)) + "\"");
    }
  }
  if (!have_format) fail_line(file, 2, "PLY header has no \"format\" line");
  header.data_offset = pos;
  header.data_line = line_no + 1;
  return header;
}

template <class T>
T load(const char* p, bool swap) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if (swap) {
    if constexpr (sizeof(T) == 2) {
      auto u = std::bit_cast<std::uint16_t>(v);
      v = std::bit_cast<T>(static_cast<std::uint16_t>(__builtin_bswap16(u)));
    } else if constexpr (sizeof(T) == 4) {
      v = std::bit_cast<T>(__builtin_bswap32(std::bit_cast<std::uint32_t>(v)));
    } else if constexpr (sizeof(T) == 8) {
      v = std::bit_cast<T>(__builtin_bswap64(std::bit_cast<std::uint64_t>(v)));
    }
  }
  return v;
}

double load_scalar(const char* p, Scalar s, bool swap) {
  switch (s) {
    case Scalar::Int8: return static_cast<std::int8_t>(*p);
    case Scalar::UInt8: return static_cast<std::uint8_t>(*p);
    case Scalar::Int16: return load<std::int16_t>(p, swap);
    case Scalar::UInt16: return load<std::uint16_t>(p, swap);
    case Scalar::Int32: return load<std::int32_t>(p, swap);
    case Scalar::UInt32: return load<std::uint32_t>(p, swap);
    case Scalar::Float32: return load<float>(p, swap);
    case Scalar::Float64: return load<double>(p, swap);
  }
  return 0;
}

bool is_integer_type(Scalar s) { return s != Scalar::Float32 && s != Scalar::Float64; }

/// Maps a color property value to 0..255 according to its type.
std::uint8_t to_color(double v, Scalar type) {
  double c;
  switch (type) {
    case Scalar::Float32:
    case Scalar::Float64: c = v * 255.0; break;
    case Scalar::UInt16:
    case Scalar::Int16: c = v / 257.0; break;
    default: c = v; break;
  }
  if (!(c > 0)) return 0;  // also NaN
  if (c >= 255) return 255;
  return static_cast<std::uint8_t>(std::lround(c));
}

/// Indices of the vertex properties we use (-1 when absent).
struct VertexLayout {
  std::array<int, 3> pos{-1, -1, -1};
  std::array<int, 3> nrm{-1, -1, -1};
  std::array<int, 3> rgb{-1, -1, -1};
  bool normals() const { return nrm[0] >= 0 && nrm[1] >= 0 && nrm[2] >= 0; }
  bool colors() const { return rgb[0] >= 0 && rgb[1] >= 0 && rgb[2] >= 0; }
};

VertexLayout vertex_layout(const std::filesystem::path& file, const Element& v) {
  VertexLayout l;
  l.pos = {v.find({"x"}), v.find({"y"}), v.find({"z"})};
  if (l.pos[0] < 0 || l.pos[1] < 0 || l.pos[2] < 0)
    fail_line(file, v.header_line, "vertex element lacks one of the properties x, y, z");
  l.nrm = {v.find({"nx", "normal_x"}), v.find({"ny", "normal_y"}), v.find({"nz", "normal_z"})};
  l.rgb = {v.find({"red", "r", "diffuse_red"}), v.find({"green", "g", "diffuse_green"}),
           v.find({"blue", "b", "diffuse_blue"})};
  for (int idx : {l.pos[0], l.pos[1], l.pos[2], l.nrm[0], l.nrm[1], l.nrm[2], l.rgb[0], l.rgb[1], l.rgb[2]})
    if (idx >= 0 && v.properties[static_cast<std::size_t>(idx)].is_list)
      fail_line(file, v.header_line, "vertex property \"" + v.properties[static_cast<std::size_t>(idx)].name +
                                         "\" is a list; expected a scalar");
  return l;
}

int face_index_property(const std::filesystem::path& file, const Element& f) {
  const int idx = f.find({"vertex_indices", "vertex_index"});
  if (idx >= 0 && !f.properties[static_cast<std::size_t>(idx)].is_list)
    fail_line(file, f.header_line, "face property \"vertex_indices\" must be a list");
  if (idx >= 0 && !is_integer_type(f.properties[static_cast<std::size_t>(idx)].type))
    fail_line(file, f.header_line, "face vertex indices must have an integer type");
  return idx;
}

/// Collects fan-triangulated faces with validated indices.
struct FaceSink {
  std::vector<std::int32_t> tri;
  std::vector<std::int64_t> poly;
  void emit(std::int64_t vertex_count, const std::filesystem::path& file, const FileLocation& where) {
    if (poly.size() < 3) return;  // points and edges carry no triangles
    for (auto i : poly)
      if (i < 0 || i >= vertex_count)
        throw InputError(file, where, "face refers to vertex " + std::to_string(i) + " but there are " +
                                          std::to_string(vertex_count) + " vertices");
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
      tri.push_back(static_cast<std::int32_t>(poly[0]));
      tri.push_back(static_cast<std::int32_t>(poly[k]));
      tri.push_back(static_cast<std::int32_t>(poly[k + 1]));
    }
  }
};

std::string element_what(const Element& e, std::uint64_t i) {
  return e.name + " " + std::to_string(i) + " of " + std::to_string(e.count);
}

/// Fails, before anything is allocated, when the element counts of the header cannot fit in
/// the data that follows it (a truncated file, or an absurd count). The error is located where
/// the data ends: the start of the first incomplete record when that is known exactly (binary,
/// no list before it), else the end of the file (its byte offset, or its last line for ascii).
void check_counts(const std::filesystem::path& file, const Header& h, std::string_view bytes) {
  const bool ascii = h.encoding == Encoding::Ascii;
  const std::uint64_t available = bytes.size() - h.data_offset;
  std::uint64_t need = 0;  // a lower bound of the bytes taken by the elements before `e`
  bool exact = true;       // `need` is exact (binary, no list property so far)
  for (const auto& e : h.elements) {
    // ascii: at least one character and one separator per value; binary: the record size
    // (lists counting their length field only).
    const std::uint64_t per = ascii ? 2 * e.properties.size() : e.min_binary_record();
    const std::uint64_t left = available - std::min(need, available);
    if (per != 0 && e.count > left / per) {
      const std::string claim = "the header (line " + std::to_string(e.header_line) + ") claims " +
                                std::to_string(e.count) + " " + e.name + " records of " +
                                (ascii || e.has_lists() ? "at least " : "") + std::to_string(per) + " bytes" +
                                (ascii ? " as text" : "") + " but only " + std::to_string(available) +
                                " bytes of data follow the header";
      if (!ascii && exact && !e.has_lists()) {
        const std::uint64_t complete = left / per;
        fail_byte(file, h.data_offset + need + complete * per,
                  "file ends inside " + element_what(e, complete) + " (" + claim + ")");
      }
      if (!ascii) fail_byte(file, bytes.size(), "file ends too early: " + claim);
      const auto lines = static_cast<std::uint64_t>(std::count(bytes.begin(), bytes.end(), '\n'));
      fail_line(file, lines + 1, "file ends too early: " + claim);
    }
    need += per * e.count;
    exact = exact && !e.has_lists();
  }
}

/// The number of vertices the header declares (0 without a vertex element), so that faces can
/// be checked even when they come first.
std::int64_t declared_vertices(const Header& h) {
  for (const auto& e : h.elements)
    if (e.name == "vertex") return static_cast<std::int64_t>(e.count);
  return 0;
}

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
      fail_byte(file, off, "file ends inside " + element_what(e, i) + " (needs " + std::to_string(n) +
                               " more bytes, " + std::to_string(size - off) + " left)");
  };

  for (const Element& e : h.elements) {
    const bool is_vertex = e.name == "vertex" && !seen_vertex;
    const bool is_face = want_faces && e.name == "face";
    if (is_vertex) {
      seen_vertex = true;
      if (e.count > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
        fail_line(file, e.header_line, "too many vertices (" + std::to_string(e.count) + "); at most 2^31-1 supported");
      const VertexLayout l = vertex_layout(file, e);
      const auto n = static_cast<Eigen::Index>(e.count);
      out.cloud.positions.resize(n, 3);
      if (l.normals()) out.cloud.normals.resize(n, 3);
      if (l.colors()) out.cloud.colors.resize(n, 3);
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
            need(record + scalar_size(e.properties[k].is_list ? e.properties[k].count_type : e.properties[k].type), e, static_cast<std::uint64_t>(i));
            offsets[k] = record;
            if (e.properties[k].is_list) {
              const double c = load_scalar(base + off + record, e.properties[k].count_type, swap);
              if (c < 0) fail_byte(file, off + record, "negative list length in " + element_what(e, static_cast<std::uint64_t>(i)));
              record += scalar_size(e.properties[k].count_type) +
                        static_cast<std::size_t>(c) * scalar_size(e.properties[k].type);
            } else {
              record += scalar_size(e.properties[k].type);
            }
          }
        }
        need(record, e, static_cast<std::uint64_t>(i));
        const char* rec = base + off;
        for (int c = 0; c < 3; ++c) out.cloud.positions(i, c) = get(rec, l.pos[static_cast<std::size_t>(c)]);
        if (l.normals())
          for (int c = 0; c < 3; ++c) out.cloud.normals(i, c) = get(rec, l.nrm[static_cast<std::size_t>(c)]);
        if (l.colors())
          for (int c = 0; c < 3; ++c) {
            const int idx = l.rgb[static_cast<std::size_t>(c)];
            out.cloud.colors(i, c) = to_color(get(rec, idx), e.properties[static_cast<std::size_t>(idx)].type);
          }
        note_non_finite(out, i, FileLocation{std::nullopt, off});
        off += record;
      }
      continue;
    }
    // Any other element: walk it (faces are collected when asked for).
    const int face_prop = is_face ? face_index_property(file, e) : -1;
    if (!e.has_lists()) {
      const std::uint64_t rec = e.min_binary_record();
      if (rec != 0 && e.count > (size - off) / rec)
        fail_byte(file, off + ((size - off) / rec) * rec,
                  "file ends inside " + element_what(e, (size - off) / rec));
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
            faces.poly.push_back(static_cast<std::int64_t>(load_scalar(base + off + j * scalar_size(p.type), p.type, swap)));
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
      fail_byte(file, off, std::to_string(size - off) + " unexpected bytes after the last element (counts in the header too small?)");
  }
  if (!seen_vertex) fail_line(file, 1, "PLY file has no \"vertex\" element");
  if (want_faces) out.triangles = Eigen::Map<Triangles>(faces.tri.data(), static_cast<Eigen::Index>(faces.tri.size() / 3), 3);
  return out;
}

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
      fail_line(file, cur.line(), "expected a number for property \"" + p.name + "\" of " + element_what(e, i) +
                                      ", found \"" + std::string(t.substr(0, 40)) + "\"");
    if (is_integer_type(p.type) && (!std::isfinite(v) || v != std::floor(v)))
      fail_line(file, cur.line(), "expected an integer for property \"" + p.name + "\" of " + element_what(e, i) +
                                      ", found \"" + std::string(t.substr(0, 40)) + "\"");
    return v;
  };
  auto list_length = [&](const Element& e, std::uint64_t i, const Property& p) {
    const std::string_view t = cur.next_token();
    if (t.empty()) fail_line(file, cur.line(), "file ends inside " + element_what(e, i));
    std::int64_t c;
    if (!parse_int(t, c) || c < 0)
      fail_line(file, cur.line(), "expected a list length for \"" + p.name + "\" of " + element_what(e, i) +
                                      ", found \"" + std::string(t.substr(0, 40)) + "\"");
    if (c > 1'000'000) fail_line(file, cur.line(), "list length " + std::to_string(c) + " is implausible");
    return c;
  };

  std::vector<double> values;
  for (const Element& e : h.elements) {
    const bool is_vertex = e.name == "vertex" && !seen_vertex;
    const bool is_face = want_faces && e.name == "face";
    VertexLayout l;
    if (is_vertex) {
      seen_vertex = true;
      if (e.count > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
        fail_line(file, e.header_line, "too many vertices (" + std::to_string(e.count) + "); at most 2^31-1 supported");
      l = vertex_layout(file, e);
      const auto n = static_cast<Eigen::Index>(e.count);
      out.cloud.positions.resize(n, 3);
      if (l.normals()) out.cloud.normals.resize(n, 3);
      if (l.colors()) out.cloud.colors.resize(n, 3);
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
              fail_line(file, cur.line(), "face refers to vertex " + std::string(last_token) + " but there are " +
                                              std::to_string(vertex_count) + " vertices");
            faces.poly.push_back(static_cast<std::int64_t>(v));
          }
        }
      }
      if (is_vertex) {
        const auto r = static_cast<Eigen::Index>(i);
        for (int c = 0; c < 3; ++c) out.cloud.positions(r, c) = values[static_cast<std::size_t>(l.pos[static_cast<std::size_t>(c)])];
        if (l.normals())
          for (int c = 0; c < 3; ++c) out.cloud.normals(r, c) = values[static_cast<std::size_t>(l.nrm[static_cast<std::size_t>(c)])];
        if (l.colors())
          for (int c = 0; c < 3; ++c) {
            const auto idx = static_cast<std::size_t>(l.rgb[static_cast<std::size_t>(c)]);
            out.cloud.colors(r, c) = to_color(values[idx], e.properties[idx].type);
          }
        note_non_finite(out, r, FileLocation{record_line, std::nullopt});
      }
      if (face_prop >= 0) faces.emit(vertex_count, file, FileLocation{record_line, std::nullopt});
    }
  }
  if (const std::string_view extra = cur.next_token(); !extra.empty())
    fail_line(file, cur.line(),
              "unexpected data \"" + std::string(extra.substr(0, 40)) +
                  "\" after the last element (counts in the header too small?)");
  if (!seen_vertex) fail_line(file, 1, "PLY file has no \"vertex\" element");
  if (want_faces) out.triangles = Eigen::Map<Triangles>(faces.tri.data(), static_cast<Eigen::Index>(faces.tri.size() / 3), 3);
  return out;
}

}  // namespace

ParsedFile read_ply(const std::filesystem::path& file, std::string_view bytes, bool want_faces) {
  const Header h = parse_header(file, bytes);
  check_counts(file, h, bytes);
  return h.encoding == Encoding::Ascii ? read_ascii(file, bytes, h, want_faces)
                                       : read_binary(file, bytes, h, want_faces);
}

}  // namespace clustersurf::io
