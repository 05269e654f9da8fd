#pragma once
// Reading and writing point clouds and triangle meshes. Clouds: PLY (ascii, binary little/big
// endian), XYZ/PTS/TXT, OBJ, and the scanners' LAS, E57, PTX and PCD. Meshes: PLY and OBJ in;
// PLY, OBJ, OFF, binary STL and glTF binary (GLB) out. Readers validate everything they read
// and throw InputError naming the file and the line or byte offset; writers write atomically
// (temporary file, then rename) and put the points back at their origin.

#include <clustersurf/core/point_cloud.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace clustersurf {

/// File formats known to the readers and writers.
enum class FileFormat { Ply, Xyz, Obj, Las, E57, Ptx, Pcd, Off, Stl, Glb };

/// The format implied by a file name's extension (.ply, .xyz/.pts/.txt/.csv, .obj, .las, .e57,
/// .ptx, .pcd, .off, .stl, .glb), or throws InputError for an unknown extension.
FileFormat format_from_extension(const std::filesystem::path& file);

/// The format a file's first bytes prove (PLY, LAS, E57 and PCD have a signature), if any.
std::optional<FileFormat> format_from_magic(std::string_view bytes);

/// Options for the point-cloud readers.
struct ReadOptions {
  /// Drop points whose coordinates (or normal) are NaN or infinite instead of failing;
  /// the number dropped is reported through `warn`. Default: fail.
  bool drop_non_finite = false;
  /// Receives non-fatal warnings (dropped points, ignored content). Default: ignore them.
  std::function<void(const std::string&)> warn;
  /// read_point_cloud() of a mesh (PLY or OBJ with faces) without vertex normals: give every
  /// vertex the area-weighted mean of its faces' normals, oriented by the faces' winding,
  /// when every vertex belongs to a face and the faces are valid. A mesh knows which side is
  /// out; its vertices alone do not.
  bool normals_from_faces = true;
  /// read_point_cloud() of a mesh (PLY or OBJ with faces) with fewer vertices than this: this
  /// many points drawn uniformly by area on its faces (sample_surface(), seed 1: the same points
  /// on every read), with its faces' normals (turned to agree with its vertex normals where it
  /// has them), its interpolated colors and its origin, instead of its vertices. A mesh's
  /// vertices sample its surface only as finely as its edges: a coarse mesh's thin parts (a
  /// bunny's ears) are thinner than that, and a surface fitted to the vertices loses them. 0
  /// reads the vertices of every mesh.
  std::size_t mesh_samples = 100'000;
};

/// Reads the points of a PLY, XYZ/PTS/TXT, OBJ, LAS, E57, PTX or PCD file (format by signature,
/// else by extension). A mesh's points are samples of its faces (ReadOptions::mesh_samples), or
/// its vertices (with normals from its faces: ReadOptions::normals_from_faces); unknown
/// properties are skipped. Scanner files
/// bring their attributes (intensity, classification) and, where the file knows where the
/// scanner stood, the scanner positions. A cloud far from zero is moved next to it
/// (shift_to_origin). Throws InputError (malformed content, no points) or IoError (cannot open
/// or read).
PointCloud read_point_cloud(const std::filesystem::path& file, const ReadOptions& options = {});

/// Unit vertex normals of `mesh`: at each vertex the sum of its triangles' cross products
/// (area-weighted, oriented by the winding), normalized; zero rows where a vertex belongs to
/// no triangle of positive area (or the sum is not finite).
Points vertex_normals(const TriangleMesh& mesh);

/// Reads a triangle mesh from PLY or OBJ (polygons are fan-triangulated). A mesh far from zero
/// (georeferenced) is moved next to it as a cloud is (shift_to_origin): its vertices are then
/// relative to TriangleMesh::origin, and the writers add it back bit for bit. Throws like
/// read_point_cloud, and InputError when a face index is out of range.
TriangleMesh read_triangle_mesh(const std::filesystem::path& file, const ReadOptions& options = {});

/// Parses a whole file's bytes already in memory, in `format` (bytes with a signature are read
/// in the format it proves, whatever `format` says); `name` names them in errors. Validates and throws exactly
/// like read_point_cloud (InputError), which reads a file through it.
PointCloud parse_point_cloud(std::string_view bytes, FileFormat format, const std::filesystem::path& name = "<memory>",
                             const ReadOptions& options = {});
/// Parses a triangle mesh's bytes in `format` (PLY or OBJ), as read_triangle_mesh.
TriangleMesh parse_triangle_mesh(std::string_view bytes, FileFormat format,
                                 const std::filesystem::path& name = "<memory>", const ReadOptions& options = {});

/// Options for writing PLY files.
struct PlyWriteOptions {
  /// Binary little-endian (default) or ascii.
  bool binary = true;
  /// Store coordinates and normals as double (bit-exact round trip) instead of float. Points
  /// with a non-zero origin are always written in double: float would lose their georeference.
  bool double_precision = false;
};

/// Writes a point cloud as PLY (with normals, colors and attributes, as float properties, when
/// present). Atomic. Throws IoError.
void write_ply(const std::filesystem::path& file, const PointCloud& cloud, const PlyWriteOptions& options = {});
/// Writes a triangle mesh as PLY (with per-vertex normals, colors and attributes when present).
/// Atomic.
void write_ply(const std::filesystem::path& file, const TriangleMesh& mesh, const PlyWriteOptions& options = {});
/// Writes a point cloud as text, one "x y z [nx ny nz]" line per point, with 17 significant
/// digits (bit-exact round trip). Atomic.
void write_xyz(const std::filesystem::path& file, const PointCloud& cloud);
/// Writes a triangle mesh as OBJ (v, vn when normals exist, f). Atomic.
void write_obj(const std::filesystem::path& file, const TriangleMesh& mesh);
/// Writes a triangle mesh as OFF (with per-vertex colors, COFF, when present). Atomic.
void write_off(const std::filesystem::path& file, const TriangleMesh& mesh);
/// Writes a triangle mesh as binary STL (facet normals from the winding; float coordinates,
/// relative to the mesh's origin when it is non-zero, as STL has no place for one). Atomic.
void write_stl(const std::filesystem::path& file, const TriangleMesh& mesh);
/// Writes a triangle mesh as glTF 2.0 binary (.glb): float positions, normals and colors when
/// present, 32-bit indices; a non-zero origin becomes the node's translation. Atomic.
void write_glb(const std::filesystem::path& file, const TriangleMesh& mesh);
/// Writes a point cloud in the format its extension names (PLY with `ply` options). Atomic.
void write_point_cloud(const std::filesystem::path& file, const PointCloud& cloud, const PlyWriteOptions& ply = {});
/// Writes a triangle mesh as PLY, OBJ, OFF, STL or GLB by extension. Atomic.
void write_triangle_mesh(const std::filesystem::path& file, const TriangleMesh& mesh, const PlyWriteOptions& ply = {});

}  // namespace clustersurf
