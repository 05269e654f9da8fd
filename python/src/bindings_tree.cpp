// reconstruct(), load(), and the Tree and Node classes: info, evaluation, meshing, node access.

#include "bindings.hpp"

#include <clustersurf/errors.hpp>
#include <clustersurf/implicit_surface.hpp>
#include <clustersurf/mesh_extraction.hpp>
#include <clustersurf/mesh_trim.hpp>
#include <clustersurf/orientation.hpp>
#include <clustersurf/tree_file.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <limits>
#include <variant>

namespace clustersurf::python {

namespace {

using namespace pybind11::literals;

/// One node of a tree, by index; keeps the tree alive.
struct NodeRef {
  std::shared_ptr<const ClusterTree> tree;
  std::int32_t index = 0;
  const ClusterNode& node() const { return tree->nodes[static_cast<std::size_t>(index)]; }
};

NodeRef node_at(const TreeRef& t, std::int64_t index) {
  const auto n = static_cast<std::int64_t>(t.tree->nodes.size());
  if (index < 0) index += n;
  if (index < 0 || index >= n) throw py::index_error("node index out of range");
  return {t.tree, static_cast<std::int32_t>(index)};
}

ProxyKind parse_proxy(const std::string& s) {
  if (s == "plane") return ProxyKind::Plane;
  if (s == "poly") return ProxyKind::Poly;
  if (s == "quadric") return ProxyKind::Quadric;
  throw OptionError("proxy must be plane, poly or quadric, not \"" + s + "\"");
}

/// The tolerance of `max_error` ("auto", or a fraction of the diagonal as a number or text) on
/// top of noise_factor × the estimated noise (0: the noise is ignored), as the CLI's.
void parse_max_error(const py::handle& value, double noise_factor, BuildOptions& o) {
  if (!(noise_factor >= 0) || !std::isfinite(noise_factor)) throw OptionError("noise_factor must be >= 0");
  o.threshold_mode = noise_factor > 0 ? ThresholdMode::Auto : ThresholdMode::Relative;
  if (noise_factor > 0) o.noise_factor = noise_factor;
  constexpr const char* kWhat = "max_error must be \"auto\" or a non-negative fraction of the diagonal";
  if (py::isinstance<py::str>(value)) {
    const auto text = value.cast<std::string>();
    if (text == "auto") return;
    std::size_t used = 0;
    try {
      o.threshold = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size() || !(o.threshold >= 0)) throw OptionError(std::string(kWhat) + ", not \"" + text + "\"");
  } else {
    try {
      o.threshold = py::cast<double>(value);
    } catch (const py::cast_error&) {
      throw OptionError(kWhat);
    }
    if (!(o.threshold >= 0)) throw OptionError(kWhat);
  }
}

LevelOfDetail make_lod(const ClusterTree& tree, std::optional<std::int64_t> lod_depth, std::optional<double> lod_error) {
  LevelOfDetail lod;
  if (lod_depth) lod.max_depth = to_uint32(*lod_depth, "lod_depth");
  if (lod_error) {
    if (!(*lod_error >= 0)) throw OptionError("lod_error must be a non-negative fraction of the diagonal");
    lod.max_error = *lod_error * tree.bbox.diagonal();
  }
  return lod;
}

py::dict percentiles(const std::array<double, 5>& a) {
  return py::dict("min"_a = a[0], "p25"_a = a[1], "median"_a = a[2], "p75"_a = a[3], "max"_a = a[4]);
}

/// The figures of `clustersurf --json info`, same keys.
py::dict info_dict(const ClusterTree& tree) {
  const TreeSummary s = summarize(tree);
  const TreeParameters& p = tree.parameters;
  py::dict hist;
  for (int k = 0; k < 4; ++k) hist[to_string(static_cast<ProxyKind>(k))] = s.proxy_histogram[static_cast<std::size_t>(k)];
  const auto vec = [](const Eigen::Vector3d& v) { return py::make_tuple(v.x(), v.y(), v.z()); };
  py::dict parameters("proxy"_a = to_string(p.proxy), "splitter"_a = to_string(p.splitter),
                      "error_metric"_a = to_string(p.metric), "threshold_mode"_a = to_string(p.threshold_mode),
                      "threshold"_a = p.threshold, "noise_factor"_a = p.noise_factor, "min_points"_a = p.min_points,
                      "max_depth"_a = p.max_depth, "alpha"_a = p.alpha, "kstep"_a = p.kstep,
                      "lloyd_restarts"_a = p.lloyd_restarts, "proxy_lloyd_iterations"_a = p.proxy_lloyd_iterations,
                      "support_factor"_a = p.support_factor, "seed"_a = p.seed);
  return py::dict("nodes"_a = s.nodes, "leaves"_a = s.leaves, "depth"_a = s.depth, "input_points"_a = tree.input_points, "outliers"_a = tree.outliers(),
                  "has_point_leaves"_a = !tree.point_leaf.empty(), "bbox_min"_a = vec(tree.bbox.min),
                  "bbox_max"_a = vec(tree.bbox.max), "diagonal"_a = tree.bbox.diagonal(), "leaf_proxies"_a = hist,
                  "leaf_size"_a = percentiles(s.leaf_size_percentiles),
                  "leaf_rms_error"_a = percentiles(s.leaf_rms_percentiles),
                  "leaves_over_threshold"_a = s.leaves_over_threshold, "noise_sigma"_a = p.noise_sigma,
                  "error_threshold"_a = p.error_threshold, "parameters"_a = parameters);
}

py::array_t<double> vector_array(const Eigen::Vector3d& v) {
  py::array_t<double> a(3);
  std::copy_n(v.data(), 3, a.mutable_data());
  return a;
}

/// The proxy's coefficients in the order of the tree file (docs/file-format.md).
py::array_t<double> coefficients(const Proxy& proxy) {
  std::vector<double> c;
  const auto put = [&c](const auto& values) { c.insert(c.end(), values.begin(), values.end()); };
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, PointProxy>) {
          put(p.center);
        } else if constexpr (std::is_same_v<T, PlaneProxy>) {
          put(p.point);
          put(p.normal);
        } else if constexpr (std::is_same_v<T, PolyProxy>) {
          put(p.frame.origin);
          c.insert(c.end(), p.frame.axes.data(), p.frame.axes.data() + 9);  // column-major: e1, e2, e3
          put(p.coeffs);
        } else {
          put(p.center);
          c.push_back(p.scale);
          put(p.coeffs);
        }
      },
      proxy.variant());
  py::array_t<double> a(static_cast<py::ssize_t>(c.size()));
  std::copy(c.begin(), c.end(), a.mutable_data());
  return a;
}

/// The proxy's parameters by name.
py::dict proxy_dict(const Proxy& proxy) {
  return std::visit(
      [](const auto& p) -> py::dict {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, PointProxy>) {
          return py::dict("type"_a = "point", "center"_a = vector_array(p.center));
        } else if constexpr (std::is_same_v<T, PlaneProxy>) {
          return py::dict("type"_a = "plane", "point"_a = vector_array(p.point), "normal"_a = vector_array(p.normal));
        } else if constexpr (std::is_same_v<T, PolyProxy>) {
          py::array_t<double> axes({3, 3});
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) axes.mutable_at(r, c) = p.frame.axes(r, c);
          py::array_t<double> coeffs(6);
          std::copy(p.coeffs.begin(), p.coeffs.end(), coeffs.mutable_data());
          return py::dict("type"_a = "poly", "origin"_a = vector_array(p.frame.origin), "axes"_a = axes, "coeffs"_a = coeffs);
        } else {
          py::array_t<double> coeffs(10);
          std::copy(p.coeffs.begin(), p.coeffs.end(), coeffs.mutable_data());
          return py::dict("type"_a = "quadric", "center"_a = vector_array(p.center), "scale"_a = p.scale, "coeffs"_a = coeffs);
        }
      },
      proxy.variant());
}

py::object index_or_none(std::int32_t i) { return i < 0 ? py::object(py::none()) : py::object(py::int_(i)); }

void bind_node(py::module_& m) {
  py::class_<NodeRef>(m, "Node", R"doc(
One node of a Tree (a view: it keeps the tree alive). Nodes are numbered in depth-first
pre-order, root 0; a node's children come after it.)doc")
      .def_property_readonly("index", [](const NodeRef& n) { return n.index; }, "Position in pre-order (root: 0).")
      .def_property_readonly("parent", [](const NodeRef& n) { return index_or_none(n.node().parent); },
                             "Index of the parent, None for the root.")
      .def_property_readonly("left", [](const NodeRef& n) { return index_or_none(n.node().left); },
                             "Index of the left child, None for a leaf.")
      .def_property_readonly("right", [](const NodeRef& n) { return index_or_none(n.node().right); },
                             "Index of the right child, None for a leaf.")
      .def_property_readonly(
          "children",
          [](const NodeRef& n) {
            py::list out;
            if (!n.node().is_leaf())
              for (std::int32_t c : {n.node().left, n.node().right}) out.append(NodeRef{n.tree, c});
            return out;
          },
          "The two child nodes, or an empty list for a leaf.")
      .def_property_readonly("is_leaf", [](const NodeRef& n) { return n.node().is_leaf(); }, "True for a leaf.")
      .def_property_readonly("depth", [](const NodeRef& n) { return n.node().depth; }, "Depth (root: 0).")
      .def_property_readonly("point_count", [](const NodeRef& n) { return n.node().point_count; },
                             "Number of input points in the cluster.")
      .def_property_readonly("rms_error", [](const NodeRef& n) { return n.node().rms_error; },
                             "RMS of |Q| over the cluster's points (input units).")
      .def_property_readonly("max_error", [](const NodeRef& n) { return n.node().max_error; },
                             "Largest |Q| over the cluster's points (input units).")
      .def_property_readonly("proxy_type", [](const NodeRef& n) { return to_string(n.node().proxy.kind()); },
                             "\"point\", \"plane\", \"poly\" or \"quadric\".")
      .def_property_readonly("proxy", [](const NodeRef& n) { return proxy_dict(n.node().proxy); }, R"doc(
The proxy's parameters as a dict with "type" and: point: center; plane: point, normal; poly:
origin, axes (3x3, columns e1 e2 e3) and coeffs c0..c5 of w = c0 + c1 u + c2 v + c3 u² +
c4 uv + c5 v² in local coordinates (u, v, w); quadric: center, scale and the 10 coeffs of the
quadric in y = (x - center) / scale.)doc")
      .def_property_readonly("coefficients", [](const NodeRef& n) { return coefficients(n.node().proxy); }, R"doc(
The proxy's numbers, flat, in the order of the .cstree file: point 3, plane 6, poly 18
(origin, axes column by column, c0..c5), quadric 14 (center, scale, c0..c9).)doc")
      .def_property_readonly(
          "support",
          [](const NodeRef& n) { return py::make_tuple(vector_array(n.node().support.center), n.node().support.radius); },
          "(center, radius) of the support sphere: the cluster mean and alpha x the cluster's bbox diagonal.")
      .def_property_readonly(
          "bound", [](const NodeRef& n) { return py::make_tuple(vector_array(n.node().bound.center), n.node().bound.radius); },
          "(center, radius) of a sphere enclosing the supports of the node and its whole subtree.")
      .def(
          "proxy_value",
          [](const NodeRef& n, const py::handle& xyz) {
            const Points p = to_points(xyz, "xyz");
            py::array_t<double> out(p.rows());
            auto* o = out.mutable_data();
            for (Eigen::Index i = 0; i < p.rows(); ++i) o[i] = n.node().proxy.value(p.row(i).transpose());
            return out;
          },
          py::arg("xyz"), "The proxy's approximate signed distance Q at each row of xyz (n, 3).")
      .def("__repr__", [](const NodeRef& n) {
        return "<clustersurf.Node " + std::to_string(n.index) + ": depth " + std::to_string(n.node().depth) + ", " +
               std::to_string(n.node().point_count) + " points, " + to_string(n.node().proxy.kind()) +
               (n.node().is_leaf() ? ", leaf>" : ">");
      });
}

/// f (or ∇f) at every row of xyz, NaN where undefined or not above min_weight.
py::array_t<double> sample(const ClusterTree& tree, const py::handle& xyz, double min_weight, std::optional<std::int64_t> lod_depth,
                           std::optional<double> lod_error, bool gradient) {
  if (!(min_weight >= 0) || !std::isfinite(min_weight)) throw OptionError("min_weight must be >= 0");
  const Points p = to_points(xyz, "xyz");
  const LevelOfDetail lod = make_lod(tree, lod_depth, lod_error);
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
      if (gradient) gradients.row(i) = defined ? Eigen::RowVector3d(s.gradient.transpose()) : Eigen::RowVector3d(nan, nan, nan);
      else v[i] = defined ? s.value : nan;
    }
  }
  if (gradient) return to_array(std::move(gradients));
  return values;
}

}  // namespace

void bind_tree(py::module_& m, py::class_<TreeRef>& tree_class) {
  bind_node(m);

  m.def(
      "reconstruct",
      [](const py::object& points, const py::object& normals, const std::string& proxy, const std::string& splitter,
         const py::object& max_error, std::optional<double> absolute_error, const std::string& error, const py::object& min_points,
         std::int64_t max_depth, double alpha, std::int64_t kstep, std::int64_t lloyd_restarts, std::int64_t proxy_lloyd,
         double noise_factor, double support_factor, std::uint64_t seed, bool ignore_normals, bool no_point_leaves, bool keep_outliers, const py::object& progress) {
        BuildOptions o;
        o.proxy = parse_proxy(proxy);
        if (splitter == "split-plane") o.splitter = SplitterKind::SplitPlane;
        else if (splitter == "lloyd") o.splitter = SplitterKind::Lloyd;
        else throw OptionError("splitter must be split-plane or lloyd, not \"" + splitter + "\"");
        if (error == "rms") o.metric = ErrorMetric::Rms;
        else if (error == "max") o.metric = ErrorMetric::Max;
        else throw OptionError("error must be rms or max, not \"" + error + "\"");
        if (absolute_error) {
          if (!(*absolute_error >= 0)) throw OptionError("absolute_error must be >= 0");
          o.threshold_mode = ThresholdMode::Absolute;
          o.threshold = *absolute_error;
        } else {
          parse_max_error(max_error, noise_factor, o);
        }
        if (!py::isinstance<py::str>(min_points) || min_points.cast<std::string>() != "auto") {
          if (!py::isinstance<py::int_>(min_points)) throw OptionError("min_points must be \"auto\" or a whole number >= 1");
          o.min_points = to_uint32(min_points.cast<std::int64_t>(), "min_points");
          if (o.min_points < 1) throw OptionError("min_points must be \"auto\" or at least 1");
        }
        o.max_depth = to_uint32(max_depth, "max_depth");
        o.alpha = alpha;
        o.kstep = to_uint32(kstep, "kstep");
        o.lloyd_restarts = to_uint32(lloyd_restarts, "lloyd_restarts");
        if (o.lloyd_restarts < 1) throw OptionError("lloyd_restarts must be at least 1");
        o.proxy_lloyd_iterations = to_uint32(proxy_lloyd, "proxy_lloyd");
        o.support_factor = support_factor;
        o.seed = seed;
        o.keep_point_leaves = !no_point_leaves;
        o.remove_outliers = !keep_outliers;

        PointCloud cloud;
        py::object given_normals = normals;
        if (py::hasattr(points, "positions")) {  // a PointCloud from read_points()
          cloud.positions = to_points(points.attr("positions"), "points");
          if (given_normals.is_none()) given_normals = points.attr("normals");
        } else {
          cloud.positions = to_points(points, "points");
        }
        if (!given_normals.is_none()) {
          cloud.normals = to_points(given_normals, "normals");
          if (cloud.normals.rows() != cloud.positions.rows()) throw OptionError("normals must have one row per point");
        }
        auto tree = std::make_shared<ClusterTree>(run_released(progress, [&](ProgressCallback callback) {
          o.progress = std::move(callback);
          o.use_normals = !ignore_normals;
          ClusterTree t = build_cluster_tree(cloud, o);
          o.progress = {};
          if (ignore_normals) cloud.normals.resize(0, 3);
          orient_tree(t, cloud);
          return t;
        }));
        return TreeRef{std::move(tree)};
      },
      py::arg("points"), py::arg("normals") = py::none(), py::kw_only(), py::arg("proxy") = "poly",
      py::arg("splitter") = "split-plane", py::arg("max_error") = "auto", py::arg("absolute_error") = py::none(),
      py::arg("error") = "rms", py::arg("min_points") = "auto", py::arg("max_depth") = 200, py::arg("alpha") = 0.75,
      py::arg("kstep") = 0, py::arg("lloyd_restarts") = 4, py::arg("proxy_lloyd") = 0, py::arg("noise_factor") = 1.0,
      py::arg("support_factor") = 2.0,
      py::arg("seed") = 1, py::arg("ignore_normals") = false, py::arg("no_point_leaves") = false,
      py::arg("keep_outliers") = false, py::arg("progress") = py::none(), R"doc(
Builds and orients the cluster tree of a point cloud, as ``clustersurf reconstruct`` does.

``points``: (n, 3) array (float32 or float64), or a PointCloud from read_points() (its normals
are used unless ``normals`` is given). ``normals``: optional (n, 3) array orienting the surface;
without them the orientation propagates between touching clusters.

Options mirror the CLI's (same names with ``_`` for ``-``, same defaults): ``proxy`` "plane",
"poly" or "quadric"; ``splitter`` "split-plane" or "lloyd"; ``max_error`` the tolerance a leaf
may keep beyond the estimated noise, a fraction of the bounding-box diagonal or "auto" (0.00005);
``noise_factor`` (the noise counted; 0 ignores it); ``absolute_error`` in input units (overrides
max_error); ``error`` "rms" or "max"; ``min_points`` ("auto": from the noise and the tolerance,
15 to 20); ``max_depth``; ``alpha`` (support radius =
alpha x cluster bbox diagonal); ``kstep``; ``lloyd_restarts``; ``proxy_lloyd``;
``support_factor``; ``seed``; ``ignore_normals``; ``no_point_leaves``; ``keep_outliers`` (isolated points
are left out of every cluster unless set; their ``point_leaf`` is -1).

``progress``: optional callable (stage: str, fraction: float) -> bool; returning False raises
Cancelled. Ctrl-C interrupts the build. The GIL is released while building. The result is
the same tree for any thread count, byte-identical to the CLI's when saved.)doc");

  m.def(
      "load",
      [](const std::filesystem::path& file) {
        auto tree = [&] {
          py::gil_scoped_release release;
          return std::make_shared<const ClusterTree>(load_tree(file));
        }();
        return TreeRef{std::move(tree)};
      },
      py::arg("path"), "Reads a .cstree file (validated and checksummed). Raises IoError or InputError.");

  tree_class
      .def(
          "save",
          [](const TreeRef& t, const std::filesystem::path& file) {
            py::gil_scoped_release release;
            save_tree(file, *t.tree);
          },
          py::arg("path"), "Writes the tree as a .cstree file, atomically; the same tree always gives the same bytes.")
      .def(
          "to_bytes", [](const TreeRef& t) { return py::bytes(serialize_tree(*t.tree)); },
          "The .cstree file's bytes.")
      .def_static(
          "from_bytes",
          [](const py::bytes& bytes) {
            const std::string_view view(bytes);
            return TreeRef{std::make_shared<const ClusterTree>(deserialize_tree(view))};
          },
          py::arg("data"), "A tree from .cstree bytes (as to_bytes() gives). Raises InputError when they are corrupt.")
      .def(py::pickle([](const TreeRef& t) { return py::bytes(serialize_tree(*t.tree)); },
                      [](const py::bytes& bytes) { return TreeRef{std::make_shared<const ClusterTree>(deserialize_tree(std::string_view(bytes)))}; }))
      .def("info", [](const TreeRef& t) { return info_dict(*t.tree); }, R"doc(
Figures and parameters of the tree, with the keys of ``clustersurf --json info``: nodes,
leaves, depth, input_points, outliers, has_point_leaves, bbox_min, bbox_max, diagonal, leaf_proxies,
leaf_size, leaf_rms_error, leaves_over_threshold, noise_sigma, error_threshold, parameters.)doc")
      .def("__len__", [](const TreeRef& t) { return t.tree->nodes.size(); }, "Number of nodes.")
      .def("node", &node_at, py::arg("index"), "The node at `index` (pre-order; negative counts from the end).")
      .def("__getitem__", &node_at, py::arg("index"))
      .def_property_readonly("root", [](const TreeRef& t) { return NodeRef{t.tree, 0}; }, "The root node.")
      .def_property_readonly(
          "nodes",
          [](const TreeRef& t) {
            py::list out;
            for (std::size_t i = 0; i < t.tree->nodes.size(); ++i) out.append(NodeRef{t.tree, static_cast<std::int32_t>(i)});
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
      .def_property_readonly("depth", [](const TreeRef& t) { return t.tree->depth(); }, "Largest node depth (root: 0).")
      .def_property_readonly(
          "bbox", [](const TreeRef& t) { return py::make_tuple(vector_array(t.tree->bbox.min), vector_array(t.tree->bbox.max)); },
          "(min, max) corners of the input's bounding box.")
      .def(
          "leaf_of_points",
          [](const TreeRef& t) {
            if (t.tree->point_leaf.empty())
              throw OptionError("the tree stores no leaf per point (it was built with no_point_leaves / --no-point-leaves)");
            py::array_t<std::int32_t> a(static_cast<py::ssize_t>(t.tree->point_leaf.size()));
            std::copy(t.tree->point_leaf.begin(), t.tree->point_leaf.end(), a.mutable_data());
            return a;
          },
          "The leaf node index of every input point, in input order (int32 array; -1 for an outlier).")
      .def(
          "evaluate",
          [](const TreeRef& t, const py::handle& xyz, double min_weight, std::optional<std::int64_t> lod_depth,
             std::optional<double> lod_error) { return sample(*t.tree, xyz, min_weight, lod_depth, lod_error, false); },
          py::arg("xyz"), py::kw_only(), py::arg("min_weight") = 0.1, py::arg("lod_depth") = py::none(),
          py::arg("lod_error") = py::none(), R"doc(
The implicit function f (approximate signed distance, positive outside) at each row of xyz
(n, 3); a float64 array of n values, NaN where f is undefined: no support reaches, or the total
weight is not above ``min_weight`` (0.1, a stricter floor than the mesher's 0.02). ``lod_depth`` / ``lod_error`` blend a
coarser cut of the tree, as in mesh(). Runs in parallel without the GIL.)doc")
      .def(
          "gradient",
          [](const TreeRef& t, const py::handle& xyz, double min_weight, std::optional<std::int64_t> lod_depth,
             std::optional<double> lod_error) { return sample(*t.tree, xyz, min_weight, lod_depth, lod_error, true); },
          py::arg("xyz"), py::kw_only(), py::arg("min_weight") = 0.1, py::arg("lod_depth") = py::none(),
          py::arg("lod_error") = py::none(),
          "The exact gradient of f at each row of xyz: an (n, 3) array, NaN rows where f is undefined (see evaluate).")
      .def(
          "mesh",
          [](const TreeRef& t, const std::optional<std::variant<std::int64_t, std::string>>& resolution, std::optional<double> voxel_size,
             std::optional<std::int64_t> lod_depth, std::optional<double> lod_error, const py::object& points, double trim,
             std::size_t min_component_points, bool close_pinholes, const py::object& progress) {
            const auto* cells = resolution ? std::get_if<std::int64_t>(&*resolution) : nullptr;
            if (resolution && cells == nullptr && std::get<std::string>(*resolution) != "auto")
              throw OptionError("resolution must be a number of cells or \"auto\", not \"" + std::get<std::string>(*resolution) + "\"");
            if (cells != nullptr && (*cells < 2 || *cells > 100000)) throw OptionError("resolution must be in [2, 100000]");
            std::optional<PointCloud> input;
            if (!points.is_none()) {
              input.emplace();
              input->positions =
                  to_points(py::hasattr(points, "positions") ? py::object(points.attr("positions")) : points, "points");
            }
            if (voxel_size && !(*voxel_size > 0)) throw OptionError("voxel_size must be positive");
            // The default: auto where the points are given, else MeshOptions' cell count.
            const bool automatic = resolution ? cells == nullptr : input.has_value();
            if (automatic && !voxel_size) {
              if (!input) throw OptionError("resolution=\"auto\" needs the input points (points=...)");
              voxel_size = cell_size_for_points(*input);
            }
            const LevelOfDetail lod = make_lod(*t.tree, lod_depth, lod_error);
            TriangleMesh mesh = run_released(progress, [&](ProgressCallback callback) {
              const ImplicitSurface surface(*t.tree, lod);
              MeshOptions options;
              if (cells != nullptr) options.resolution = static_cast<std::uint32_t>(*cells);
              options.voxel_size = voxel_size;
              options.progress = std::move(callback);
              TriangleMesh m = extract_mesh(surface, options);
              if (!input) return m;
              TrimOptions trimming;
              trimming.spread_factor = trim;
              trimming.min_component_points = min_component_points;
              trimming.close_pinholes = close_pinholes;
              return trim_to_points(m, clustered_points(*t.tree, input->positions), trimming);
            });
            return py::make_tuple(to_array(std::move(mesh.vertices)), to_array(std::move(mesh.triangles)),
                                  to_array(std::move(mesh.normals)));
          },
          py::kw_only(), py::arg("resolution") = py::none(), py::arg("voxel_size") = py::none(), py::arg("lod_depth") = py::none(),
          py::arg("lod_error") = py::none(), py::arg("points") = py::none(), py::arg("trim") = TrimOptions{}.spread_factor,
          py::arg("min_component_points") = TrimOptions{}.min_component_points,
          py::arg("close_pinholes") = TrimOptions{}.close_pinholes, py::arg("progress") = py::none(), R"doc(
Meshes the surface f = 0, as ``clustersurf mesh`` does (same options, same mesh).

``resolution``: grid cells along the longest bbox side, or ``"auto"``: cells two median point
spacings of ``points`` wide (the default when ``points`` are given, else 256 cells); ``voxel_size`` (input units) overrides it; ``lod_depth``: blend
the cut at this depth instead of the leaves; ``lod_error``: blend the
shallowest nodes whose error is at most this fraction of the diagonal; ``points``: the tree's
input ((n, 3) array or PointCloud), to drop the triangles farther from it than ``trim`` × the
local spread (0: keep all) and the loose fragments on which fewer than ``min_component_points``
input points lie nearest (0: keep all), and to close the pinholes the points cover
(``close_pinholes``), as ``clustersurf reconstruct --mesh`` does. ``progress`` as in
reconstruct(). Returns (vertices (n, 3) float64, faces (m, 3) int32, normals (n, 3) float64),
triangles facing outward.)doc")
      .def("__repr__", [](const TreeRef& t) {
        return "<clustersurf.Tree: " + std::to_string(t.tree->nodes.size()) + " nodes, " +
               std::to_string(t.tree->leaves().size()) + " leaves, depth " + std::to_string(t.tree->depth()) + ", " +
               std::to_string(t.tree->input_points) + " points>";
      });
}

}  // namespace clustersurf::python
