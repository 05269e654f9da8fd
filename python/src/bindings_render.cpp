// Tree.render(): the ray tracer of `clustersurf render` on one tree, into a numpy picture.

#include "bindings.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/render.hpp>

#include <pybind11/stl.h>

#include <cstdio>

namespace clustersurf::python {

namespace {

std::optional<Eigen::Vector3d> vector_option(const std::optional<std::vector<double>>& v, const char* name) {
  if (!v) return std::nullopt;
  if (v->size() != 3) throw OptionError(std::string(name) + " takes (x, y, z)");
  return Eigen::Vector3d((*v)[0], (*v)[1], (*v)[2]);
}

}  // namespace

void bind_render(py::class_<TreeRef>& tree_class) {
  tree_class.def(
      "render",
      [](const TreeRef& t, int width, int height, int samples, const std::string& mode, const std::string& show,
         std::optional<std::int64_t> level, std::optional<std::int64_t> highlight, const py::object& points,
         std::optional<double> error_scale, double azimuth, double elevation, std::optional<double> distance,
         double fov, const std::optional<std::vector<double>>& eye, const std::optional<std::vector<double>>& target,
         const std::optional<std::vector<double>>& up, const std::string& background, bool ao,
         std::optional<std::int64_t> lod_depth, std::optional<double> lod_error, double min_weight,
         const py::object& progress) {
        const ClusterTree& tree = *t.tree;
        RenderOptions o;
        o.width = width;
        o.height = height;
        o.samples = samples;
        o.mode = parse_intersect_mode(mode);
        o.show = parse_show_mode(show);
        if (level) o.level = to_uint32(*level, "level");
        if (highlight) {
          if (*highlight < 0 || *highlight >= static_cast<std::int64_t>(tree.nodes.size()))
            throw OptionError("highlight must be a node index in [0, " + std::to_string(tree.nodes.size()) + ")");
          o.highlight = static_cast<std::int32_t>(*highlight);
        }
        o.error_scale = error_scale;
        o.camera.azimuth = azimuth;
        o.camera.elevation = elevation;
        o.camera.distance = distance;
        o.camera.fov = fov;
        o.camera.eye = vector_option(eye, "eye");
        o.camera.target = vector_option(target, "target");
        o.camera.up = vector_option(up, "up");
        o.background = parse_background(background);
        o.ambient_occlusion = ao;
        o.lod = level_of_detail(tree, lod_depth ? std::optional(to_uint32(*lod_depth, "lod_depth")) : std::nullopt,
                                lod_error);
        o.min_weight = min_weight;
        Points reference;
        if (!points.is_none()) {
          reference = cloud_argument(points, py::none(), py::none(), py::none(), "points").positions;
          o.reference_points = &reference;
        }
        if (o.show == ShowMode::Error && o.reference_points == nullptr)
          throw OptionError("show=\"error\" needs the input points (points=...)");
        auto image = std::make_unique<Image>(run_released(
            progress, [&](const ProgressCallback& callback) { return render_tree(tree, o, nullptr, callback); }));
        const py::ssize_t h = image->height, w = image->width;
        static_assert(sizeof(Rgba8) == 4);
        auto* data = reinterpret_cast<std::uint8_t*>(image->pixels.data());
        py::capsule owner(image.release(), [](void* p) { delete static_cast<Image*>(p); });
        return py::array_t<std::uint8_t>({h, w, py::ssize_t{4}}, data, owner);
      },
      py::kw_only(), py::arg("width") = RenderOptions{}.width, py::arg("height") = RenderOptions{}.height,
      py::arg("samples") = RenderOptions{}.samples, py::arg("mode") = to_string(RenderOptions{}.mode),
      py::arg("show") = to_string(RenderOptions{}.show), py::arg("level") = py::none(),
      py::arg("highlight") = py::none(), py::arg("points") = py::none(), py::arg("error_scale") = py::none(),
      py::arg("azimuth") = CameraOptions{}.azimuth, py::arg("elevation") = CameraOptions{}.elevation,
      py::arg("distance") = py::none(), py::arg("fov") = CameraOptions{}.fov, py::arg("eye") = py::none(),
      py::arg("target") = py::none(), py::arg("up") = py::none(), py::arg("background") = "white",
      py::arg("ao") = false, py::arg("lod_depth") = py::none(), py::arg("lod_error") = py::none(),
      py::arg("min_weight") = RenderOptions{}.min_weight, py::arg("progress") = py::none(), R"doc(
Ray-traces a picture of the tree, as ``clustersurf render`` does; returns an (height, width, 4)
uint8 RGBA array (the pixels its PNG would hold).

Options mirror the CLI: ``width``, ``height``, ``samples`` (rays per pixel); ``mode``
"implicit", "hit-blend" or "brute-force"; ``show`` "surface", "clusters", "spheres", "proxies"
or "error" (needs ``points``, an (n, 3) array or PointCloud; ``error_scale``); ``level``
(clusters: color by the ancestor at this depth); ``highlight`` (a node index); the camera
``azimuth``, ``elevation``, ``distance``, ``fov`` or ``eye``/``target``/``up`` as (x, y, z) (``up``
default: the tree's up axis, z for a tree of a LAS, E57 or PTX survey, else y);
``background`` "transparent", "white", "black" or "#rrggbb"; ``ao`` (ambient occlusion);
``lod_depth``, ``lod_error``, ``min_weight``. ``progress`` as in reconstruct(). Runs on all
cores without the GIL.)doc");
}

}  // namespace clustersurf::python
