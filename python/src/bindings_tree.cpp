// reconstruct(), load(), and the Tree class: info, f and its gradient, meshing, node access.

#include "bindings.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/surface/closed_surface.hpp>
#include <clustersurf/surface/implicit_surface.hpp>

#include <clustersurf/cluster/tree_file.hpp>
#include <tbb/parallel_for.h>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <limits>

namespace clustersurf::python {

namespace {

using namespace pybind11::literals;

/// The library's report of the tree (tree_info_json(), the CLI's `--json info`) as a dict.
py::dict info_dict(const ClusterTree& tree) { return json_dict(tree_info_json(tree)); }

/// f (or ∇f) at every row of xyz, NaN where undefined or not above min_weight.
py::array_t<double> sample(const ClusterTree& tree, const py::handle& xyz, double min_weight,
                           std::optional<std::int64_t> lod_depth, std::optional<double> lod_error, bool gradient) {
  if (!(min_weight >= 0) || !std::isfinite(min_weight)) throw OptionError("min_weight must be >= 0");
  const Points p = to_points(xyz, "xyz");
  const LevelOfDetail lod =
      level_of_detail(tree, lod_depth ? std::optional(to_uint32(*lod_depth, "lod_depth")) : std::nullopt, lod_error);
  const auto nan = std::numeric_limits<double>::quiet_NaN();
  Points gradients(gradient ? p.rows() : 0, 3);
  py::array_t<double> values(gradient ? 0 : p.rows());
  double* v = values.mutable_data();
  {
    py::gil_scoped_release release;
    const ImplicitSurface surface(tree, lod);
    const std::vector<SurfaceSample> samples = surface.sample_all(p);
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
      const SurfaceSample& s = samples[static_cast<std::size_t>(i)];
      const bool defined = s.defined && s.weight > min_weight;
      if (gradient)
        gradients.row(i) = defined ? Eigen::RowVector3d(s.gradient.transpose()) : Eigen::RowVector3d(nan, nan, nan);
      else
        v[i] = defined ? s.value : nan;
    }
  }
  if (gradient) return to_array(std::move(gradients));
  return values;
}

}  // namespace

std::shared_ptr<const PointCloud> tree_input(PointCloud cloud) {
  auto kept = std::make_shared<PointCloud>();
  kept->positions = std::move(cloud.positions);
  kept->colors = std::move(cloud.colors);
  kept->attributes = std::move(cloud.attributes);
  return kept;
}

namespace {

/// reconstruct(), reconstruct_mesh() and load(): a tree from points or from a file.
void bind_reconstruct(py::module_& m) {
  m.def(
      "reconstruct",
      [](const py::object& points, const py::object& normals, const py::object& progress, const py::kwargs& kwargs) {
        ReconstructOptions o = reconstruct_options(kwargs, {OptionStage::Build});
        o.mesh = false;
        PointCloud cloud = cloud_argument(points, normals, py::none(), py::none(), "points");
        auto tree = run_released(progress, [&](const ProgressCallback& callback) {
          return std::make_shared<const ClusterTree>(reconstruct(cloud, o, callback).tree);
        });
        return TreeRef{std::move(tree), tree_input(std::move(cloud))};
      },
      py::arg("points"), py::arg("normals") = py::none(), py::kw_only(), py::arg("progress") = py::none(),
      (R"doc(
Builds and orients the cluster tree of a point cloud, as ``clustersurf reconstruct`` does
(the library's reconstruct(): the same checks, the same tree).

``points``: (n, 3) array (float32 or float64), or a PointCloud from read_points() (its normals
are used unless ``normals`` is given; the tree is built on its ``positions``, relative to its
``origin``), or any object with ``.positions`` or ``.vertices``. ``normals``: optional (n, 3)
array orienting the surface; without them the orientation propagates between touching clusters.
``progress``: optional callable (stage: str, fraction: float) -> bool; returning False raises
Cancelled. Ctrl-C interrupts the build. The GIL is released while building. The result is
the same tree for any thread count, byte-identical to the CLI's when saved.

The keyword options are the CLI's (the same names with ``_`` for ``-``, the same defaults;
option_schema() lists them), checked by the library (OptionError):
)doc" + options_doc(OptionStage::Build))
          .c_str());

  m.def(
      "reconstruct_mesh",
      [](const py::object& points, const py::object& normals, const py::object& progress, const py::kwargs& kwargs) {
        ReconstructOptions o = reconstruct_options(kwargs);
        o.mesh = true;
        const PointCloud cloud = cloud_argument(points, normals, py::none(), py::none(), "points");
        SurfaceMesh mesh = run_released(progress, [&](const ProgressCallback& callback) {
          return std::move(*reconstruct(cloud, o, callback).mesh);
        });
        return mesh_object(std::move(mesh));
      },
      py::arg("points"), py::arg("normals") = py::none(), py::kw_only(), py::arg("progress") = py::none(), R"doc(
The whole pipeline in one call, as ``clustersurf reconstruct IN --mesh OUT`` does (the library's
reconstruct() with its mesh): the tree built and oriented, its surface meshed, trimmed to the
points, its loose fragments dropped and, when the points have colors, colored from them.
Returns the Mesh, byte for byte the CLI's for the same points and options.

``points`` as in reconstruct(): an (n, 3) array, a PointCloud (its normals and colors used), an
Open3D point cloud, or any object with ``.positions`` or ``.vertices``; ``normals`` overrides
theirs. Keyword options are reconstruct()'s and Tree.mesh()'s (tolerance, min_points, ...,
resolution, voxel_size, trim, min_component_points, close_pinholes, color, watertight,
fill_holes, decimate, decimate_tolerance), with the CLI's defaults. ``progress`` as in
reconstruct(); the GIL is released.)doc");

  m.def(
      "load",
      [](const std::filesystem::path& file) {
        auto tree = [&] {
          py::gil_scoped_release release;
          return std::make_shared<const ClusterTree>(load_tree(file));
        }();
        return TreeRef{std::move(tree)};
      },
      py::arg("path"),
      "Reads the .cstree file at ``path`` (validated and checksummed) into a Tree. Raises IoError or InputError.");
}

/// Saving and reading a Tree, its nodes and its figures.
void bind_tree_structure(py::class_<TreeRef>& tree_class) {
  tree_class
      .def(
          "save",
          [](const TreeRef& t, const std::filesystem::path& file) {
            py::gil_scoped_release release;
            save_tree(file, *t.tree);
          },
          py::arg("path"),
          "Writes the tree as the .cstree file ``path``, atomically; the same tree always gives the same bytes.")
      .def(
          "to_bytes", [](const TreeRef& t) { return py::bytes(serialize_tree(*t.tree)); }, "The .cstree file's bytes.")
      .def_static(
          "from_bytes",
          [](const py::bytes& bytes) {
            const std::string_view view(bytes);
            return TreeRef{std::make_shared<const ClusterTree>(deserialize_tree(view))};
          },
          py::arg("data"),
          "A tree from ``data``, .cstree bytes (as to_bytes() gives). Raises InputError when they are corrupt.")
      .def(py::pickle([](const TreeRef& t) { return py::bytes(serialize_tree(*t.tree)); },
                      [](const py::bytes& bytes) {
                        return TreeRef{std::make_shared<const ClusterTree>(deserialize_tree(std::string_view(bytes)))};
                      }))
      .def(
          "info", [](const TreeRef& t) { return info_dict(*t.tree); }, R"doc(
Figures and parameters of the tree, with the keys of ``clustersurf --json info``: nodes,
leaves, depth, input_points, outliers, has_point_leaves, bbox_min, bbox_max, diagonal, leaf_proxies,
leaf_size, leaf_rms_error, leaves_over_threshold, noise_sigma, error_threshold, parameters.)doc")
      .def(
          "__len__", [](const TreeRef& t) { return t.tree->nodes.size(); }, "Number of nodes.")
      .def("node", &node_at, py::arg("index"), "The node at `index` (pre-order; negative counts from the end).")
      .def("__getitem__", &node_at, py::arg("index"), "tree[index]: the node at ``index``, as node(index).")
      .def_property_readonly(
          "root",
          [](const TreeRef& t) {
            return NodeRef{t.tree, 0};
          },
          "The root node.")
      .def_property_readonly(
          "nodes",
          [](const TreeRef& t) {
            py::list out;
            for (std::size_t i = 0; i < t.tree->nodes.size(); ++i)
              out.append(NodeRef{t.tree, static_cast<std::int32_t>(i)});
            return out;
          },
          "Every node, in pre-order (a list of Node views).")
      .def_property_readonly(
          "leaves",
          [](const TreeRef& t) {
            const std::vector<std::int32_t> leaves = t.tree->leaves();
            py::array_t<std::int32_t> a(static_cast<py::ssize_t>(leaves.size()));
            std::copy(leaves.begin(), leaves.end(), a.mutable_data());
            return a;
          },
          "Indices of the leaves, in pre-order (int32 array).")
      .def_property_readonly(
          "depth", [](const TreeRef& t) { return t.tree->depth(); }, "Largest node depth (root: 0).")
      .def_property_readonly(
          "bbox",
          [](const TreeRef& t) {
            return py::make_tuple(vector_array(t.tree->bbox.min), vector_array(t.tree->bbox.max));
          },
          "(min, max) corners of the input's bounding box, relative to ``origin``.")
      .def_property_readonly(
          "origin", [](const TreeRef& t) { return vector_array(t.tree->origin); },
          "Where the input lay: the tree (nodes, bbox, meshes) is relative to this point of the file's coordinates "
          "(zero unless the input was read far from zero).");
}

/// f, its gradient, inside() and the leaf of each input point.
void bind_tree_queries(py::class_<TreeRef>& tree_class) {
  tree_class
      .def(
          "leaf_of_points",
          [](const TreeRef& t) {
            if (t.tree->point_leaf.empty())
              throw OptionError(
                  "the tree stores no leaf per point (it was built with no_point_leaves / --no-point-leaves)");
            py::array_t<std::int32_t> a(static_cast<py::ssize_t>(t.tree->point_leaf.size()));
            std::copy(t.tree->point_leaf.begin(), t.tree->point_leaf.end(), a.mutable_data());
            return a;
          },
          "The leaf node index of every input point, in input order (int32 array; -1 for an outlier).")
      .def(
          "evaluate",
          [](const TreeRef& t, const py::handle& xyz, double min_weight, std::optional<std::int64_t> lod_depth,
             std::optional<double> lod_error) { return sample(*t.tree, xyz, min_weight, lod_depth, lod_error, false); },
          py::arg("xyz"), py::kw_only(), py::arg("min_weight") = kMinWeight, py::arg("lod_depth") = py::none(),
          py::arg("lod_error") = py::none(), R"doc(
The implicit function f (approximate signed distance, positive outside) at each row of xyz
(n, 3); a float64 array of n values, NaN where f is undefined: no support reaches, or the total
weight is not above ``min_weight`` (0.02: where the mesher and the renderer stop too).
``lod_depth`` / ``lod_error`` blend a coarser cut of the tree, as in mesh(). Runs in parallel
without the GIL.)doc")
      .def(
          "inside",
          [](const TreeRef& t, const py::handle& xyz, std::int64_t resolution) {
            const Points p = to_points(xyz, "xyz");
            ClosingOptions o;
            o.resolution = to_uint32(resolution, "resolution");
            py::array_t<bool> out(p.rows());
            auto r = out.mutable_unchecked<1>();
            {
              py::gil_scoped_release release;
              const ImplicitSurface surface(*t.tree);
              const ClosedSurface closed(surface, o);
              std::vector<std::uint8_t> inside(static_cast<std::size_t>(p.rows()));
              tbb::parallel_for(Eigen::Index{0}, p.rows(), [&](Eigen::Index i) {
                inside[static_cast<std::size_t>(i)] = closed.inside(p.row(i).transpose());
              });
              for (Eigen::Index i = 0; i < p.rows(); ++i) r(i) = inside[static_cast<std::size_t>(i)] != 0;
            }
            return out;
          },
          py::arg("xyz"), py::kw_only(), py::arg("resolution") = ClosingOptions{}.resolution, R"doc(
Whether each row of ``xyz`` (n, 3), in the tree's coordinates, lies inside the closed surface:
f < 0 where the blend defines f, else the harmonic fill that closes the holes (f fading into
it where the blend's weight falls below its confidence floor), the same field
``mesh(watertight=True)`` meshes; everything beyond the fill grid (the bounding box and a few
cells) is outside. ``resolution``: cells of the fill grid along the longest side (default
128). Builds the fill each call (about a second for 10^5 points); a bool array of n.)doc")
      .def(
          "gradient",
          [](const TreeRef& t, const py::handle& xyz, double min_weight, std::optional<std::int64_t> lod_depth,
             std::optional<double> lod_error) { return sample(*t.tree, xyz, min_weight, lod_depth, lod_error, true); },
          py::arg("xyz"), py::kw_only(), py::arg("min_weight") = kMinWeight, py::arg("lod_depth") = py::none(),
          py::arg("lod_error") = py::none(),
          R"doc(
The exact gradient of f at each row of ``xyz`` (n, 3): an (n, 3) float64 array, NaN rows where
f is undefined or the weight is not above ``min_weight``; ``lod_depth`` / ``lod_error`` blend a
coarser cut of the tree, as in evaluate() and mesh().)doc");
}

/// Tree.mesh() and the Tree's repr.
void bind_tree_mesh(py::class_<TreeRef>& tree_class) {
  tree_class
      .def(
          "mesh",
          [](const TreeRef& t, const py::object& points, const py::object& progress, const py::kwargs& kwargs) {
            const SurfaceMeshOptions o = reconstruct_options(kwargs, {OptionStage::Mesh}).meshing;
            PointCloud given;
            if (!points.is_none()) {
              PointCloud cloud = cloud_argument(points, py::none(), py::none(), py::none(), "points");
              given.positions = std::move(cloud.positions);
              given.colors = std::move(cloud.colors);
              given.attributes = std::move(cloud.attributes);
            }
            const PointCloud* input = points.is_none() ? t.input.get() : &given;
            SurfaceMesh mesh = run_released(progress, [&](const ProgressCallback& callback) {
              if (input == nullptr) return mesh_tree(*t.tree, o, nullptr, callback);
              const CloudIndex index(*input);
              return mesh_tree(*t.tree, o, &index, callback);
            });
            return mesh_object(std::move(mesh));
          },
          py::kw_only(), py::arg("points") = py::none(), py::arg("progress") = py::none(),
          (R"doc(
Meshes the surface f = 0, as ``clustersurf mesh`` does (the library's mesh_tree(): same
options, same mesh). Returns a Mesh (vertices (n, 3) float64, faces (m, 3) int32, normals
(n, 3) float64, colors (n, 3) uint8 or None), triangles facing outward. Its vertices are in
the tree's coordinates, those of the positions it was built from; its ``origin`` is the
tree's (a scan read far from zero), so ``world_vertices`` are the file's coordinates.

``points``: the tree's input ((n, 3) array or PointCloud; OptionError when it is not; default:
the input a tree built by reconstruct() keeps, none for a loaded or unpickled tree), which the
trim, the fragment filter, the pinholes and the input and distance colors need. A closed mesh
(``watertight``) marks its filled-in vertices 1 in ``attributes["filled"]``. ``progress`` as in
reconstruct().

The keyword options are ``clustersurf mesh``'s (the same names with ``_`` for ``-``, the same
defaults; option_schema() lists them), checked by the library (OptionError):
)doc" + options_doc(OptionStage::Mesh))
              .c_str())
      .def("__repr__", [](const TreeRef& t) {
        return "<clustersurf.Tree: " + std::to_string(t.tree->nodes.size()) + " nodes, " +
               std::to_string(t.tree->leaves().size()) + " leaves, depth " + std::to_string(t.tree->depth()) + ", " +
               std::to_string(t.tree->input_points) + " points>";
      });
}

}  // namespace

void bind_tree(py::module_& m, py::class_<TreeRef>& tree_class) {
  bind_reconstruct(m);
  bind_tree_structure(tree_class);
  bind_tree_queries(tree_class);
  bind_tree_mesh(tree_class);
}

}  // namespace clustersurf::python
