// PLY reader: ascii and binary (little/big endian), every PLY scalar type, list properties,
// arbitrary extra elements (skipped), faces (optional). Counts are checked against the file size
// before anything is allocated. The parts: io/ply_format.hpp.

#include "io/ply_format.hpp"

namespace clustersurf::io {

ParsedFile read_ply(const std::filesystem::path& file, std::string_view bytes, bool want_faces) {
  const ply::Header h = ply::parse_header(file, bytes);
  ply::check_counts(file, h, bytes);
  ParsedFile parsed = h.encoding == ply::Encoding::Ascii ? ply::read_ascii(file, bytes, h, want_faces)
                                                         : ply::read_binary(file, bytes, h, want_faces);
  parsed.cloud.up = h.up;
  return parsed;
}

}  // namespace clustersurf::io
