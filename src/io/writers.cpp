// PLY (binary little-endian or ascii), XYZ, OBJ and OFF writers, all atomic, all in the file's
// coordinates (positions + origin).

#include "io/atomic_file.hpp"
#include "io/ply_mesh_stream.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>

#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <vector>

namespace clustersurf {

namespace {

/// A coordinate put back at its origin; an origin of 0 leaves it untouched (-0 stays -0).
double at_origin(double x, double origin) { return origin == 0 ? x : x + origin; }

static_assert(std::endian::native == std::endian::little, "binary writers assume a little-endian host");

/// The records of a PLY body, binary or ascii, buffered into an atomic file in blocks of about 1 MiB.
class PlyBody {
 public:
  PlyBody(io::AtomicFile& out, const PlyWriteOptions& o) : out_(out), o_(o) { buf_.reserve(1 << 20); }

  /// A vertex record: position at `origin`, then the normal, color and attributes given.
  void vertex(Eigen::Index i, const Points& v, const Eigen::Vector3d& origin, const Points* n, const Colors* c,
              const std::vector<const PointAttribute*>& extra) {
    if (o_.binary) {
      for (int k = 0; k < 3; ++k) put_real(at_origin(v(i, k), origin(k)));
      if (n)
        for (int k = 0; k < 3; ++k) put_real((*n)(i, k));
      if (c)
        for (int k = 0; k < 3; ++k) put((*c)(i, k));
      for (const PointAttribute* a : extra) put(a->values(i));
    } else {
      for (int k = 0; k < 3; ++k) {
        if (k > 0) buf_.push_back(' ');
        text_real(at_origin(v(i, k), origin(k)));
      }
      if (n)
        for (int k = 0; k < 3; ++k) buf_.push_back(' '), text_real((*n)(i, k));
      if (c) fmt::format_to(std::back_inserter(buf_), " {} {} {}", (*c)(i, 0), (*c)(i, 1), (*c)(i, 2));
      for (const PointAttribute* a : extra) fmt::format_to(std::back_inserter(buf_), " {}", a->values(i));
      buf_.push_back('\n');
    }
    flush_if_full();
  }

  /// A face record of the triangle `t`.
  void triangle(const Triangles& tris, Eigen::Index t) {
    if (o_.binary) {
      put(static_cast<std::uint8_t>(3));
      for (int k = 0; k < 3; ++k) put(tris(t, k));
    } else {
      fmt::format_to(std::back_inserter(buf_), "3 {} {} {}\n", tris(t, 0), tris(t, 1), tris(t, 2));
    }
    flush_if_full();
  }

  void flush() {
    out_.write(buf_.data(), buf_.size());
    buf_.clear();
  }

 private:
  void flush_if_full() {
    if (buf_.size() > (1u << 20) - 256) flush();
  }
  template <class T>
  void put(const T& value) {
    const char* p = reinterpret_cast<const char*>(&value);
    buf_.append(p, p + sizeof(value));
  }
  void put_real(double x) {
    if (o_.double_precision)
      put(x);
    else
      put(static_cast<float>(x));
  }
  /// The shortest text that reads back to the same value ({} in fmt).
  void text_real(double x) {
    if (o_.double_precision)
      fmt::format_to(std::back_inserter(buf_), "{}", x);
    else
      fmt::format_to(std::back_inserter(buf_), "{}", static_cast<float>(x));
  }

  io::AtomicFile& out_;
  const PlyWriteOptions& o_;
  fmt::memory_buffer buf_;
};

void write_ply_impl(const std::filesystem::path& file, const Points& v, const Eigen::Vector3d& origin, UpAxis up,
                    const Points& n, const Colors& c, const std::vector<PointAttribute>& attributes,
                    const Triangles* tris, PlyWriteOptions o) {
  const Eigen::Index nv = v.rows();
  o.double_precision = o.double_precision || !origin.isZero();
  const bool has_n = n.rows() == nv && nv > 0;
  const bool has_c = c.rows() == nv && nv > 0;
  std::vector<const PointAttribute*> extra;  // the attributes with a value per vertex
  std::vector<std::string> names;
  for (const PointAttribute& a : attributes)
    if (a.values.size() == nv && nv > 0 && !a.name.empty() && a.name.find_first_of(" \t\r\n") == std::string::npos) {
      extra.push_back(&a);
      names.push_back(a.name);
    }
  const std::string h =
      io::ply_header(static_cast<std::uint64_t>(nv),
                     tris != nullptr ? std::optional(static_cast<std::uint64_t>(tris->rows())) : std::nullopt, o.binary,
                     o.double_precision, has_n, has_c, names, up);
  io::AtomicFile out(file);
  out.write(h);
  PlyBody body(out, o);
  for (Eigen::Index i = 0; i < nv; ++i) body.vertex(i, v, origin, has_n ? &n : nullptr, has_c ? &c : nullptr, extra);
  if (tris != nullptr)
    for (Eigen::Index t = 0; t < tris->rows(); ++t) body.triangle(*tris, t);
  body.flush();
  out.commit();
}

}  // namespace

std::string io::ply_header(std::uint64_t vertices, std::optional<std::uint64_t> faces, bool binary,
                           bool double_precision, bool normals, bool colors, const std::vector<std::string>& attributes,
                           UpAxis up) {
  const char* real = double_precision ? "double" : "float";
  std::string h = "ply\n";
  h += binary ? "format binary_little_endian 1.0\n" : "format ascii 1.0\n";
  h += "comment written by clustersurf\n";
  if (up == UpAxis::Z) h += "comment up z\n";
  h += fmt::format("element vertex {}\nproperty {} x\nproperty {} y\nproperty {} z\n", vertices, real, real, real);
  if (normals) h += fmt::format("property {} nx\nproperty {} ny\nproperty {} nz\n", real, real, real);
  if (colors) h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  for (const std::string& name : attributes) h += "property float " + name + "\n";
  if (faces) h += fmt::format("element face {}\nproperty list uchar int vertex_indices\n", *faces);
  h += "end_header\n";
  return h;
}

void write_ply(const std::filesystem::path& file, const PointCloud& cloud, const PlyWriteOptions& options) {
  if (cloud.scanner_of_point.size() != static_cast<std::size_t>(cloud.size()) || cloud.empty()) {
    write_ply_impl(file, cloud.positions, cloud.origin, cloud.up, cloud.normals, cloud.colors, cloud.attributes,
                   nullptr, options);
    return;
  }
  // Which scan saw each point, as the "scan" property the reader takes it from (floats hold
  // every index below 2^24 exactly).
  std::vector<PointAttribute> attributes = cloud.attributes;
  PointAttribute& scan = attributes.emplace_back(PointAttribute{"scan", Eigen::VectorXf(cloud.size())});
  for (Eigen::Index i = 0; i < cloud.size(); ++i)
    scan.values(i) = static_cast<float>(cloud.scanner_of_point[static_cast<std::size_t>(i)]);
  write_ply_impl(file, cloud.positions, cloud.origin, cloud.up, cloud.normals, cloud.colors, attributes, nullptr,
                 options);
}

void write_ply(const std::filesystem::path& file, const TriangleMesh& mesh, const PlyWriteOptions& options) {
  write_ply_impl(file, mesh.vertices, mesh.origin, mesh.up, mesh.normals, mesh.colors, mesh.attributes, &mesh.triangles,
                 options);
}

void write_xyz(const std::filesystem::path& file, const PointCloud& cloud) {
  io::AtomicFile out(file);
  fmt::memory_buffer text;
  for (Eigen::Index i = 0; i < cloud.size(); ++i) {
    fmt::format_to(std::back_inserter(text), "{} {} {}", at_origin(cloud.positions(i, 0), cloud.origin.x()),
                   at_origin(cloud.positions(i, 1), cloud.origin.y()),
                   at_origin(cloud.positions(i, 2), cloud.origin.z()));
    if (cloud.has_normals())
      fmt::format_to(std::back_inserter(text), " {} {} {}", cloud.normals(i, 0), cloud.normals(i, 1),
                     cloud.normals(i, 2));
    text.push_back('\n');
    if (text.size() > (1u << 20)) out.write(text.data(), text.size()), text.clear();
  }
  out.write(text.data(), text.size());
  out.commit();
}

void write_obj(const std::filesystem::path& file, const TriangleMesh& mesh) {
  io::AtomicFile out(file);
  fmt::memory_buffer text;
  fmt::format_to(std::back_inserter(text), "# written by clustersurf: {} vertices, {} triangles\n",
                 mesh.vertices.rows(), mesh.triangles.rows());
  const bool has_n = mesh.normals.rows() == mesh.vertices.rows() && mesh.vertices.rows() > 0;
  const bool has_c = mesh.colors.rows() == mesh.vertices.rows() && mesh.vertices.rows() > 0;
  auto drain = [&] {
    if (text.size() > (1u << 20)) out.write(text.data(), text.size()), text.clear();
  };
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
    fmt::format_to(std::back_inserter(text), "v {} {} {}", at_origin(mesh.vertices(i, 0), mesh.origin.x()),
                   at_origin(mesh.vertices(i, 1), mesh.origin.y()), at_origin(mesh.vertices(i, 2), mesh.origin.z()));
    if (has_c)
      fmt::format_to(std::back_inserter(text), " {:.4f} {:.4f} {:.4f}", mesh.colors(i, 0) / 255.0,
                     mesh.colors(i, 1) / 255.0, mesh.colors(i, 2) / 255.0);
    text.push_back('\n');
    drain();
  }
  if (has_n)
    for (Eigen::Index i = 0; i < mesh.normals.rows(); ++i) {
      fmt::format_to(std::back_inserter(text), "vn {} {} {}\n", mesh.normals(i, 0), mesh.normals(i, 1),
                     mesh.normals(i, 2));
      drain();
    }
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f) {
    const auto a = mesh.triangles(f, 0) + 1, b = mesh.triangles(f, 1) + 1, c = mesh.triangles(f, 2) + 1;
    if (has_n)
      fmt::format_to(std::back_inserter(text), "f {}//{} {}//{} {}//{}\n", a, a, b, b, c, c);
    else
      fmt::format_to(std::back_inserter(text), "f {} {} {}\n", a, b, c);
    drain();
  }
  out.write(text.data(), text.size());
  out.commit();
}

void write_off(const std::filesystem::path& file, const TriangleMesh& mesh) {
  io::AtomicFile out(file);
  const Eigen::Index nv = mesh.vertices.rows();
  const bool has_c = mesh.colors.rows() == nv && nv > 0;
  fmt::memory_buffer text;
  fmt::format_to(std::back_inserter(text), "{}\n{} {} 0\n", has_c ? "COFF" : "OFF", nv, mesh.triangles.rows());
  auto drain = [&] {
    if (text.size() > (1u << 20)) out.write(text.data(), text.size()), text.clear();
  };
  for (Eigen::Index i = 0; i < nv; ++i) {
    fmt::format_to(std::back_inserter(text), "{} {} {}", at_origin(mesh.vertices(i, 0), mesh.origin.x()),
                   at_origin(mesh.vertices(i, 1), mesh.origin.y()), at_origin(mesh.vertices(i, 2), mesh.origin.z()));
    if (has_c)
      fmt::format_to(std::back_inserter(text), " {} {} {} 255", mesh.colors(i, 0), mesh.colors(i, 1),
                     mesh.colors(i, 2));
    text.push_back('\n');
    drain();
  }
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f) {
    fmt::format_to(std::back_inserter(text), "3 {} {} {}\n", mesh.triangles(f, 0), mesh.triangles(f, 1),
                   mesh.triangles(f, 2));
    drain();
  }
  out.write(text.data(), text.size());
  out.commit();
}

}  // namespace clustersurf
