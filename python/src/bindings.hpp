#pragma once
// Shared pieces of the Python bindings: numpy <-> Eigen conversions, option parsing helpers,
// progress callbacks that check for Ctrl-C, and the functions that add each group of bindings
// to the module.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/core/progress.hpp>
#include <clustersurf/pipeline/option_schema.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/render/render.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf::python {

namespace py = pybind11;

/// Any array-like of shape (n, 3), converted to float64 rows (float32 and integer arrays are
/// cast). Throws OptionError naming `name` when the shape is wrong.
Points to_points(const py::handle& array, const char* name);
/// Same for (n, 3) uint8 colors (values are cast, not rescaled).
Colors to_colors(const py::handle& array, const char* name);
/// Same for (m, 3) triangle indices; every index must be in [0, vertex_count).
Triangles to_triangles(const py::handle& array, const char* name, Eigen::Index vertex_count);

/// A (n, 3) numpy array owning `m`'s storage (moved, not copied).
py::array_t<double> to_array(Points&& m);
py::array_t<std::uint8_t> to_array(Colors&& m);
py::array_t<std::int32_t> to_array(Triangles&& m);
/// Like to_array, or None for an empty matrix (absent normals or colors).
py::object to_array_or_none(Points&& m);
py::object to_array_or_none(Colors&& m);

/// A clustersurf.PointCloud / clustersurf.Mesh (python/clustersurf/_types.py) taking over the
/// arrays (moved, not copied); absent normals, colors and scanners become None, the origin a
/// (3,) float64 array and the attributes a dict of float32 arrays.
py::object cloud_object(PointCloud&& cloud);
py::object mesh_object(TriangleMesh&& mesh);
/// mesh_object() of the mesh the pipeline made, its `report` the library's surface_mesh_json().
py::object mesh_object(SurfaceMesh&& mesh);

/// (x, y, z) from any 3-element sequence or array (None: zero); OptionError naming `name` else.
Eigen::Vector3d to_vector3(const py::handle& value, const char* name);

/// True when `object` stands for a whole surface or cloud instead of an array: it has
/// `.vertices` or `.positions` (a clustersurf Mesh or PointCloud, trimesh.Trimesh, an Open3D
/// mesh, any object with those attributes).
bool is_surface_object(const py::handle& object);

/// A mesh argument: `object` is either a surface object (its parts come from
/// clustersurf._types._surface_parts(): vertices, faces or triangles, origin, and normals and
/// colors of clustersurf's own types) or the vertices array, with `faces`, `normals`, `colors`
/// and `origin` beside it; any of these that is not None overrides the object's. No faces (None)
/// makes a point set. OptionError messages name prefix + "vertices", prefix + "faces", ...
TriangleMesh mesh_argument(const py::handle& object, const py::handle& faces, const py::handle& normals,
                           const py::handle& colors, const py::handle& origin, const std::string& prefix);

/// A point-cloud argument: an (n, 3) array or a surface object (positions or vertices, and of a
/// clustersurf PointCloud its normals, colors, origin and scanners); `normals`, `colors` and
/// `origin` override the object's when not None. Validates shapes and scanner indices; `name`
/// names the positions in OptionError messages.
PointCloud cloud_argument(const py::handle& object, const py::handle& normals, const py::handle& colors,
                          const py::handle& origin, const std::string& name);

/// A non-negative integer option that must fit `std::uint32_t`; throws OptionError naming it.
std::uint32_t to_uint32(std::int64_t value, const char* name);

/// The progress callback handed to long operations while the GIL is released. It takes the GIL
/// to call the user's `progress(stage, fraction)` (when not None; a false return cancels) and to
/// check for Ctrl-C. A Python exception raised there (KeyboardInterrupt included) cancels the
/// operation and is re-raised by rethrow_if_interrupted() instead of clustersurf.Cancelled.
class ProgressBridge {
 public:
  explicit ProgressBridge(py::object progress);
  ProgressCallback callback();
  /// Re-raises the Python exception that cancelled the operation, if one did.
  void rethrow_if_interrupted();

 private:
  struct State;
  std::shared_ptr<State> state_;
};

/// Runs `work` with the GIL released and a ProgressBridge for `progress`; a Python exception
/// raised in the callback propagates unchanged.
template <class Work>
auto run_released(const py::object& progress, Work&& work) {
  ProgressBridge bridge(progress);
  try {
    py::gil_scoped_release release;
    return work(bridge.callback());
  } catch (const std::exception&) {
    bridge.rethrow_if_interrupted();
    throw;
  }
}

/// What a Python `Tree` holds: an immutable cluster tree shared with its `Node` views, and
/// for a tree built in Python the positions, colors and attributes of its input, so that mesh()
/// trims and colors as `clustersurf reconstruct --mesh` does without being given the points again.
struct TreeRef {
  explicit TreeRef(std::shared_ptr<const ClusterTree> built, std::shared_ptr<const PointCloud> points = nullptr)
      : tree(std::move(built)), input(std::move(points)) {}
  std::shared_ptr<const ClusterTree> tree;
  std::shared_ptr<const PointCloud> input;
};

/// The part of a tree's input cloud that TreeRef keeps: its positions, colors and attributes.
std::shared_ptr<const PointCloud> tree_input(PointCloud cloud);

/// What a Python `Node` holds: one node of a tree, by index; keeps the tree alive.
struct NodeRef {
  std::shared_ptr<const ClusterTree> tree;
  std::int32_t index = 0;
  const ClusterNode& node() const { return tree->nodes[static_cast<std::size_t>(index)]; }
};

/// The node at `index` of `t` (negative counts from the end); raises IndexError.
NodeRef node_at(const TreeRef& t, std::int64_t index);

/// A 3-vector as a numpy array of 3 float64.
py::array_t<double> vector_array(const Eigen::Vector3d& v);

/// A library report (a JSON object) as a dict.
py::dict json_dict(const std::string& json);

/// The options of reconstruct() and of a mesh from keyword arguments named as the option schema's
/// (reconstruct_option_schema()): only those of `stages`; a None value leaves the default.
/// OptionError for an unknown name or a bad value.
ReconstructOptions reconstruct_options(const py::dict& options,
                                       std::vector<OptionStage> stages = {OptionStage::Build, OptionStage::Mesh});
/// The render options from keyword arguments named as render_option_schema()'s; a None value
/// leaves the default. OptionError for an unknown name or a bad value.
RenderOptions render_options(const py::dict& options);
/// The schema's options of `stage` (reconstruct or render) as docstring lines: name, Python
/// default and help.
std::string options_doc(OptionStage stage);

/// Groups of bindings, one per source file.
void bind_io(py::module_& m);
void bind_node(py::module_& m);
void bind_tree(py::module_& m, py::class_<TreeRef>& tree_class);
void bind_render(py::class_<TreeRef>& tree_class);
void bind_tiles(py::module_& m);
void bind_option_schema(py::module_& m);

}  // namespace clustersurf::python
