// Binary mesh writers: STL (printers) and glTF 2.0 binary (Blender, the web). Both atomic.

#include "io/atomic_file.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <fmt/format.h>

#include <Eigen/Geometry>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace clustersurf {

namespace {

static_assert(std::endian::native == std::endian::little, "binary writers assume a little-endian host");

bool has_rows(const auto& m, Eigen::Index n) { return n > 0 && m.rows() == n; }

/// Appends the bytes of `value` to `out`.
template <class T>
void put(std::vector<char>& out, const T& value) {
  const char* p = reinterpret_cast<const char*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}

/// Pads `out` with `fill` to a multiple of 4 bytes (glTF chunk and view alignment).
void pad4(std::vector<char>& out, char fill) {
  while (out.size() % 4 != 0) out.push_back(fill);
}

/// Unit vertex normals fit for glTF (which requires unit length), or empty when the mesh has
/// none or one of them is zero or not finite.
Points unit_normals(const TriangleMesh& mesh) {
  const Eigen::Index nv = mesh.vertices.rows();
  if (!has_rows(mesh.normals, nv)) return {};
  Points n = mesh.normals;
  for (Eigen::Index i = 0; i < nv; ++i) {
    const double len = n.row(i).norm();
    if (!(len > 0) || !std::isfinite(len)) return {};
    n.row(i) /= len;
  }
  return n;
}

}  // namespace

void write_stl(const std::filesystem::path& file, const TriangleMesh& mesh) {
  const Eigen::Index nf = mesh.triangles.rows();
  if (nf > std::numeric_limits<std::uint32_t>::max()) throw OptionError(file.string() + ": too many triangles for STL");
  std::string header = mesh.origin.isZero() ? std::string("binary STL written by clustersurf")
                                            : fmt::format("clustersurf; coordinates relative to origin {} {} {}",
                                                          mesh.origin.x(), mesh.origin.y(), mesh.origin.z());
  header.resize(80, ' ');
  io::AtomicFile out(file);
  out.write(header);
  std::vector<char> buf;
  buf.reserve(1 << 20);
  put(buf, static_cast<std::uint32_t>(nf));
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(f, 0)), b = mesh.vertices.row(mesh.triangles(f, 1)),
                          c = mesh.vertices.row(mesh.triangles(f, 2));
    Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    n = len > 0 && std::isfinite(len) ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& v : {n, a, b, c})
      for (int k = 0; k < 3; ++k) put(buf, static_cast<float>(v(k)));
    put(buf, std::uint16_t{0});
    if (buf.size() > (1u << 20) - 64) out.write(buf.data(), buf.size()), buf.clear();
  }
  out.write(buf.data(), buf.size());
  out.commit();
}

namespace {

/// The binary chunk of a GLB: positions, then normals, then RGBA colors, then indices, each a
/// buffer view (offset and length), and the positions' bounds.
struct GlbBuffer {
  struct View {
    std::size_t offset, length;
  };
  std::vector<char> bytes;
  std::vector<View> views;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity()), hi = -lo;

  void begin_view() {
    pad4(bytes, '\0');
    views.push_back({bytes.size(), 0});
  }
  void end_view() { views.back().length = bytes.size() - views.back().offset; }
};

/// glb_buffer() of `mesh` with `normals` (unit_normals(), empty for none) and its colors when
/// `colors`.
GlbBuffer glb_buffer(const TriangleMesh& mesh, const Points& normals, bool colors) {
  const Eigen::Index nv = mesh.vertices.rows(), nf = mesh.triangles.rows();
  GlbBuffer b;
  b.begin_view();
  for (Eigen::Index i = 0; i < nv; ++i) {
    const Eigen::Vector3f p = mesh.vertices.row(i).transpose().cast<float>();
    b.lo = b.lo.cwiseMin(p), b.hi = b.hi.cwiseMax(p);
    for (int k = 0; k < 3; ++k) put(b.bytes, p(k));
  }
  b.end_view();
  if (normals.rows() > 0) {
    b.begin_view();
    for (Eigen::Index i = 0; i < nv; ++i)
      for (int k = 0; k < 3; ++k) put(b.bytes, static_cast<float>(normals(i, k)));
    b.end_view();
  }
  if (colors) {
    b.begin_view();
    for (Eigen::Index i = 0; i < nv; ++i) {
      for (int k = 0; k < 3; ++k) put(b.bytes, mesh.colors(i, k));
      put(b.bytes, std::uint8_t{255});
    }
    b.end_view();
  }
  b.begin_view();
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) put(b.bytes, static_cast<std::uint32_t>(mesh.triangles(f, k)));
  b.end_view();
  pad4(b.bytes, '\0');
  return b;
}

/// The JSON chunk of a GLB over `buffer`: one scene, one node (translated to the mesh's origin,
/// turned to glTF's +y up), one indexed primitive; padded with spaces to 4 bytes.
std::string glb_json(const TriangleMesh& mesh, const GlbBuffer& buffer, bool normals, bool colors) {
  const Eigen::Index nv = mesh.vertices.rows(), nf = mesh.triangles.rows();
  std::string views_json, accessors_json, attributes_json;
  int view = 0;
  auto add_view = [&](int target) {
    if (!views_json.empty()) views_json += ',';
    views_json += fmt::format(R"({{"buffer":0,"byteOffset":{},"byteLength":{},"target":{}}})",
                              buffer.views[view].offset, buffer.views[view].length, target);
    return view++;
  };
  auto add_accessor = [&](int v, int component, Eigen::Index count, const char* type, const std::string& extra) {
    if (!accessors_json.empty()) accessors_json += ',';
    accessors_json += fmt::format(R"({{"bufferView":{},"componentType":{},"count":{},"type":"{}"{}}})", v, component,
                                  count, type, extra);
  };
  constexpr int kFloat = 5126, kUnsignedByte = 5121, kUnsignedInt = 5125, kArrayBuffer = 34962, kElementArray = 34963;
  int accessor = 0;
  const Eigen::Vector3f& lo = buffer.lo;
  const Eigen::Vector3f& hi = buffer.hi;
  add_accessor(
      add_view(kArrayBuffer), kFloat, nv, "VEC3",
      nv > 0 ? fmt::format(R"(,"min":[{},{},{}],"max":[{},{},{}])", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z())
             : std::string());
  attributes_json = fmt::format(R"("POSITION":{})", accessor++);
  if (normals) {
    add_accessor(add_view(kArrayBuffer), kFloat, nv, "VEC3", "");
    attributes_json += fmt::format(R"(,"NORMAL":{})", accessor++);
  }
  if (colors) {
    add_accessor(add_view(kArrayBuffer), kUnsignedByte, nv, "VEC4", R"(,"normalized":true)");
    attributes_json += fmt::format(R"(,"COLOR_0":{})", accessor++);
  }
  add_accessor(add_view(kElementArray), kUnsignedInt, 3 * nf, "SCALAR", "");
  const int indices = accessor++;
  // glTF is +y up: a z-up mesh is turned by -90 degrees about x, (x, y, z) -> (x, z, -y), its
  // origin with it (the node's transform is translation * rotation).
  const bool z_up = mesh.up == UpAxis::Z;
  const Eigen::Vector3d shift =
      z_up ? Eigen::Vector3d(mesh.origin.x(), mesh.origin.z(), -mesh.origin.y()) : mesh.origin;
  std::string translation =
      shift.isZero() ? std::string() : fmt::format(R"(,"translation":[{},{},{}])", shift.x(), shift.y(), shift.z());
  if (z_up) translation += R"(,"rotation":[-0.7071067811865476,0,0,0.7071067811865476])";
  std::string json = fmt::format(
      R"({{"asset":{{"version":"2.0","generator":"clustersurf"}},"scene":0,"scenes":[{{"nodes":[0]}}],)"
      R"("nodes":[{{"mesh":0{}}}],"meshes":[{{"primitives":[{{"attributes":{{{}}},"indices":{},"mode":4}}]}}],)"
      R"("accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]}})",
      translation, attributes_json, indices, accessors_json, views_json, buffer.bytes.size());
  while (json.size() % 4 != 0) json.push_back(' ');
  return json;
}

}  // namespace

void write_glb(const std::filesystem::path& file, const TriangleMesh& mesh) {
  const Points normals = unit_normals(mesh);
  const bool has_n = normals.rows() == mesh.vertices.rows() && mesh.vertices.rows() > 0;
  const bool has_c = has_rows(mesh.colors, mesh.vertices.rows());
  const GlbBuffer buffer = glb_buffer(mesh, has_n ? normals : Points(), has_c);
  const std::string json = glb_json(mesh, buffer, has_n, has_c);
  const std::vector<char>& bin = buffer.bytes;

  const std::size_t total = 12 + 8 + json.size() + 8 + bin.size();
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw OptionError(file.string() + ": mesh too large for GLB (4 GB)");
  std::vector<char> head;
  put(head, std::uint32_t{0x46546C67});  // "glTF"
  put(head, std::uint32_t{2});
  put(head, static_cast<std::uint32_t>(total));
  put(head, static_cast<std::uint32_t>(json.size()));
  put(head, std::uint32_t{0x4E4F534A});  // "JSON"
  io::AtomicFile out(file);
  out.write(head.data(), head.size());
  out.write(json);
  head.clear();
  put(head, static_cast<std::uint32_t>(bin.size()));
  put(head, std::uint32_t{0x004E4942});  // "BIN\0"
  out.write(head.data(), head.size());
  out.write(bin.data(), bin.size());
  out.commit();
}

}  // namespace clustersurf
