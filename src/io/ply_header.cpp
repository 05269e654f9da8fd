// The PLY header: format, elements and their properties, and whether the data can hold them.

#include "io/ply_format.hpp"
#include "io/text_parse.hpp"

#include <algorithm>

namespace clustersurf::io::ply {

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
  if (!next_line(line) || line != "ply") fail_line(file, 1, "not a PLY file: expected the first line to be \"ply\"");
  for (;;) {
    if (!next_line(line))
      fail_line(file, line_no + 1, "PLY header has no \"end_header\" line (file truncated or not PLY)");
    tok.clear();
    split_fields(line, tok);
    // split_fields treats ',' and '#' as separators; PLY keywords never contain them, comments
    // are handled by keyword below.
    if (line == "comment up z") header.up = UpAxis::Z;
    if (line.rfind("comment", 0) == 0 || line.rfind("obj_info", 0) == 0) continue;
    if (tok.empty()) continue;
    const std::string_view kw = tok[0];
    if (kw == "end_header") break;
    if (kw == "format") {
      if (tok.size() != 3)
        fail_line(file, line_no, "expected \"format <ascii|binary_little_endian|binary_big_endian> 1.0\"");
      if (tok[1] == "ascii")
        header.encoding = Encoding::Ascii;
      else if (tok[1] == "binary_little_endian")
        header.encoding = Encoding::BinaryLittle;
      else if (tok[1] == "binary_big_endian")
        header.encoding = Encoding::BinaryBig;
      else
        fail_line(file, line_no, "unknown PLY format \"" + std::string(tok[1]) + "\"");
      if (tok[2] != "1.0")
        fail_line(file, line_no, "unsupported PLY version \"" + std::string(tok[2]) + "\" (expected 1.0)");
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

std::string element_what(const Element& e, std::uint64_t i) {
  return e.name + " " + std::to_string(i) + " of " + std::to_string(e.count);
}

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
      const std::string claim =
          "the header (line " + std::to_string(e.header_line) + ") claims " + std::to_string(e.count) + " " + e.name +
          " records of " + (ascii || e.has_lists() ? "at least " : "") + std::to_string(per) + " bytes" +
          (ascii ? " as text" : "") + " but only " + std::to_string(available) + " bytes of data follow the header";
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

std::int64_t declared_vertices(const Header& h) {
  for (const auto& e : h.elements)
    if (e.name == "vertex") return static_cast<std::int64_t>(e.count);
  return 0;
}

int face_index_property(const std::filesystem::path& file, const Element& f) {
  const int idx = f.find({"vertex_indices", "vertex_index"});
  if (idx >= 0 && !f.properties[static_cast<std::size_t>(idx)].is_list)
    fail_line(file, f.header_line, "face property \"vertex_indices\" must be a list");
  if (idx >= 0 && !is_integer_type(f.properties[static_cast<std::size_t>(idx)].type))
    fail_line(file, f.header_line, "face vertex indices must have an integer type");
  return idx;
}

}  // namespace clustersurf::io::ply
