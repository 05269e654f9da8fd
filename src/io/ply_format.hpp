#pragma once
// The PLY reader's parts (ply_reader.cpp dispatches): the header and its element layout
// (ply_header.cpp), the vertex and face records both encodings fill the same way
// (ply_records.cpp), and the binary (ply_binary.cpp) and ascii (ply_ascii.cpp) walks over the
// data.

#include "io/readers.hpp"

#include <clustersurf/core/errors.hpp>

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace clustersurf::io::ply {

enum class Encoding { Ascii, BinaryLittle, BinaryBig };
enum class Scalar : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

inline constexpr std::size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::Int8:
    case Scalar::UInt8:
      return 1;
    case Scalar::Int16:
    case Scalar::UInt16:
      return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32:
      return 4;
    case Scalar::Float64:
      return 8;
  }
  return 0;
}

inline std::optional<Scalar> scalar_from_name(std::string_view name) {
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
  UpAxis up = UpAxis::Y;        // "comment up z" (as clustersurf writes it) says z
};

[[noreturn]] void fail_line(const std::filesystem::path& file, std::uint64_t line, const std::string& msg);
[[noreturn]] void fail_byte(const std::filesystem::path& file, std::uint64_t offset, const std::string& msg);

/// The header up to "end_header"; InputError (with the line) for anything malformed.
Header parse_header(const std::filesystem::path& file, std::string_view bytes);
/// Fails, before anything is allocated, when the element counts of the header cannot fit in
/// the data that follows it (a truncated file, or an absurd count). The error is located where
/// the data ends: the start of the first incomplete record when that is known exactly (binary,
/// no list before it), else the end of the file (its byte offset, or its last line for ascii).
void check_counts(const std::filesystem::path& file, const Header& h, std::string_view bytes);
/// The number of vertices the header declares (0 without a vertex element), so that faces can
/// be checked even when they come first.
std::int64_t declared_vertices(const Header& h);
/// "vertex 12 of 400", for messages.
std::string element_what(const Element& e, std::uint64_t i);
inline bool is_integer_type(Scalar s) { return s != Scalar::Float32 && s != Scalar::Float64; }
/// The index of the face element's vertex index list (-1: none); InputError when it is not an
/// integer list.
int face_index_property(const std::filesystem::path& file, const Element& f);

/// Indices of the vertex properties we use (-1 when absent).
struct VertexLayout {
  std::array<int, 3> pos{-1, -1, -1};
  std::array<int, 3> nrm{-1, -1, -1};
  std::array<int, 3> rgb{-1, -1, -1};
  int scan = -1;  ///< which scan saw the vertex (PointCloud::scanner_of_point)
  bool normals() const { return nrm[0] >= 0 && nrm[1] >= 0 && nrm[2] >= 0; }
  bool colors() const { return rgb[0] >= 0 && rgb[1] >= 0 && rgb[2] >= 0; }
};

/// A color property's value as 0..255 by its type: floats from 0..1, 16-bit integers from
/// 0..65535, others as they are, clamped.
std::uint8_t to_color(double v, Scalar type);

/// The vertex properties of `v` we use; InputError when x, y or z is missing or one of them is a list.
VertexLayout vertex_layout(const std::filesystem::path& file, const Element& v);

/// A binary scalar at p, byte-swapped when `swap`.
template <class T>
inline T load(const char* p, bool swap) {
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

inline double load_scalar(const char* p, Scalar s, bool swap) {
  switch (s) {
    case Scalar::Int8:
      return static_cast<std::int8_t>(*p);
    case Scalar::UInt8:
      return static_cast<std::uint8_t>(*p);
    case Scalar::Int16:
      return load<std::int16_t>(p, swap);
    case Scalar::UInt16:
      return load<std::uint16_t>(p, swap);
    case Scalar::Int32:
      return load<std::int32_t>(p, swap);
    case Scalar::UInt32:
      return load<std::uint32_t>(p, swap);
    case Scalar::Float32:
      return load<float>(p, swap);
    case Scalar::Float64:
      return load<double>(p, swap);
  }
  return 0;
}

/// The vertex element's records into out.cloud: the positions, and the normals and colors when
/// the element has them, sized once; fill() stores one record from its property values.
class VertexRecords {
 public:
  /// Checks the layout (x, y, z present, none of them a list) and sizes out.cloud.
  VertexRecords(const std::filesystem::path& file, const Element& vertex, ParsedFile& out);

  /// Stores record i: value(k) is the k-th property of the record. `where` locates it for the
  /// non-finite check.
  template <class Value>
  void fill(Eigen::Index i, Value&& value, const FileLocation& where) {
    for (int c = 0; c < 3; ++c) out_.cloud.positions(i, c) = value(layout_.pos[static_cast<std::size_t>(c)]);
    if (layout_.normals())
      for (int c = 0; c < 3; ++c) out_.cloud.normals(i, c) = value(layout_.nrm[static_cast<std::size_t>(c)]);
    if (layout_.colors())
      for (int c = 0; c < 3; ++c) {
        const int k = layout_.rgb[static_cast<std::size_t>(c)];
        out_.cloud.colors(i, c) = color(value(k), k);
      }
    if (layout_.scan >= 0) out_.cloud.scanner_of_point[static_cast<std::size_t>(i)] = scan(value(layout_.scan));
    note_non_finite(out_, i, where);
  }

 private:
  std::uint8_t color(double value, int property) const;
  /// A scan index: a whole number from 0 to 2^32 − 2, else kNotAScan.
  static std::uint32_t scan(double value);

  const Element& element_;
  VertexLayout layout_;
  ParsedFile& out_;
};

/// A "scan" value that is not a scan index: a file with one has some other property by that
/// name, and its points no scans (finish() drops them).
inline constexpr std::uint32_t kNotAScan = 0xFFFFFFFFu;

/// Collects fan-triangulated faces with validated indices.
struct FaceSink {
  std::vector<std::int32_t> tri;
  std::vector<std::int64_t> poly;
  /// Fan-triangulates `poly` (fewer than 3 indices: nothing); InputError for an index out of
  /// range.
  void emit(std::int64_t vertex_count, const std::filesystem::path& file, const FileLocation& where);
};

/// The checks both encodings end with: a vertex element was seen; the faces go to out.
void finish(const std::filesystem::path& file, bool seen_vertex, bool want_faces, FaceSink& faces, ParsedFile& out);

/// The data after the header, by encoding.
ParsedFile read_binary(const std::filesystem::path& file, std::string_view bytes, const Header& h, bool want_faces);
ParsedFile read_ascii(const std::filesystem::path& file, std::string_view bytes, const Header& h, bool want_faces);

}  // namespace clustersurf::io::ply
