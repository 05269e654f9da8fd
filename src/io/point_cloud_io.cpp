// Format dispatch and validation shared by every reader (non-finite values, empty clouds).

#include "io/mapped_file.hpp"
#include "io/readers.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/io/surface_sampling.hpp>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

namespace clustersurf {

namespace {

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool has_ply_magic(std::string_view bytes) { return bytes.substr(0, 4) == "ply\n" || bytes.substr(0, 5) == "ply\r\n"; }

/// Rejects (or drops, by option) points with a non-finite coordinate or normal.
void check_finite(const std::filesystem::path& file, io::ParsedFile& parsed, const ReadOptions& options) {
  PointCloud& c = parsed.cloud;
  const Eigen::Index n = c.size();
  std::vector<Eigen::Index> keep;
  keep.reserve(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    const bool ok = c.positions.row(i).allFinite() && (!c.has_normals() || c.normals.row(i).allFinite());
    if (!ok && !options.drop_non_finite)
      throw InputError(file, parsed.first_non_finite.value_or(FileLocation{}),
                       "point " + std::to_string(i) +
                           " (0-based) has a non-finite coordinate or normal "
                           "(NaN or Inf); use the option to drop such points");
    if (ok) keep.push_back(i);
  }
  const auto m = static_cast<Eigen::Index>(keep.size());
  if (m == n) return;
  if (parsed.triangles.rows() != 0)
    throw InputError(file, parsed.first_non_finite.value_or(FileLocation{}),
                     "mesh has vertices with non-finite coordinates; they cannot be dropped without breaking faces");
  c = select(c, keep);
  if (options.warn)
    options.warn(file.string() + ": dropped " + std::to_string(n - m) + " of " + std::to_string(n) +
                 " points with non-finite coordinates or normals");
}

const char* format_name(FileFormat format) {
  switch (format) {
    case FileFormat::Ply:
      return "PLY";
    case FileFormat::Xyz:
      return "XYZ";
    case FileFormat::Obj:
      return "OBJ";
    case FileFormat::Las:
      return "LAS";
    case FileFormat::E57:
      return "E57";
    case FileFormat::Ptx:
      return "PTX";
    case FileFormat::Pcd:
      return "PCD";
    case FileFormat::Off:
      return "OFF";
    case FileFormat::Stl:
      return "STL";
    case FileFormat::Glb:
      return "glTF";
  }
  return "?";
}

io::ParsedFile parse(std::string_view bytes, FileFormat format, const std::filesystem::path& file,
                     const ReadOptions& options, bool want_faces) {
  if (bytes.empty()) throw InputError(file, {}, "file is empty");
  format = format_from_magic(bytes).value_or(format);
  const bool holds_faces = format == FileFormat::Ply || format == FileFormat::Obj;
  if (want_faces && !holds_faces)
    throw InputError(
        file, {},
        std::string("cannot read a mesh from a ") + format_name(format) + " file (meshes are read from .ply or .obj)");
  io::ParsedFile parsed;
  switch (format) {
    case FileFormat::Ply:
      parsed = io::read_ply(file, bytes, want_faces);
      break;
    case FileFormat::Obj:
      parsed = io::read_obj(file, bytes, want_faces);
      break;
    case FileFormat::Xyz:
      parsed = io::read_xyz(file, bytes);
      break;
    case FileFormat::Las:
      parsed = io::read_las(file, bytes);
      break;
    case FileFormat::E57:
      parsed = io::read_e57(file, bytes);
      break;
    case FileFormat::Ptx:
      parsed = io::read_ptx(file, bytes);
      break;
    case FileFormat::Pcd:
      parsed = io::read_pcd(file, bytes);
      break;
    case FileFormat::Off:
    case FileFormat::Stl:
    case FileFormat::Glb:
      throw InputError(file, {},
                       std::string("cannot read ") + format_name(format) +
                           " files: clustersurf writes them (read clouds from .ply, .xyz, .obj, "
                           ".las, .e57, .ptx or .pcd)");
  }
  // Georeferenced surveys are z-up by convention.
  if (format == FileFormat::Las || format == FileFormat::E57 || format == FileFormat::Ptx) parsed.cloud.up = UpAxis::Z;
  check_finite(file, parsed, options);
  if (parsed.cloud.empty()) throw InputError(file, {}, "file holds no points");
  return parsed;
}

io::ParsedFile read(const std::filesystem::path& file, const ReadOptions& options, bool want_faces) {
  const io::MappedFile mapped(file);
  const std::string_view bytes = mapped.view();
  // The signature decides before the extension (a PLY file named .xyz is still read), and an
  // empty file is reported as such whatever its name.
  const FileFormat format =
      bytes.empty() ? FileFormat::Ply : format_from_magic(bytes).value_or(format_from_extension(file));
  return parse(bytes, format, file, options, want_faces);
}

/// Whether `bytes` (of a PLY or OBJ file) declares faces: a PLY header's face element, or an
/// OBJ `f` record. Cheap: it decides whether a cloud without normals is parsed again as a mesh.
bool declares_faces(std::string_view bytes) {
  if (has_ply_magic(bytes)) {
    const std::size_t end = bytes.find("end_header");
    const std::string_view header = bytes.substr(0, end);
    return header.find("\nelement face ") != std::string_view::npos;
  }
  return bytes.substr(0, 2) == "f " || bytes.find("\nf ") != std::string_view::npos;
}

TriangleMesh to_mesh(io::ParsedFile&& parsed) {
  TriangleMesh mesh;
  mesh.vertices = std::move(parsed.cloud.positions);
  mesh.normals = std::move(parsed.cloud.normals);
  mesh.colors = std::move(parsed.cloud.colors);
  mesh.up = parsed.cloud.up;
  mesh.triangles = std::move(parsed.triangles);
  return mesh;
}

/// `mesh` moved next to zero when it lies far from it (shift_to_origin()).
TriangleMesh shifted_to_origin(TriangleMesh mesh) {
  shift_to_origin(mesh);
  return mesh;
}

/// Turns every triangle whose winding disagrees with the sum of its vertices' normals (a file
/// whose normals and winding disagree), so its samples' normals follow the file's normals.
void orient_faces_by_normals(TriangleMesh& mesh) {
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const auto tri = mesh.triangles.row(t);
    const Eigen::Vector3d a = mesh.vertices.row(tri(0)), b = mesh.vertices.row(tri(1)), c = mesh.vertices.row(tri(2));
    const Eigen::Vector3d n =
        (mesh.normals.row(tri(0)) + mesh.normals.row(tri(1)) + mesh.normals.row(tri(2))).transpose();
    if ((b - a).cross(c - a).dot(n) < 0) std::swap(mesh.triangles(t, 1), mesh.triangles(t, 2));
  }
}

}  // namespace

FileFormat format_from_extension(const std::filesystem::path& file) {
  const std::string ext = lower_extension(file);
  if (ext == ".ply") return FileFormat::Ply;
  if (ext == ".xyz" || ext == ".pts" || ext == ".txt" || ext == ".csv" || ext == ".xyzn") return FileFormat::Xyz;
  if (ext == ".obj") return FileFormat::Obj;
  if (ext == ".las") return FileFormat::Las;
  if (ext == ".laz")
    throw InputError(file, {},
                     "LAZ (compressed LAS) is not supported: decompress it to .las first (e.g. laszip or PDAL)");
  if (ext == ".e57") return FileFormat::E57;
  if (ext == ".ptx") return FileFormat::Ptx;
  if (ext == ".pcd") return FileFormat::Pcd;
  if (ext == ".off") return FileFormat::Off;
  if (ext == ".stl") return FileFormat::Stl;
  if (ext == ".glb") return FileFormat::Glb;
  throw InputError(file, {},
                   "unknown file format \"" + ext +
                       "\" (expected .ply, .xyz, .pts, .txt, .csv, .obj, .las, .e57, .ptx, .pcd, .off, .stl or .glb)");
}

std::optional<FileFormat> format_from_magic(std::string_view bytes) {
  if (has_ply_magic(bytes)) return FileFormat::Ply;
  if (bytes.substr(0, 4) == "LASF") return FileFormat::Las;
  if (bytes.substr(0, 8) == "ASTM-E57") return FileFormat::E57;
  if (bytes.substr(0, 6) == "# .PCD" || bytes.substr(0, 8) == "VERSION ") return FileFormat::Pcd;
  return std::nullopt;
}

Points vertex_normals(const TriangleMesh& mesh) {
  Points normals = Points::Zero(mesh.vertices.rows(), 3);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const auto tri = mesh.triangles.row(t);
    const Eigen::Vector3d a = mesh.vertices.row(tri(0)), b = mesh.vertices.row(tri(1)), c = mesh.vertices.row(tri(2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!n.allFinite()) continue;
    for (int k = 0; k < 3; ++k) normals.row(tri(k)) += n.transpose();
  }
  for (Eigen::Index v = 0; v < normals.rows(); ++v) {
    const double norm = normals.row(v).norm();
    if (norm > 0 && std::isfinite(norm))
      normals.row(v) /= norm;
    else
      normals.row(v).setZero();
  }
  return normals;
}

PointCloud read_point_cloud(const std::filesystem::path& file, const ReadOptions& options) {
  const io::MappedFile mapped(file);
  const std::string_view bytes = mapped.view();
  const FileFormat format =
      bytes.empty() ? FileFormat::Ply : format_from_magic(bytes).value_or(format_from_extension(file));
  return parse_point_cloud(bytes, format, file, options);
}

TriangleMesh read_triangle_mesh(const std::filesystem::path& file, const ReadOptions& options) {
  return shifted_to_origin(to_mesh(read(file, options, true)));
}

PointCloud parse_point_cloud(std::string_view bytes, FileFormat format, const std::filesystem::path& name,
                             const ReadOptions& options) {
  PointCloud cloud = parse(bytes, format, name, options, false).cloud;
  shift_to_origin(cloud);
  format = format_from_magic(bytes).value_or(format);
  if ((format != FileFormat::Ply && format != FileFormat::Obj) || !declares_faces(bytes)) return cloud;
  const bool sample = options.mesh_samples > static_cast<std::size_t>(cloud.size());
  if (!sample && (!options.normals_from_faces || cloud.has_normals())) return cloud;
  // A mesh: its faces carry its surface and which side is out, when they are whole and cover
  // its vertices.
  TriangleMesh mesh;
  try {
    mesh = to_mesh(parse(bytes, format, name, options, true));
  } catch (const InputError&) {
    return cloud;  // faces the point reader skipped may be malformed; the points stand alone
  }
  if (mesh.vertices.rows() != cloud.size() || mesh.triangles.rows() == 0) return cloud;
  mesh.vertices.rowwise() -= cloud.origin.transpose();  // as shift_to_origin moved the points
  mesh.origin = cloud.origin;
  mesh.up = cloud.up;
  if (sample) {
    if (mesh.normals.rows() == mesh.vertices.rows()) orient_faces_by_normals(mesh);
    try {
      SurfaceSamplingOptions sampling;
      sampling.count = options.mesh_samples;
      PointCloud samples = sample_surface(mesh, sampling);
      if (options.warn)
        options.warn(
            fmt::format("{}: a mesh of {} vertices, read as {} points drawn uniformly on its {} faces: its "
                        "vertices alone sample it too coarsely (0 mesh samples reads them)",
                        name.string(), mesh.vertices.rows(), options.mesh_samples, mesh.triangles.rows()));
      return samples;
    } catch (const OptionError&) {
      // No face of positive area: the vertices are all there is.
    }
  }
  if (!options.normals_from_faces || cloud.has_normals()) return cloud;
  Points normals = vertex_normals(mesh);
  if (!normals.allFinite() || (normals.rowwise().squaredNorm().array() == 0).any()) return cloud;
  cloud.normals = std::move(normals);
  return cloud;
}

TriangleMesh parse_triangle_mesh(std::string_view bytes, FileFormat format, const std::filesystem::path& name,
                                 const ReadOptions& options) {
  return shifted_to_origin(to_mesh(parse(bytes, format, name, options, true)));
}

void write_point_cloud(const std::filesystem::path& file, const PointCloud& cloud, const PlyWriteOptions& ply) {
  const FileFormat format = format_from_extension(file);
  switch (format) {
    case FileFormat::Ply:
      write_ply(file, cloud, ply);
      return;
    case FileFormat::Xyz:
      write_xyz(file, cloud);
      return;
    case FileFormat::Obj: {
      TriangleMesh m;
      m.vertices = cloud.positions;
      m.normals = cloud.normals;
      m.origin = cloud.origin;
      m.up = cloud.up;
      write_obj(file, m);
      return;
    }
    default:
      throw OptionError(file.string() + ": cannot write a point cloud as " + format_name(format) +
                        " (use .ply, .xyz or .obj)");
  }
}

void write_triangle_mesh(const std::filesystem::path& file, const TriangleMesh& mesh, const PlyWriteOptions& ply) {
  const FileFormat format = format_from_extension(file);
  switch (format) {
    case FileFormat::Ply:
      write_ply(file, mesh, ply);
      return;
    case FileFormat::Obj:
      write_obj(file, mesh);
      return;
    case FileFormat::Off:
      write_off(file, mesh);
      return;
    case FileFormat::Stl:
      write_stl(file, mesh);
      return;
    case FileFormat::Glb:
      write_glb(file, mesh);
      return;
    default:
      throw OptionError(file.string() + ": cannot write a mesh as " + format_name(format) +
                        " (use .ply, .obj, .off, .stl or .glb)");
  }
}

}  // namespace clustersurf
