#pragma once
// The PCD reader's parts (pcd_reader.cpp reads a whole file): the header, checked against the
// file's size, and the ascii, binary and binary_compressed records read one at a time
// (pcd_header.cpp), which PointStream also reads a block at a time.

#include <clustersurf/core/errors.hpp>

#include "io/lzf_stream.hpp"
#include "io/text_parse.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace clustersurf::io::pcd {

/// One declared field: its name, element type ('F', 'I' or 'U') and size, element count, and
/// where its first element sits in a binary record.
struct Field {
  std::string name;
  char type = 'F';
  unsigned size = 4;
  std::uint64_t count = 1;
  std::uint64_t offset = 0;
};

/// Which declared field supplies each quantity the reader keeps (-1: none).
struct Roles {
  int position[3] = {-1, -1, -1};
  int normal[3] = {-1, -1, -1};
  int packed_rgb = -1;
  int rgb[3] = {-1, -1, -1};
  int intensity = -1;
  int classification = -1;

  bool normals() const { return normal[0] >= 0 && normal[1] >= 0 && normal[2] >= 0; }
};

enum class Data { Ascii, Binary, BinaryCompressed };

/// A PCD header, checked: every keyword and value, x, y and z among the fields, POINTS equal to
/// WIDTH × HEIGHT and no more points than the rest of the file can hold.
struct Layout {
  std::vector<Field> fields;
  Roles roles;
  Data data = Data::Ascii;
  std::uint64_t points = 0;
  std::uint64_t record = 0;     ///< bytes of a binary record
  std::size_t body = 0;         ///< byte offset of the data
  std::uint64_t data_line = 0;  ///< the line of DATA
  std::int64_t height = 1;
  double viewpoint[7] = {0, 0, 0, 1, 0, 0, 0};
};

/// Parses and checks the header of `bytes`; InputError naming the line otherwise.
Layout read_layout(const std::filesystem::path& file, std::string_view bytes);

/// The LZF data of a binary_compressed file, its sizes checked (InputError with the byte
/// offset): the compressed bytes, where they start in the file, and the decompressed size
/// (POINTS x record: the fields' values one after another).
struct CompressedData {
  std::string_view packed;
  std::size_t begin = 0;
  std::uint64_t unpacked = 0;
};
CompressedData compressed_data(const std::filesystem::path& file, std::string_view bytes, const Layout& layout);

/// The value of element `bytes` (little-endian) of a field of `type` and `size`.
double decode(const char* bytes, char type, unsigned size);

/// A red, green or blue field's value (decode()'s) as 16 bits: clamped to 0..65535, NaN 0.
inline std::uint16_t wide_channel(double value) {
  return value > 0 ? static_cast<std::uint16_t>(value < 65535.0 ? value : 65535.0) : std::uint16_t{0};
}

/// The red, green and blue packed as 0x00RRGGBB in `value` (decode()'s) of field `f`: the bytes
/// of a 4-byte float, or an unsigned integer.
std::array<std::uint8_t, 3> packed_color(double value, const Field& f);

/// The records of a PCD file, one at a time: ascii lines, binary records, or binary_compressed
/// data (its fields' values one after another), decoded by one LzfStream per field, each
/// resumed where its field's values begin. `file`, `bytes` and `layout` must outlive it.
class Records {
 public:
  /// Binary_compressed data is checked here, decoded through once: its sizes, and the LZF data
  /// itself (InputError with the byte offset); `consumed` (if given) hears how far into the
  /// file that pass has read, every 64 MiB of compressed data and at its end.
  Records(const std::filesystem::path& file, std::string_view bytes, const Layout& layout,
          const std::function<void(std::size_t)>& consumed = {});
  /// Moves to the next record; false after the last (POINTS of them). InputError (line) for a
  /// malformed ascii line or an ascii file that ends early.
  bool next();
  /// The first element of field `f` of the current record (binary_compressed: of the fields
  /// with a role in Roles, the only ones decoded; NaN for the others).
  double value(int f) const;
  /// Where the current record is: its line (ascii), byte offset (binary), or the byte where
  /// its x value's compressed data continues (binary_compressed).
  FileLocation location() const;
  /// Bytes of an ascii or binary file consumed so far (binary_compressed: see take_read_spans()).
  std::size_t offset() const;
  /// Binary_compressed: the byte ranges of the file each field's decoder has read since the
  /// last call (empty otherwise).
  std::vector<std::pair<std::size_t, std::size_t>> take_read_spans();
  /// Back to before the first record (binary_compressed data is not decoded through again).
  void rewind();

 private:
  const std::filesystem::path& file_;
  std::string_view bytes_;
  const Layout& layout_;
  std::optional<TextCursor> cursor_;
  std::vector<std::string_view> tokens_;
  std::vector<double> values_;
  std::vector<std::size_t> first_;  // ascii: the column of each field's first element
  std::uint64_t read_ = 0;          // records read so far
  // binary_compressed: the fields decoded (every role's, ascending); indexed like them, each
  // one's decoder where its values begin, its decoder now, and how far into the data
  // take_read_spans() has handed out; per field, its index in kept_ (or -1); the current
  // record's first element of each kept field, 8 bytes each.
  std::size_t packed_begin_ = 0;
  std::vector<int> kept_;
  std::vector<LzfStream> starts_;
  std::vector<LzfStream> decoders_;
  std::vector<std::size_t> handed_;
  std::vector<int> slot_;
  std::vector<char> record_;
};

}  // namespace clustersurf::io::pcd
