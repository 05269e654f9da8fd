// The vertex and face records of a PLY file, filled the same way from either encoding.

#include "io/ply_format.hpp"

#include <algorithm>
#include <cmath>

namespace clustersurf::io::ply {

std::uint8_t to_color(double v, Scalar type) {
  double c;
  switch (type) {
    case Scalar::Float32:
    case Scalar::Float64:
      c = v * 255.0;
      break;
    case Scalar::UInt16:
    case Scalar::Int16:
      c = v / 257.0;
      break;
    default:
      c = v;
      break;
  }
  if (!(c > 0)) return 0;  // also NaN
  if (c >= 255) return 255;
  return static_cast<std::uint8_t>(std::lround(c));
}

VertexLayout vertex_layout(const std::filesystem::path& file, const Element& v) {
  VertexLayout l;
  l.pos = {v.find({"x"}), v.find({"y"}), v.find({"z"})};
  if (l.pos[0] < 0 || l.pos[1] < 0 || l.pos[2] < 0)
    fail_line(file, v.header_line, "vertex element lacks one of the properties x, y, z");
  l.nrm = {v.find({"nx", "normal_x"}), v.find({"ny", "normal_y"}), v.find({"nz", "normal_z"})};
  l.rgb = {v.find({"red", "r", "diffuse_red"}), v.find({"green", "g", "diffuse_green"}),
           v.find({"blue", "b", "diffuse_blue"})};
  l.scan = v.find({"scan", "scan_index"});
  for (int idx : {l.pos[0], l.pos[1], l.pos[2], l.nrm[0], l.nrm[1], l.nrm[2], l.rgb[0], l.rgb[1], l.rgb[2], l.scan})
    if (idx >= 0 && v.properties[static_cast<std::size_t>(idx)].is_list)
      fail_line(
          file, v.header_line,
          "vertex property \"" + v.properties[static_cast<std::size_t>(idx)].name + "\" is a list; expected a scalar");
  return l;
}

VertexRecords::VertexRecords(const std::filesystem::path& file, const Element& vertex, ParsedFile& out)
    : element_(vertex), layout_(vertex_layout(file, vertex)), out_(out) {
  if (vertex.count > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
    fail_line(file, vertex.header_line,
              "too many vertices (" + std::to_string(vertex.count) + "); at most 2^31-1 supported");
  const auto n = static_cast<Eigen::Index>(vertex.count);
  out.cloud.positions.resize(n, 3);
  if (layout_.normals()) out.cloud.normals.resize(n, 3);
  if (layout_.colors()) out.cloud.colors.resize(n, 3);
  if (layout_.scan >= 0) out.cloud.scanner_of_point.resize(static_cast<std::size_t>(n));
}

std::uint32_t VertexRecords::scan(double value) {
  return value >= 0 && value < static_cast<double>(kNotAScan) && value == std::floor(value)
             ? static_cast<std::uint32_t>(value)
             : kNotAScan;
}

std::uint8_t VertexRecords::color(double value, int property) const {
  return to_color(value, element_.properties[static_cast<std::size_t>(property)].type);
}

void FaceSink::emit(std::int64_t vertex_count, const std::filesystem::path& file, const FileLocation& where) {
  if (poly.size() < 3) return;  // points and edges carry no triangles
  for (auto i : poly)
    if (i < 0 || i >= vertex_count)
      throw InputError(file, where,
                       "face refers to vertex " + std::to_string(i) + " but there are " + std::to_string(vertex_count) +
                           " vertices");
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    tri.push_back(static_cast<std::int32_t>(poly[0]));
    tri.push_back(static_cast<std::int32_t>(poly[k]));
    tri.push_back(static_cast<std::int32_t>(poly[k + 1]));
  }
}

void finish(const std::filesystem::path& file, bool seen_vertex, bool want_faces, FaceSink& faces, ParsedFile& out) {
  if (!seen_vertex) fail_line(file, 1, "PLY file has no \"vertex\" element");
  std::vector<std::uint32_t>& scans = out.cloud.scanner_of_point;
  if (std::find(scans.begin(), scans.end(), kNotAScan) != scans.end()) scans.clear();
  if (want_faces)
    out.triangles = Eigen::Map<Triangles>(faces.tri.data(), static_cast<Eigen::Index>(faces.tri.size() / 3), 3);
}

}  // namespace clustersurf::io::ply
