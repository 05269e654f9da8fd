// The Node class: one node of a Tree, its proxy and spheres, as views that keep the tree alive.

#include "bindings.hpp"

#include <pybind11/stl.h>

#include <variant>

namespace clustersurf::python {

NodeRef node_at(const TreeRef& t, std::int64_t index) {
  const auto n = static_cast<std::int64_t>(t.tree->nodes.size());
  if (index < 0) index += n;
  if (index < 0 || index >= n) throw py::index_error("node index out of range");
  return {t.tree, static_cast<std::int32_t>(index)};
}

py::array_t<double> vector_array(const Eigen::Vector3d& v) {
  py::array_t<double> a(3);
  std::copy_n(v.data(), 3, a.mutable_data());
  return a;
}

namespace {

using namespace pybind11::literals;

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
        } else if constexpr (std::is_same_v<T, CreaseProxy>) {
          put(p.a.point), put(p.a.normal), put(p.b.point), put(p.b.normal);
          c.push_back(p.convex ? 1.0 : 0.0);
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
          return py::dict("type"_a = "poly", "origin"_a = vector_array(p.frame.origin), "axes"_a = axes,
                          "coeffs"_a = coeffs);
        } else if constexpr (std::is_same_v<T, CreaseProxy>) {
          const auto plane = [](const PlaneProxy& q) {
            return py::dict("point"_a = vector_array(q.point), "normal"_a = vector_array(q.normal));
          };
          return py::dict("type"_a = "crease", "a"_a = plane(p.a), "b"_a = plane(p.b), "convex"_a = p.convex);
        } else {
          py::array_t<double> coeffs(10);
          std::copy(p.coeffs.begin(), p.coeffs.end(), coeffs.mutable_data());
          return py::dict("type"_a = "quadric", "center"_a = vector_array(p.center), "scale"_a = p.scale,
                          "coeffs"_a = coeffs);
        }
      },
      proxy.variant());
}

py::object index_or_none(std::int32_t i) { return i < 0 ? py::object(py::none()) : py::object(py::int_(i)); }

}  // namespace

void bind_node(py::module_& m) {
  py::class_<NodeRef>(m, "Node", R"doc(
One node of a Tree (a view: it keeps the tree alive). Nodes are numbered in depth-first
pre-order, root 0; a node's children come after it.)doc")
      .def_property_readonly(
          "index", [](const NodeRef& n) { return n.index; }, "Position in pre-order (root: 0).")
      .def_property_readonly(
          "parent", [](const NodeRef& n) { return index_or_none(n.node().parent); },
          "Index of the parent, None for the root.")
      .def_property_readonly(
          "left", [](const NodeRef& n) { return index_or_none(n.node().left); },
          "Index of the left child, None for a leaf.")
      .def_property_readonly(
          "right", [](const NodeRef& n) { return index_or_none(n.node().right); },
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
      .def_property_readonly(
          "is_leaf", [](const NodeRef& n) { return n.node().is_leaf(); }, "True for a leaf.")
      .def_property_readonly(
          "depth", [](const NodeRef& n) { return n.node().depth; }, "Depth (root: 0).")
      .def_property_readonly(
          "point_count", [](const NodeRef& n) { return n.node().point_count; },
          "Number of input points in the cluster.")
      .def_property_readonly(
          "rms_error", [](const NodeRef& n) { return n.node().rms_error; },
          "RMS of |Q| over the cluster's points (input units).")
      .def_property_readonly(
          "max_error", [](const NodeRef& n) { return n.node().max_error; },
          "Largest |Q| over the cluster's points (input units).")
      .def_property_readonly(
          "proxy_type", [](const NodeRef& n) { return to_string(n.node().proxy.kind()); },
          "\"point\", \"plane\", \"poly\", \"quadric\" or \"crease\".")
      .def_property_readonly(
          "proxy", [](const NodeRef& n) { return proxy_dict(n.node().proxy); },
          R"doc(The proxy's parameters as a dict with "type" and: point: center; plane: point,
normal; poly: origin, axes (3x3, columns e1 e2 e3) and coeffs c0..c5 of w = c0 + c1 u + c2 v + c3 u² +
c4 uv + c5 v² in local coordinates (u, v, w); quadric: center, scale and the 10 coeffs of the
quadric in y = (x - center) / scale; crease: planes a and b (each a dict of point, normal) and
convex (Q = max of the two planes' values when True, min when False).)doc")
      .def_property_readonly(
          "coefficients", [](const NodeRef& n) { return coefficients(n.node().proxy); },
          R"doc(The proxy's numbers, flat, in the order of the .cstree file: point 3, plane 6,
poly 18 (origin, axes column by column, c0..c5), quadric 14 (center, scale, c0..c9), crease 13 (the
two planes' point and normal, then 1 for a convex edge or 0 for a concave one).)doc")
      .def_property_readonly(
          "support",
          [](const NodeRef& n) {
            return py::make_tuple(vector_array(n.node().support.center), n.node().support.radius);
          },
          "(center, radius) of the support sphere: the cluster mean and alpha x the cluster's bbox diagonal.")
      .def_property_readonly(
          "bound",
          [](const NodeRef& n) { return py::make_tuple(vector_array(n.node().bound.center), n.node().bound.radius); },
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

}  // namespace clustersurf::python
