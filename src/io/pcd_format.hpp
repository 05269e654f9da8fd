#pragma once
// The PCD reader's parts (pcd_reader.cpp reads a whole file): the header, checked against the
// file's size, and the ascii and binary records read one at a time (pcd_header.cpp), which
// PointStream also reads a block at a time.

#include <clustersurf/errors.hpp>

#include "io/text_parse.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
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

/// The value of element `bytes` (little-endian) of a field of `type` and `size`.
double decode(const char* bytes, char type, unsigned size);

/// The records of an ascii or binary PCD file, one at a time (InputError for a
/// binary_compressed one, whose fields lie one after another). `file`, `bytes` and `layout`
/// must outlive it.
class Records {
 public:
  Records(const std::filesystem::path& file, std::string_view bytes, const Layout& layout);
  /// Moves to the next record; false after the last (POINTS of them). InputError (line) for a
  /// malformed ascii line or an ascii file that ends early.
  bool next();
  /// The first element of field `f` of the current record.
  double value(int f) const;
  /// Where the current record is: its line (ascii) or byte offset (binary).
  FileLocation location() const;
  /// Bytes of the file consumed so far.
  std::size_t offset() const;

 private:
  const std::filesystem::path& file_;
  std::string_view bytes_;
  const Layout& layout_;
  TextCursor cursor_;
  std::vector<std::string_view> tokens_;
  std::vector<double> values_;
  std::vector<std::size_t> first_;  // ascii: the column of each field's first element
  std::uint64_t read_ = 0;          // records read so far
};

}  // namespace clustersurf::io::pcd
