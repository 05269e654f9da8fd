// E57's XML section: the scans of /data3D, their prototypes, limits and poses, each binary
// section opened and checked before any point is decoded; see e57_scans.hpp.

#include "io/e57_scans.hpp"

#include <pugixml.hpp>

#include <bit>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>

namespace clustersurf::io::e57 {

namespace {

constexpr std::uint64_t kMaxXmlBytes = std::uint64_t{64} << 20;

/// The XML section and how to name a place in it (the physical byte offset of a node).
struct Xml {
  const PagedFile& pages;
  std::uint64_t logical = 0;

  std::uint64_t where(const pugi::xml_node& n) const {
    const std::ptrdiff_t off = n.offset_debug();
    return pages.to_physical(logical + static_cast<std::uint64_t>(std::max<std::ptrdiff_t>(off, 0)));
  }
  [[noreturn]] void fail(const pugi::xml_node& n, const std::string& message) const { pages.fail(where(n), message); }
};

/// `text` without leading and trailing blanks.
std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t\r\n") - first + 1);
}

/// `text` as a T (int64, uint64 or double), whole and in range; nullopt otherwise.
template <class T>
std::optional<T> parse_number(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  T v{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty()) return std::nullopt;
  return v;
}

/// Attribute `name` of `n` as a T; `fallback` when absent; throws when not a number.
template <class T>
T number_attribute(const Xml& xml, const pugi::xml_node& n, const char* name, T fallback) {
  const pugi::xml_attribute a = n.attribute(name);
  if (!a) return fallback;
  const auto v = parse_number<T>(a.value());
  if (!v)
    xml.fail(n,
             std::string("attribute ") + name + "=\"" + a.value() + "\" of <" + n.name() + "> is not a valid number");
  return *v;
}

/// The value of an Integer, ScaledInteger or Float element (empty text: 0); `fallback` when
/// the element is absent.
double element_value(const Xml& xml, const pugi::xml_node& n, double fallback) {
  if (!n) return fallback;
  const std::string_view type = n.attribute("type").value(), text = trim(n.child_value());
  if (type == "Float") {
    const auto v = text.empty() ? 0.0 : parse_number<double>(text);
    if (!v) xml.fail(n, std::string("<") + n.name() + "> holds no valid Float");
    return *v;
  }
  if (type == "Integer" || type == "ScaledInteger") {
    const auto v = text.empty() ? 0 : parse_number<std::int64_t>(text);
    if (!v) xml.fail(n, std::string("<") + n.name() + "> holds no valid Integer");
    if (type == "Integer") return static_cast<double>(*v);
    return static_cast<double>(*v) * number_attribute(xml, n, "scale", 1.0) + number_attribute(xml, n, "offset", 0.0);
  }
  xml.fail(n, std::string("<") + n.name() + "> should be a number but has type \"" + std::string(type) + "\"");
}

/// Reads one prototype child (Float, ScaledInteger or Integer) and its bit width.
Field read_field(const Xml& xml, const pugi::xml_node& n) {
  Field f{n.name(), {}};
  const std::string_view type = n.attribute("type").value();
  if (type == "Float") {
    const std::string_view precision = n.attribute("precision").value();
    if (precision != "single" && precision != "double" && !precision.empty())
      xml.fail(n, "field " + f.name + " has precision \"" + std::string(precision) + "\" (expected single or double)");
    f.codec.kind = precision == "single" ? FieldCodec::Kind::Float32 : FieldCodec::Kind::Float64;
    f.codec.bits = precision == "single" ? 32 : 64;
    if (n.attribute("minimum") && n.attribute("maximum")) {
      f.minimum = number_attribute(xml, n, "minimum", 0.0);
      f.maximum = number_attribute(xml, n, "maximum", 0.0);
    }
    return f;
  }
  if (type != "Integer" && type != "ScaledInteger")
    xml.fail(n, "field " + f.name + " has unsupported type \"" + std::string(type) +
                    "\" (expected Float, ScaledInteger or Integer)");
  const auto lo = number_attribute(xml, n, "minimum", std::numeric_limits<std::int64_t>::min());
  const auto hi = number_attribute(xml, n, "maximum", std::numeric_limits<std::int64_t>::max());
  if (hi < lo) xml.fail(n, "field " + f.name + " has maximum below minimum");
  f.codec.kind = FieldCodec::Kind::Integer;
  f.codec.bits = static_cast<unsigned>(std::bit_width(static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo)));
  f.codec.minimum = lo;
  if (type == "ScaledInteger") {
    f.codec.scale = number_attribute(xml, n, "scale", 1.0);
    f.codec.offset = number_attribute(xml, n, "offset", 0.0);
  }
  f.minimum = f.codec.value(0);
  f.maximum = f.codec.value(static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo));
  return f;
}

/// The index of the field called `name` in `fields`, or -1.
int find_field(const std::vector<Field>& fields, std::string_view name) {
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == name) return static_cast<int>(i);
  return -1;
}

/// Reads a scan's prototype, limits and pose and opens its binary section (whose size bounds
/// the record count); adds its record bits to `total_bits`, which must stay within the file.
Scan read_scan(const Xml& xml, const pugi::xml_node& node, std::uint64_t& total_bits) {
  Scan s;
  const pugi::xml_node points = node.child("points");
  if (!points || std::string_view(points.attribute("type").value()) != "CompressedVector")
    xml.fail(node, "scan has no <points> CompressedVector");
  const pugi::xml_node prototype = points.child("prototype");
  if (!prototype) xml.fail(points, "<points> has no <prototype>");
  std::uint64_t bits = 0;
  for (const pugi::xml_node& c : prototype.children())
    if (c.type() == pugi::node_element) {
      s.fields.push_back(read_field(xml, c));
      bits += s.fields.back().codec.bits;
    }
  const char* cartesian[3] = {"cartesianX", "cartesianY", "cartesianZ"};
  const char* spherical[3] = {"sphericalRange", "sphericalAzimuth", "sphericalElevation"};
  for (int k = 0; k < 3; ++k) s.coord[k] = find_field(s.fields, cartesian[k]);
  if (s.coord[0] < 0 || s.coord[1] < 0 || s.coord[2] < 0) {
    for (int k = 0; k < 3; ++k) s.coord[k] = find_field(s.fields, spherical[k]);
    if (s.coord[0] < 0 || s.coord[1] < 0 || s.coord[2] < 0)
      xml.fail(prototype, "prototype has neither cartesianX/Y/Z nor sphericalRange/Azimuth/Elevation");
    s.spherical = true;
  }
  s.invalid = find_field(s.fields, s.spherical ? "sphericalInvalidState" : "cartesianInvalidState");
  const char* channel[3] = {"Red", "Green", "Blue"};
  const pugi::xml_node color_limits = node.child("colorLimits");
  for (int k = 0; k < 3; ++k) {
    s.color[k] = find_field(s.fields, std::string("color") + channel[k]);
    if (s.color[k] < 0) continue;
    const Field& f = s.fields[static_cast<std::size_t>(s.color[k])];
    s.color_lo[k] =
        element_value(xml, color_limits.child((std::string("color") + channel[k] + "Minimum").c_str()), f.minimum);
    s.color_hi[k] =
        element_value(xml, color_limits.child((std::string("color") + channel[k] + "Maximum").c_str()), f.maximum);
  }
  s.intensity = find_field(s.fields, "intensity");
  if (const pugi::xml_node limits = node.child("intensityLimits")) {
    const double lo = element_value(xml, limits.child("intensityMinimum"), 0),
                 hi = element_value(xml, limits.child("intensityMaximum"), 0);
    if (hi > lo && std::isfinite(hi - lo)) s.intensity_limits = std::array<double, 2>{lo, hi};
  }
  if (const pugi::xml_node pose = node.child("pose")) {
    s.has_pose = true;
    if (const pugi::xml_node r = pose.child("rotation")) {
      const Eigen::Quaterniond q(element_value(xml, r.child("w"), 0), element_value(xml, r.child("x"), 0),
                                 element_value(xml, r.child("y"), 0), element_value(xml, r.child("z"), 0));
      if (!(q.norm() > 1e-12) || !std::isfinite(q.norm())) xml.fail(r, "pose rotation is not a valid quaternion");
      const Eigen::Quaterniond unit = q.normalized();
      s.rotation = unit.toRotationMatrix();
      s.posed = unit.coeffs() != Eigen::Quaterniond::Identity().coeffs();
    }
    const pugi::xml_node t = pose.child("translation");
    s.translation = {element_value(xml, t.child("x"), 0), element_value(xml, t.child("y"), 0),
                     element_value(xml, t.child("z"), 0)};
    if (!s.translation.allFinite()) xml.fail(t, "pose translation is not finite");
    s.posed = s.posed || !s.translation.isZero(0);
  }
  const std::uint64_t offset = number_attribute<std::uint64_t>(xml, points, "fileOffset", 0);
  s.records = number_attribute<std::uint64_t>(xml, points, "recordCount", 0);
  if (!points.attribute("fileOffset") || !points.attribute("recordCount"))
    xml.fail(points, "<points> needs fileOffset and recordCount attributes");
  if (s.records == 0) return s;  // an empty scan's section is never read
  s.section = e57::open_section(xml.pages, offset, s.records, bits, xml.where(points));
  // Sections do not overlap, so all scans' records together fit in the file too.
  const std::uint64_t max_bits = xml.pages.header().physical_length * 8;
  if (s.records > (max_bits - total_bits) / std::max<std::uint64_t>(bits, 1))
    xml.fail(points, "recordCount " + std::to_string(s.records) +
                         " and the scans before it hold more records than the file can");
  total_bits += s.records * std::max<std::uint64_t>(bits, 1);
  return s;
}

}  // namespace

Scans read_scans(const PagedFile& pages) {
  const FileHeader& header = pages.header();
  Xml xml{pages, pages.to_logical(header.xml_physical_offset, "xmlPhysicalOffset", 24)};
  if (header.xml_logical_length > pages.logical_size() - xml.logical)
    pages.fail(
        32, "XML section of " + std::to_string(header.xml_logical_length) + " bytes reaches past the end of the file");
  if (header.xml_logical_length > kMaxXmlBytes)
    pages.fail(
        32, "XML section of " + std::to_string(header.xml_logical_length) + " bytes is larger than the 64 MiB limit");
  std::string text(static_cast<std::size_t>(header.xml_logical_length), '\0');
  pages.read(xml.logical, text.size(), reinterpret_cast<unsigned char*>(text.data()));
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed =
      doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed)
    pages.fail(pages.to_physical(xml.logical + static_cast<std::uint64_t>(std::max<std::ptrdiff_t>(parsed.offset, 0))),
               std::string("XML section is not well-formed: ") + parsed.description());
  const pugi::xml_node root = doc.child("e57Root");
  if (!root) pages.fail(header.xml_physical_offset, "XML section has no <e57Root>");
  const pugi::xml_node data3d = root.child("data3D");
  if (!data3d) xml.fail(root, "file has no <data3D> (no point clouds)");

  Scans out;
  std::uint64_t total_bits = 0;
  for (const pugi::xml_node& node : data3d.children())
    if (node.type() == pugi::node_element) {
      out.scans.push_back(read_scan(xml, node, total_bits));
      out.records += out.scans.back().records;
    }
  return out;
}

std::vector<StreamField> Scan::streams() const {
  std::vector<StreamField> out(fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) out[i].codec = fields[i].codec;
  return out;
}

std::uint8_t Scan::color_byte(int k, double v) const {
  const double lo = color_lo[k], hi = color_hi[k];
  const double t = hi > lo && std::isfinite(hi - lo) ? (v - lo) * 255.0 / (hi - lo) : v;
  if (!(t > 0)) return 0;
  return t >= 255 ? std::uint8_t{255} : static_cast<std::uint8_t>(std::lround(t));
}

Eigen::Vector3d Scan::position(const Eigen::Vector3d& decoded) const {
  Eigen::Vector3d p = decoded;
  if (spherical) {
    const double r = decoded(0), az = decoded(1), el = decoded(2);
    p << r * std::cos(el) * std::cos(az), r * std::cos(el) * std::sin(az), r * std::sin(el);
  }
  return posed ? Eigen::Vector3d(rotation * p + translation) : p;
}

}  // namespace clustersurf::io::e57
