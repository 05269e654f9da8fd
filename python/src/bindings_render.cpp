// Tree.render(): the ray tracer of `clustersurf render` on one tree, into a numpy picture.

#include "bindings.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/render_option_schema.hpp>

#include <pybind11/stl.h>

namespace clustersurf::python {

namespace {

/// The picture of `t` with the keyword options, as an (height, width, 4) uint8 array.
py::array_t<std::uint8_t> render_picture(const TreeRef& t, const py::object& points,
                                         std::optional<std::int64_t> lod_depth, std::optional<double> lod_error,
                                         const py::object& progress, const py::kwargs& kwargs) {
  const ClusterTree& tree = *t.tree;
  RenderOptions o = render_options(kwargs);
  o.lod =
      level_of_detail(tree, lod_depth ? std::optional(to_uint32(*lod_depth, "lod_depth")) : std::nullopt, lod_error);
  Points reference;
  if (!points.is_none()) {
    reference = cloud_argument(points, py::none(), py::none(), py::none(), "points").positions;
    o.reference_points = &reference;
  }
  auto image = std::make_unique<Image>(run_released(
      progress, [&](const ProgressCallback& callback) { return render_tree(tree, o, nullptr, callback); }));
  const py::ssize_t h = image->height, w = image->width;
  static_assert(sizeof(Rgba8) == 4);
  auto* data = reinterpret_cast<std::uint8_t*>(image->pixels.data());
  py::capsule owner(image.release(), [](void* p) { delete static_cast<Image*>(p); });
  return py::array_t<std::uint8_t>({h, w, py::ssize_t{4}}, data, owner);
}

}  // namespace

void bind_render(py::class_<TreeRef>& tree_class) {
  tree_class.def("render", &render_picture, py::kw_only(), py::arg("points") = py::none(),
                 py::arg("lod_depth") = py::none(), py::arg("lod_error") = py::none(), py::arg("progress") = py::none(),
                 (R"doc(
Ray-traces a picture of the tree, as ``clustersurf render`` does; returns an (height, width, 4)
uint8 RGBA array (the pixels its PNG would hold). ``points``: the input points for
``show="error"``, an (n, 3) array or PointCloud; ``lod_depth``, ``lod_error``: the tree cut to
blend, as in Tree.mesh(); ``progress`` as in reconstruct(). Runs on all cores without the GIL.
The camera's ``eye``, ``target`` and ``up`` are (x, y, z); ``up`` defaults to the tree's up
axis (z for a tree of a LAS, E57 or PTX survey, else y). Keyword options:

)doc" + options_doc(OptionStage::Render))
                     .c_str());
}

}  // namespace clustersurf::python
