// Reading and writing clouds and meshes, sampling meshes and scoring reconstructions.

#include "bindings.hpp"

#include <clustersurf/errors.hpp>
#include <clustersurf/surface_comparison.hpp>
#include <clustersurf/point_cloud_io.hpp>
#include <clustersurf/range_scan.hpp>
#include <clustersurf/surface_sampling.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <vector>

namespace clustersurf::python {

namespace {

using namespace pybind11::literals;

/// Reads with the GIL released; warnings (dropped points, skipped content) become Python
/// warnings afterwards.
template <class Read>
auto read_with_warnings(bool drop_non_finite, Read&& read) {
  std::vector<std::string> warnings;
  ReadOptions options;
  options.drop_non_finite = drop_non_finite;
  options.warn = [&warnings](const std::string& message) { warnings.push_back(message); };
  auto result = [&] {
    py::gil_scoped_release release;
    return read(options);
  }();
  const py::object warn = py::module_::import("warnings").attr("warn");
  for (const std::string& message : warnings) warn(message, py::handle(PyExc_UserWarning), 2);
  return result;
}

/// A TriangleMesh from arrays; `faces` None (or empty) makes a point cloud for evaluation.
TriangleMesh mesh_from_arrays(const py::handle& vertices, const py::handle& faces, const py::handle& normals,
                              const py::handle& colors, const std::string& what) {
  TriangleMesh mesh;
  mesh.vertices = to_points(vertices, (what + "vertices").c_str());
  mesh.triangles = faces.is_none() ? Triangles(0, 3) : to_triangles(faces, (what + "faces").c_str(), mesh.vertices.rows());
  if (!normals.is_none()) mesh.normals = to_points(normals, (what + "normals").c_str());
  if (!colors.is_none()) mesh.colors = to_colors(colors, (what + "colors").c_str());
  if (mesh.normals.rows() != 0 && mesh.normals.rows() != mesh.vertices.rows())
    throw OptionError(what + "normals must have one row per vertex");
  if (mesh.colors.rows() != 0 && mesh.colors.rows() != mesh.vertices.rows())
    throw OptionError(what + "colors must have one row per vertex");
  return mesh;
}

PointCloud cloud_from_arrays(const py::handle& positions, const py::handle& normals, const py::handle& colors) {
  PointCloud cloud;
  cloud.positions = to_points(positions, "positions");
  if (!normals.is_none()) cloud.normals = to_points(normals, "normals");
  if (!colors.is_none()) cloud.colors = to_colors(colors, "colors");
  if (cloud.normals.rows() != 0 && cloud.normals.rows() != cloud.size())
    throw OptionError("normals must have one row per point");
  if (cloud.colors.rows() != 0 && cloud.colors.rows() != cloud.size()) throw OptionError("colors must have one row per point");
  return cloud;
}

py::dict topology_dict(const MeshTopology& t) {
  return py::dict("vertices"_a = t.vertices, "faces"_a = t.triangles, "edges"_a = t.edges,
                  "boundary_edges"_a = t.boundary_edges, "non_manifold_edges"_a = t.non_manifold_edges,
                  "inconsistent_edges"_a = t.inconsistent_edges, "euler_characteristic"_a = t.euler_characteristic,
                  "components"_a = t.components, "signed_volume"_a = t.signed_volume, "watertight"_a = is_watertight(t));
}

}  // namespace

void bind_io(py::module_& m) {
  m.def(
      "read_points",
      [](const std::filesystem::path& file, bool drop_non_finite) {
        return cloud_object(read_with_warnings(drop_non_finite, [&](const ReadOptions& o) { return read_point_cloud(file, o); }));
      },
      py::arg("path"), py::arg("drop_non_finite") = false, R"doc(
Reads a point cloud: PLY (ascii or binary), XYZ/PTS/TXT/CSV or OBJ (format by extension).

Returns a PointCloud with ``positions`` (n, 3) float64 and ``normals`` (n, 3) float64 and
``colors`` (n, 3) uint8, each None when the file has none. A mesh's vertices are its points.
With ``drop_non_finite`` points with NaN/Inf coordinates are dropped (with a warning) instead
of failing. Raises InputError (malformed file: the message names the line or byte) or IoError.)doc");

  m.def(
      "read_mesh",
      [](const std::filesystem::path& file) {
        return mesh_object(read_with_warnings(false, [&](const ReadOptions& o) { return read_triangle_mesh(file, o); }));
      },
      py::arg("path"), R"doc(
Reads a triangle mesh from PLY or OBJ (polygons are fan-triangulated).

Returns a Mesh with ``vertices`` (n, 3) float64, ``faces`` (m, 3) int32 and ``normals``
(float64) and ``colors`` (uint8) per vertex, or None. Raises InputError or IoError.)doc");

  m.def(
      "write_points",
      [](const std::filesystem::path& file, const py::handle& positions, const py::handle& normals, const py::handle& colors,
         bool ascii, bool double_precision) {
        const PointCloud cloud = cloud_from_arrays(positions, normals, colors);
        PlyWriteOptions ply;
        ply.binary = !ascii;
        ply.double_precision = double_precision;
        py::gil_scoped_release release;
        write_point_cloud(file, cloud, ply);
      },
      py::arg("path"), py::arg("positions"), py::arg("normals") = py::none(), py::arg("colors") = py::none(),
      py::arg("ascii") = false, py::arg("double") = false, R"doc(
Writes a point cloud as PLY (binary unless ``ascii``; float32 unless ``double``) or XYZ, by
extension, atomically. ``positions`` and ``normals`` are (n, 3) arrays, ``colors`` (n, 3)
uint8. Raises IoError.)doc");

  m.def(
      "write_mesh",
      [](const std::filesystem::path& file, const py::handle& vertices, const py::handle& faces, const py::handle& normals,
         const py::handle& colors, bool ascii) {
        const TriangleMesh mesh = mesh_from_arrays(vertices, faces, normals, colors, "");
        PlyWriteOptions ply;
        ply.binary = !ascii;
        py::gil_scoped_release release;
        write_triangle_mesh(file, mesh, ply);
      },
      py::arg("path"), py::arg("vertices"), py::arg("faces"), py::arg("normals") = py::none(), py::arg("colors") = py::none(),
      py::arg("ascii") = false, R"doc(
Writes a triangle mesh as PLY (binary unless ``ascii``) or OBJ, by extension, atomically.
``vertices`` (n, 3), ``faces`` (m, 3) integer indices, optional per-vertex ``normals`` (n, 3)
and ``colors`` (n, 3) uint8. Raises OptionError (bad shapes or indices) or IoError.)doc");

  m.def(
      "sample_surface",
      [](const py::handle& vertices, const py::handle& faces, std::int64_t n, double noise, double outliers, std::uint64_t seed) {
        if (n < 1) throw OptionError("n must be positive, not " + std::to_string(n));
        const TriangleMesh mesh = mesh_from_arrays(vertices, faces, py::none(), py::none(), "");
        SurfaceSamplingOptions options;
        options.count = static_cast<std::size_t>(n);
        options.noise = noise;
        options.outliers = outliers;
        options.seed = seed;
        PointCloud cloud = [&] {
          py::gil_scoped_release release;
          return sample_surface(mesh, options);
        }();
        return cloud_object(std::move(cloud));
      },
      py::arg("vertices"), py::arg("faces"), py::arg("n") = SurfaceSamplingOptions{}.count,
      py::arg("noise") = SurfaceSamplingOptions{}.noise, py::arg("outliers") = SurfaceSamplingOptions{}.outliers,
      py::arg("seed") = SurfaceSamplingOptions{}.seed, R"doc(
Draws ``n`` points uniformly by area from a triangle mesh, as ``clustersurf sample`` does.

``noise``: Gaussian sigma as a fraction of the bounding-box diagonal; ``outliers``: uniform
points in the box, as a fraction of n. Returns a PointCloud whose normals are the normals of
the triangles drawn from. Deterministic for a seed.)doc");

  m.def(
      "scan_surface",
      [](const py::handle& vertices, const py::handle& faces, std::int64_t n, std::int64_t scans, double noise,
         double registration, double distance, std::uint64_t seed) {
        if (n < 1) throw OptionError("n must be positive, not " + std::to_string(n));
        if (scans < 1) throw OptionError("scans must be positive, not " + std::to_string(scans));
        const TriangleMesh mesh = mesh_from_arrays(vertices, faces, py::none(), py::none(), "");
        RangeScanOptions options;
        options.count = static_cast<std::size_t>(n);
        options.scans = static_cast<std::size_t>(scans);
        options.noise = noise;
        options.registration = registration;
        options.distance = distance;
        options.seed = seed;
        PointCloud cloud = [&] {
          py::gil_scoped_release release;
          return scan_surface(mesh, options);
        }();
        return cloud_object(std::move(cloud));
      },
      py::arg("vertices"), py::arg("faces"), py::arg("n") = RangeScanOptions{}.count,
      py::arg("scans") = RangeScanOptions{}.scans, py::arg("noise") = RangeScanOptions{}.noise,
      py::arg("registration") = RangeScanOptions{}.registration, py::arg("distance") = RangeScanOptions{}.distance,
      py::arg("seed") = RangeScanOptions{}.seed, R"doc(
Scans a triangle mesh with a virtual range scanner, as ``clustersurf sample --scanner`` does.

About ``n`` points over ``scans`` viewpoints around the mesh (occlusion holes, grazing returns
dropped); ``noise``: Gaussian sigma along the line of sight and ``registration``: each scan's
rigid misregistration, both fractions of the bounding-box diagonal; ``distance``: the scanners'
distance to the box center, in diagonals. Returns a PointCloud with normals from each scan's
grid, pointing towards its scanner. Deterministic for a seed.)doc");

  const ComparisonOptions comparison;
  m.def(
      "compare_surfaces",
      [](const py::handle& recon_vertices, const py::handle& recon_faces, const py::handle& ref_vertices,
         const py::handle& ref_faces, const py::handle& recon_normals, const py::handle& ref_normals, std::int64_t samples,
         std::uint64_t seed, std::vector<double> fscore_thresholds) {
        if (samples < 1) throw OptionError("samples must be positive, not " + std::to_string(samples));
        const TriangleMesh recon = mesh_from_arrays(recon_vertices, recon_faces, recon_normals, py::none(), "recon_");
        const TriangleMesh reference = mesh_from_arrays(ref_vertices, ref_faces, ref_normals, py::none(), "ref_");
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
          fscores.append(py::dict("tau"_a = f.threshold, "precision"_a = f.precision, "recall"_a = f.recall, "fscore"_a = f.fscore));
        return py::dict("diagonal"_a = e.diagonal, "accuracy"_a = e.accuracy, "completeness"_a = e.completeness,
                        "chamfer"_a = e.chamfer, "hausdorff"_a = e.hausdorff,
                        "normal_consistency"_a = std::isnan(e.normal_consistency) ? py::object(py::none())
                                                                                    : py::object(py::float_(e.normal_consistency)),
                        "fscore"_a = fscores,
                        "samples"_a = py::dict("reconstruction"_a = e.reconstruction_samples, "reference"_a = e.reference_samples),
                        "reconstruction_mesh"_a = topology_dict(e.reconstruction_topology),
                        "reference_mesh"_a = topology_dict(e.reference_topology));
      },
      py::arg("recon_vertices"), py::arg("recon_faces"), py::arg("ref_vertices"), py::arg("ref_faces"),
      py::arg("recon_normals") = py::none(), py::arg("ref_normals") = py::none(), py::arg("samples") = comparison.samples,
      py::arg("seed") = comparison.seed, py::arg("fscore_thresholds") = comparison.fscore_thresholds, R"doc(
Scores a reconstruction against a reference surface, as ``clustersurf eval --json`` does
(``evaluate`` is its old name).

Each side is a mesh (vertices, faces) or, with faces None, a point cloud. Distances are
fractions of the reference's bounding-box diagonal. Returns a dict with diagonal, accuracy,
completeness, chamfer, hausdorff, normal_consistency (None without normals), fscore (list of
dicts tau/precision/recall/fscore), samples, reconstruction_mesh and reference_mesh.)doc");
}

}  // namespace clustersurf::python
