// Reading and writing clouds and meshes, sampling meshes and scoring reconstructions.

#include "bindings.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/range_scan.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/io/surface_sampling.hpp>
#include <clustersurf/mesh/mesh_check.hpp>
#include <clustersurf/spatial/scan_registration.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <vector>

namespace clustersurf::python {

namespace {

using namespace pybind11::literals;

/// Reads with the GIL released; warnings (dropped points, skipped content) become Python
/// warnings afterwards.
template <class Read>
auto read_with_warnings(ReadOptions options, Read&& read) {
  std::vector<std::string> warnings;
  options.warn = [&warnings](const std::string& message) { warnings.push_back(message); };
  auto result = [&] {
    py::gil_scoped_release release;
    return read(options);
  }();
  const py::object warn = py::module_::import("warnings").attr("warn");
  for (const std::string& message : warnings) warn(message, py::handle(PyExc_UserWarning), 2);
  return result;
}

/// The two sides of compare_surfaces() from its four leading arguments, read in order: each side
/// is one surface object, or vertices followed by their faces (None: a point cloud); None
/// between sides is skipped.
std::array<TriangleMesh, 2> two_surfaces(const std::array<py::handle, 4>& slots, const py::handle& recon_normals,
                                         const py::handle& ref_normals) {
  std::vector<TriangleMesh> sides;
  for (std::size_t i = 0; i < slots.size();) {
    if (slots[i].is_none()) {
      ++i;
      continue;
    }
    if (sides.size() == 2)
      throw OptionError("compare_surfaces takes two surfaces, each a mesh or cloud object or vertices and faces");
    const bool recon = sides.empty();
    const std::string prefix = recon ? "recon_" : "ref_";
    const py::handle normals = recon ? recon_normals : ref_normals;
    if (is_surface_object(slots[i])) {
      sides.push_back(mesh_argument(slots[i], py::none(), normals, py::none(), py::none(), prefix));
      ++i;
    } else {
      const py::handle faces = i + 1 < slots.size() ? slots[i + 1] : py::handle(py::none());
      sides.push_back(mesh_argument(slots[i], faces, normals, py::none(), py::none(), prefix));
      i += 2;
    }
  }
  if (sides.size() < 2) throw OptionError("compare_surfaces needs a reference surface (ref_vertices)");
  return {std::move(sides[0]), std::move(sides[1])};
}

/// Sampling and scanning need triangles: arrays without faces are an error.
TriangleMesh surface_to_sample(const py::handle& vertices, const py::handle& faces) {
  TriangleMesh mesh = mesh_argument(vertices, faces, py::none(), py::none(), py::none(), "");
  if (mesh.triangles.rows() == 0) throw OptionError("faces are required: pass vertices and faces, or a mesh object");
  return mesh;
}

/// Reading points and meshes, writing them.
void bind_files(py::module_& m) {
  m.def(
      "_origin_shift",
      [](const std::array<double, 3>& lo, const std::array<double, 3>& hi) {
        BoundingBox box;
        box.min = Eigen::Vector3d(lo[0], lo[1], lo[2]);
        box.max = Eigen::Vector3d(hi[0], hi[1], hi[2]);
        return vector_array(origin_shift(box));
      },
      py::arg("lo"), py::arg("hi"),
      "The readers' shift of a cloud whose bounding box is [lo, hi] (origin_shift() in C++): the box's center along "
      "each axis where it lies more than 16 diagonals and more than the box's width from zero, else 0.");
  m.def(
      "read_points",
      [](const std::filesystem::path& file, bool drop_non_finite, std::size_t mesh_samples) {
        ReadOptions options;
        options.drop_non_finite = drop_non_finite;
        options.mesh_samples = mesh_samples;
        return cloud_object(
            read_with_warnings(options, [&](const ReadOptions& o) { return read_point_cloud(file, o); }));
      },
      py::arg("path"), py::arg("drop_non_finite") = false, py::arg("mesh_samples") = ReadOptions{}.mesh_samples, R"doc(
Reads a point cloud file into a PointCloud: PLY, XYZ/PTS/TXT/CSV, OBJ, LAS, E57, PTX or PCD.

``path``: the file; its format is the one its first bytes prove (PLY, LAS, E57, PCD), else
its extension's. ``drop_non_finite`` (default False): drop points with NaN/Inf coordinates,
with a warning, instead of failing. ``mesh_samples`` (default 100000): a mesh (PLY or OBJ with
faces) with fewer vertices is read as that many points drawn uniformly on its faces (seeded,
with its faces' normals, and a warning saying so), since its vertices sample it too coarsely
for its thin parts; 0 reads the vertices of every mesh.

The PointCloud has ``positions`` (n, 3) float64, ``normals`` (n, 3) float64 and ``colors``
(n, 3) uint8 (None when the file has none), ``origin`` (3,) float64: a cloud far from zero
(georeferenced scans) is moved next to it, a point is at positions[i] + origin in the file's
coordinates (``world_positions``); ``attributes``: dict of per-point float32 arrays the
scanner file carries (LAS intensity and classification, E57/PTX intensity); and
``scanner_positions`` (k, 3) and ``scanner_of_point`` (n,) uint32 where the file says where
its scans stood (else None). A larger mesh's points are its vertices, with normals from its faces.
Raises InputError (malformed file: the message names the line or byte) or IoError.)doc");

  m.def(
      "read_mesh",
      [](const std::filesystem::path& file) {
        return mesh_object(
            read_with_warnings(ReadOptions{}, [&](const ReadOptions& o) { return read_triangle_mesh(file, o); }));
      },
      py::arg("path"), R"doc(
Reads a triangle mesh file into a Mesh: PLY or OBJ (polygons are fan-triangulated).

``path``: the file. The Mesh has ``vertices`` (n, 3) float64, ``faces`` (m, 3) int32,
per-vertex ``normals`` (float64) and ``colors`` (uint8) or None, and ``origin`` (3,)
float64: the vertices are relative to it, ``world_vertices`` (vertices + origin) are the
file's coordinates. Raises InputError or IoError.)doc");

  m.def(
      "write_points",
      [](const std::filesystem::path& file, const py::handle& positions, const py::handle& normals,
         const py::handle& colors, bool ascii, bool double_precision, const py::handle& origin) {
        const PointCloud cloud = cloud_argument(positions, normals, colors, origin, "positions");
        PlyWriteOptions ply;
        ply.binary = !ascii;
        ply.double_precision = double_precision;
        py::gil_scoped_release release;
        write_point_cloud(file, cloud, ply);
      },
      py::arg("path"), py::arg("positions"), py::arg("normals") = py::none(), py::arg("colors") = py::none(),
      py::arg("ascii") = false, py::arg("double") = false, py::arg("origin") = py::none(), R"doc(
Writes a point cloud as PLY, XYZ or OBJ (by the extension of ``path``), atomically.

``positions``: (n, 3) array, or a PointCloud (or any object with ``.positions`` or
``.vertices``) whose normals, colors and origin are written unless given here. ``normals``:
(n, 3) array or None; ``colors``: (n, 3) uint8 or None. ``ascii`` (default False): ascii PLY
instead of binary; ``double`` (default False): float64 PLY coordinates instead of float32
(always float64 when the origin is not zero). ``origin``: (x, y, z) added to every point in
the file (default: the cloud's origin, else zero). Raises OptionError (bad shapes) or IoError.)doc");
}

/// Writing meshes and checking them.
void bind_mesh_files(py::module_& m) {
  m.def(
      "write_mesh",
      [](const std::filesystem::path& file, const py::handle& vertices, const py::handle& faces,
         const py::handle& normals, const py::handle& colors, bool ascii, const py::handle& origin) {
        const TriangleMesh mesh = mesh_argument(vertices, faces, normals, colors, origin, "");
        if (!is_surface_object(vertices) && faces.is_none())
          throw OptionError("faces are required: pass vertices and faces, or a mesh object");
        PlyWriteOptions ply;
        ply.binary = !ascii;
        py::gil_scoped_release release;
        write_triangle_mesh(file, mesh, ply);
      },
      py::arg("path"), py::arg("vertices"), py::arg("faces") = py::none(), py::arg("normals") = py::none(),
      py::arg("colors") = py::none(), py::arg("ascii") = false, py::arg("origin") = py::none(), R"doc(
Writes a triangle mesh as PLY, OBJ, OFF, STL or GLB (by the extension of ``path``), atomically.

``vertices``: (n, 3) array with ``faces`` (m, 3) integer indices, or a mesh object in place of
both: a clustersurf Mesh (its normals, colors and origin are written unless given here), a
trimesh.Trimesh, an Open3D TriangleMesh, anything with ``.vertices`` and ``.faces`` or
``.triangles``. ``normals``: per-vertex (n, 3) or None; ``colors``: per-vertex (n, 3) uint8
or None. ``ascii`` (default False): ascii PLY instead of binary. ``origin``: (x, y, z) added
to every vertex in the file (default: the mesh's origin, else zero; STL keeps coordinates
relative to it, GLB makes it the node's translation). Raises OptionError (bad shapes or
indices) or IoError.)doc");

  m.def(
      "measure_registration",
      [](const py::handle& points) {
        const PointCloud cloud = cloud_argument(points, py::none(), py::none(), py::none(), "points");
        const ScanRegistration r = [&] {
          py::gil_scoped_release release;
          return measure_registration(cloud, KdTree(cloud.positions));
        }();
        py::dict out;
        out["scans"] = r.scans;
        out["overlaps"] = r.overlaps;
        out["median_offset"] = r.median_offset;
        out["rms_offset"] = r.rms_offset;
        return out;
      },
      py::arg("points"), R"doc(
How far apart the scans of a cloud lie where they overlap, as ``clustersurf reconstruct`` reports
it (``registration``): ``points`` is a PointCloud whose ``scanner_of_point`` says which scan saw
each point (read_points() of an E57, PTX or PLY file with a ``scan`` property, or scan_surface()).
Returns a dict: scans, overlaps (sampled points with enough of their own scan and of another
around them), median_offset and rms_offset (from the plane of a point's own scan to another scan's
points around it, along its normal, in the cloud's units); no overlaps without scan labels.)doc");

  m.def(
      "check_mesh",
      [](const py::handle& vertices, const py::handle& faces) {
        const TriangleMesh mesh = surface_to_sample(vertices, faces);
        const MeshCheck c = [&] {
          py::gil_scoped_release release;
          return check_mesh(mesh);
        }();
        return json_dict(mesh_check_json(c));
      },
      py::arg("vertices"), py::arg("faces") = py::none(), R"doc(
Is a mesh ready to print? As ``clustersurf check``: ``vertices`` (n, 3) and ``faces`` (m, 3),
or a mesh object in place of both. Returns the dict ``clustersurf --json check`` prints: the topology
(vertices, triangles, edges, boundary_edges, non_manifold_edges, inconsistent_edges, components,
small_components, euler_characteristic, area, boundary_length, boundary_per_sqrt_area,
signed_volume, watertight), genus and volume (None when not defined), self_intersections (pairs
of triangles crossing other than where they connect) with the first intersecting_pairs,
consistently_oriented, printable and problems (why not, one phrase each).)doc");
}

/// Benchmark inputs: points sampled on a mesh, virtual scans.
void bind_sampling(py::module_& m) {
  m.def(
      "sample_surface",
      [](const py::handle& vertices, const py::handle& faces, std::int64_t n, double noise, double outliers,
         std::uint64_t seed) {
        if (n < 1) throw OptionError("n must be positive, not " + std::to_string(n));
        const TriangleMesh mesh = surface_to_sample(vertices, faces);
        SurfaceSamplingOptions options;
        options.count = static_cast<std::size_t>(n);
        options.noise = noise;
        options.outliers = outliers;
        options.seed = seed;
        PointCloud cloud = [&] {
          py::gil_scoped_release release;
          return sample_surface(mesh, options);
        }();
        cloud.origin = mesh.origin;
        return cloud_object(std::move(cloud));
      },
      py::arg("vertices"), py::arg("faces") = py::none(), py::arg("n") = SurfaceSamplingOptions{}.count,
      py::arg("noise") = SurfaceSamplingOptions{}.noise, py::arg("outliers") = SurfaceSamplingOptions{}.outliers,
      py::arg("seed") = SurfaceSamplingOptions{}.seed, R"doc(
Draws ``n`` points uniformly by area from a triangle mesh, as ``clustersurf sample`` does.

``vertices`` (n, 3) and ``faces`` (m, 3), or a mesh object in place of both (anything with
``.vertices`` and ``.faces`` or ``.triangles``, as write_mesh() takes). ``n``: points on the
surface; ``noise``: Gaussian sigma as a fraction of the bounding-box diagonal; ``outliers``:
uniform points in the box, as a fraction of n; ``seed``: the same seed gives the same points.
Returns a PointCloud whose normals are the normals of the triangles drawn from, with the
mesh's origin.)doc");

  m.def(
      "scan_surface",
      [](const py::handle& vertices, const py::handle& faces, std::int64_t n, std::int64_t scans, double noise,
         double registration, double flipped_normals, double distance, std::uint64_t seed, double noise_correlation) {
        if (n < 1) throw OptionError("n must be positive, not " + std::to_string(n));
        if (scans < 1) throw OptionError("scans must be positive, not " + std::to_string(scans));
        const TriangleMesh mesh = surface_to_sample(vertices, faces);
        RangeScanOptions options;
        options.count = static_cast<std::size_t>(n);
        options.scans = static_cast<std::size_t>(scans);
        options.noise = noise;
        options.registration = registration;
        options.flipped_normals = flipped_normals;
        options.distance = distance;
        options.noise_correlation = noise_correlation;
        options.seed = seed;
        PointCloud cloud = [&] {
          py::gil_scoped_release release;
          return scan_surface(mesh, options);
        }();
        cloud.origin = mesh.origin;
        return cloud_object(std::move(cloud));
      },
      py::arg("vertices"), py::arg("faces") = py::none(), py::arg("n") = RangeScanOptions{}.count,
      py::arg("scans") = RangeScanOptions{}.scans, py::arg("noise") = RangeScanOptions{}.noise,
      py::arg("registration") = RangeScanOptions{}.registration,
      py::arg("flipped_normals") = RangeScanOptions{}.flipped_normals,
      py::arg("distance") = RangeScanOptions{}.distance, py::arg("seed") = RangeScanOptions{}.seed,
      py::arg("noise_correlation") = RangeScanOptions{}.noise_correlation, R"doc(
Scans a triangle mesh with a virtual range scanner, as ``clustersurf sample --scanner`` does.

``vertices`` and ``faces``, or a mesh object in place of both, as in sample_surface().
About ``n`` points over ``scans`` viewpoints around the mesh (occlusion holes, grazing returns
dropped); ``noise``: Gaussian sigma along the line of sight and ``registration``: each scan's
rigid misregistration, both fractions of the bounding-box diagonal; ``flipped_normals``: the
share of the returns whose normal points away from its scanner; ``distance``: the scanners'
distance to the box center, in diagonals; ``seed``: the same seed gives the same points;
``noise_correlation``: how many grid steps the range noise is correlated over (0: independent).
Returns a PointCloud with normals from each scan's grid, pointing towards its scanner, with
the mesh's origin.)doc");
}

/// Scores of a reconstruction against a reference.
void bind_comparison(py::module_& m) {
  const ComparisonOptions comparison;
  m.def(
      "compare_surfaces",
      [](const py::handle& recon_vertices, const py::handle& recon_faces, const py::handle& ref_vertices,
         const py::handle& ref_faces, const py::handle& recon_normals, const py::handle& ref_normals,
         std::int64_t samples, std::uint64_t seed, std::vector<double> fscore_thresholds) {
        if (samples < 1) throw OptionError("samples must be positive, not " + std::to_string(samples));
        const std::array<TriangleMesh, 2> sides =
            two_surfaces({recon_vertices, recon_faces, ref_vertices, ref_faces}, recon_normals, ref_normals);
        const TriangleMesh& recon = sides[0];
        const TriangleMesh& reference = sides[1];
        ComparisonOptions options;
        options.samples = static_cast<std::size_t>(samples);
        options.seed = seed;
        options.fscore_thresholds = std::move(fscore_thresholds);
        const SurfaceComparison e = [&] {
          py::gil_scoped_release release;
          return compare_surfaces(recon, reference, options);
        }();
        py::list fscores;
        for (const FScore& f : e.fscores)
          fscores.append(py::dict("tau"_a = f.threshold, "precision"_a = f.precision, "recall"_a = f.recall,
                                  "fscore"_a = f.fscore));
        return py::dict(
            "diagonal"_a = e.diagonal, "accuracy"_a = e.accuracy, "completeness"_a = e.completeness,
            "chamfer"_a = e.chamfer, "hausdorff"_a = e.hausdorff, "distance_p95"_a = e.distance_p95,
            "normal_consistency"_a = std::isnan(e.normal_consistency) ? py::object(py::none())
                                                                      : py::object(py::float_(e.normal_consistency)),
            "fscore"_a = fscores,
            "far_share"_a = std::isnan(e.far_share) ? py::object(py::none()) : py::object(py::float_(e.far_share)),
            "volume_iou"_a = std::isnan(e.volume_iou) ? py::object(py::none()) : py::object(py::float_(e.volume_iou)),
            "reference_spacing"_a = e.reference_spacing,
            "samples"_a = py::dict("reconstruction"_a = e.reconstruction_samples, "reference"_a = e.reference_samples),
            "reconstruction_mesh"_a = json_dict(mesh_topology_json(e.reconstruction_topology)),
            "reference_mesh"_a = json_dict(mesh_topology_json(e.reference_topology)));
      },
      py::arg("recon_vertices"), py::arg("recon_faces") = py::none(), py::arg("ref_vertices") = py::none(),
      py::arg("ref_faces") = py::none(), py::arg("recon_normals") = py::none(), py::arg("ref_normals") = py::none(),
      py::arg("samples") = comparison.samples, py::arg("seed") = comparison.seed,
      py::arg("fscore_thresholds") = comparison.fscore_thresholds, R"doc(
Scores a reconstruction against a reference surface, as ``clustersurf eval --json`` does
(``evaluate`` is its old name).

Each side is ``recon_vertices``, ``recon_faces`` (resp. ``ref_vertices``, ``ref_faces``): a
mesh, or with faces None a point cloud; or one object in place of the pair: a clustersurf Mesh
or PointCloud, trimesh.Trimesh, Open3D TriangleMesh, anything with ``.vertices`` (or
``.positions``) and ``.faces`` or ``.triangles`` (none: a cloud). So
``compare_surfaces(mesh, reference)`` and ``compare_surfaces(v, f, reference)`` both work.
Sides with different origins are compared in the reference's frame. ``recon_normals`` /
``ref_normals``: per-point normals of a cloud side (default: a PointCloud's own); ``samples``:
points drawn on each mesh side; ``seed``: the draw's seed; ``fscore_thresholds``: the F-score
thresholds tau. Distances are fractions of the reference's bounding-box diagonal. Returns a
dict with diagonal, accuracy, completeness, chamfer, hausdorff, distance_p95 (the 95th
percentile of both directions' distances), normal_consistency (None
without normals), fscore (list of dicts tau/precision/recall/fscore), far_share (against a
reference cloud: the share of the reconstruction farther than 8 of its median point spacings
from every point; None for a mesh reference), volume_iou (when both sides are meshes without
boundary edges: the intersection over union of the solids they bound; else None),
reference_spacing, samples, reconstruction_mesh
and reference_mesh (topology dicts, with area, boundary_length, boundary_per_sqrt_area and
small_components: components under 0.1 % of the area).)doc");
}

}  // namespace

void bind_io(py::module_& m) {
  bind_files(m);
  bind_mesh_files(m);
  bind_sampling(m);
  bind_comparison(m);
}

}  // namespace clustersurf::python
