// numpy <-> Eigen conversions, integer options and the progress bridge of the bindings.

#include "bindings.hpp"

#include <clustersurf/core/errors.hpp>

#include <limits>
#include <mutex>

namespace clustersurf::python {

namespace {

template <class Scalar>
using RowArray = py::array_t<Scalar, py::array::c_style | py::array::forcecast>;

template <class Scalar>
RowArray<Scalar> rows_of_three(const py::handle& object, const char* name) {
  auto a = RowArray<Scalar>::ensure(object);
  if (!a) throw OptionError(std::string(name) + " must be an array of shape (n, 3)");
  if (a.ndim() == 1 && a.shape(0) == 0) return RowArray<Scalar>(std::vector<py::ssize_t>{0, 3});
  if (a.ndim() != 2 || a.shape(1) != 3) {
    std::string shape;
    for (py::ssize_t d = 0; d < a.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(a.shape(d));
    if (a.ndim() == 1) shape += ",";
    throw OptionError(std::string(name) + " must be an array of shape (n, 3), not (" + shape + ")");
  }
  return a;
}

template <class Matrix>
Matrix copy_rows(const py::handle& object, const char* name) {
  using Scalar = typename Matrix::Scalar;
  const auto a = rows_of_three<Scalar>(object, name);
  Matrix m(a.shape(0), 3);
  if (a.shape(0) > 0) std::copy_n(a.data(), a.size(), m.data());
  return m;
}

template <class Matrix>
py::array_t<typename Matrix::Scalar> owning_array(Matrix&& m) {
  using Scalar = typename Matrix::Scalar;
  auto* heap = new Matrix(std::move(m));
  py::capsule owner(heap, [](void* p) { delete static_cast<Matrix*>(p); });
  return py::array_t<Scalar>({static_cast<py::ssize_t>(heap->rows()), py::ssize_t{3}}, heap->data(), owner);
}

}  // namespace

Points to_points(const py::handle& array, const char* name) {
  Points p = copy_rows<Points>(array, name);
  if (!p.allFinite()) throw OptionError(std::string(name) + " must be finite (no NaN or infinity)");
  return p;
}

Colors to_colors(const py::handle& array, const char* name) { return copy_rows<Colors>(array, name); }

Triangles to_triangles(const py::handle& array, const char* name, Eigen::Index vertex_count) {
  Triangles t = copy_rows<Triangles>(array, name);
  if (t.size() > 0 && (t.minCoeff() < 0 || t.maxCoeff() >= vertex_count))
    throw OptionError(std::string(name) + " has a vertex index outside [0, " + std::to_string(vertex_count) + ")");
  return t;
}

py::array_t<double> to_array(Points&& m) { return owning_array(std::move(m)); }
py::array_t<std::uint8_t> to_array(Colors&& m) { return owning_array(std::move(m)); }
py::array_t<std::int32_t> to_array(Triangles&& m) { return owning_array(std::move(m)); }

py::object to_array_or_none(Points&& m) {
  if (m.rows() == 0) return py::none();
  return to_array(std::move(m));
}

py::object to_array_or_none(Colors&& m) {
  if (m.rows() == 0) return py::none();
  return to_array(std::move(m));
}

std::uint32_t to_uint32(std::int64_t value, const char* name) {
  if (value < 0 || value > std::numeric_limits<std::uint32_t>::max())
    throw OptionError(std::string(name) + " must be in [0, 4294967295], not " + std::to_string(value));
  return static_cast<std::uint32_t>(value);
}

struct ProgressBridge::State {
  py::object progress;  // None or a callable; only touched with the GIL held
  std::mutex mutex;
  std::optional<py::error_already_set> error;
};

ProgressBridge::ProgressBridge(py::object progress) : state_(std::make_shared<State>()) {
  state_->progress = std::move(progress);
}

ProgressCallback ProgressBridge::callback() {
  return [state = state_](std::string_view stage, double fraction) -> bool {
    py::gil_scoped_acquire gil;
    try {
      if (!state->progress.is_none()) {
        const py::object answer = state->progress(py::str(stage.data(), stage.size()), fraction);
        if (!answer.is_none() && !py::bool_(answer)) return false;
      }
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      return true;
    } catch (py::error_already_set& e) {
      const std::lock_guard lock(state->mutex);
      if (!state->error) state->error.emplace(std::move(e));
      return false;
    }
  };
}

void ProgressBridge::rethrow_if_interrupted() {
  std::optional<py::error_already_set> error;
  {
    const std::lock_guard lock(state_->mutex);
    error.swap(state_->error);
  }
  if (error) throw std::move(*error);
}

namespace {

/// A 1-D numpy array owning `v`'s storage (moved, not copied).
template <class Vector>
py::array_t<typename Vector::value_type> owning_vector(Vector&& v) {
  using Scalar = typename Vector::value_type;
  auto* heap = new Vector(std::move(v));
  py::capsule owner(heap, [](void* p) { delete static_cast<Vector*>(p); });
  return py::array_t<Scalar>({static_cast<py::ssize_t>(heap->size())}, heap->data(), owner);
}

py::array_t<float> float_vector(Eigen::VectorXf&& v) {
  auto* heap = new Eigen::VectorXf(std::move(v));
  py::capsule owner(heap, [](void* p) { delete static_cast<Eigen::VectorXf*>(p); });
  return py::array_t<float>({static_cast<py::ssize_t>(heap->size())}, heap->data(), owner);
}

py::module_ types_module() { return py::module_::import("clustersurf._types"); }

}  // namespace

py::object cloud_object(PointCloud&& cloud) {
  using namespace pybind11::literals;
  py::dict attributes;
  for (PointAttribute& a : cloud.attributes) attributes[py::str(a.name)] = float_vector(std::move(a.values));
  py::object scanner_of_point = py::none();
  if (cloud.has_scanners()) scanner_of_point = owning_vector(std::move(cloud.scanner_of_point));
  return types_module().attr("PointCloud")(
      to_array(std::move(cloud.positions)), "normals"_a = to_array_or_none(std::move(cloud.normals)),
      "colors"_a = to_array_or_none(std::move(cloud.colors)), "origin"_a = vector_array(cloud.origin),
      "attributes"_a = attributes,
      "scanner_positions"_a =
          cloud.scanner_positions.rows() > 0 ? py::object(to_array(std::move(cloud.scanner_positions))) : py::none(),
      "scanner_of_point"_a = scanner_of_point, "up"_a = cloud.up == UpAxis::Z ? "z" : "y");
}

py::object mesh_object(SurfaceMesh&& made) {
  py::dict report = json_dict(surface_mesh_json(made));
  py::object mesh = mesh_object(std::move(made.mesh));
  mesh.attr("report") = report;
  return mesh;
}

py::object mesh_object(TriangleMesh&& mesh) {
  using namespace pybind11::literals;
  py::dict attributes;
  for (PointAttribute& a : mesh.attributes) attributes[py::str(a.name)] = float_vector(std::move(a.values));
  return types_module().attr("Mesh")(
      to_array(std::move(mesh.vertices)), to_array(std::move(mesh.triangles)),
      "normals"_a = to_array_or_none(std::move(mesh.normals)), "colors"_a = to_array_or_none(std::move(mesh.colors)),
      "origin"_a = vector_array(mesh.origin), "attributes"_a = attributes, "up"_a = mesh.up == UpAxis::Z ? "z" : "y");
}

Eigen::Vector3d to_vector3(const py::handle& value, const char* name) {
  if (value.is_none()) return Eigen::Vector3d::Zero();
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.ndim() != 1 || a.shape(0) != 3)
    throw OptionError(std::string(name) + " must be (x, y, z): three numbers");
  const Eigen::Vector3d v(a.at(0), a.at(1), a.at(2));
  if (!v.allFinite()) throw OptionError(std::string(name) + " must be finite (no NaN or infinity)");
  return v;
}

bool is_surface_object(const py::handle& object) {
  return !object.is_none() && !py::isinstance<py::array>(object) &&
         (py::hasattr(object, "vertices") || py::hasattr(object, "positions") || py::hasattr(object, "points"));
}

namespace {

/// The parts of a surface object: (vertices, faces, normals, colors, origin, scanner_positions,
/// scanner_of_point), None for what it does not have.
py::tuple surface_parts(const py::handle& object) {
  return types_module().attr("_surface_parts")(object).cast<py::tuple>();
}

py::handle either(py::handle given, py::handle own) { return given.is_none() ? own : given; }

/// The up axis of a parts tuple (its eighth entry, "y" or "z"; absent or None: y).
UpAxis up_of(const py::tuple& parts) {
  if (parts.size() < 8 || parts[7].is_none()) return UpAxis::Y;
  return parts[7].cast<std::string>() == "z" ? UpAxis::Z : UpAxis::Y;
}

}  // namespace

TriangleMesh mesh_argument(const py::handle& object, const py::handle& faces, const py::handle& normals,
                           const py::handle& colors, const py::handle& origin, const std::string& prefix) {
  const py::tuple parts = is_surface_object(object)
                              ? surface_parts(object)
                              : py::make_tuple(object, py::none(), py::none(), py::none(), py::none());
  TriangleMesh mesh;
  mesh.vertices = to_points(parts[0], (prefix + "vertices").c_str());
  const py::handle f = either(faces, parts[1]);
  mesh.triangles = f.is_none() ? Triangles(0, 3) : to_triangles(f, (prefix + "faces").c_str(), mesh.vertices.rows());
  const py::handle n = either(normals, parts[2]);
  if (!n.is_none()) mesh.normals = to_points(n, (prefix + "normals").c_str());
  const py::handle c = either(colors, parts[3]);
  if (!c.is_none()) mesh.colors = to_colors(c, (prefix + "colors").c_str());
  mesh.origin = to_vector3(either(origin, parts[4]), (prefix + "origin").c_str());
  mesh.up = up_of(parts);
  if (mesh.normals.rows() != 0 && mesh.normals.rows() != mesh.vertices.rows())
    throw OptionError(prefix + "normals must have one row per vertex");
  if (mesh.colors.rows() != 0 && mesh.colors.rows() != mesh.vertices.rows())
    throw OptionError(prefix + "colors must have one row per vertex");
  return mesh;
}

PointCloud cloud_argument(const py::handle& object, const py::handle& normals, const py::handle& colors,
                          const py::handle& origin, const std::string& name) {
  const py::tuple parts = is_surface_object(object) ? surface_parts(object)
                                                    : py::make_tuple(object, py::none(), py::none(), py::none(),
                                                                     py::none(), py::none(), py::none());
  PointCloud cloud;
  cloud.positions = to_points(parts[0], name.c_str());
  const py::handle n = either(normals, parts[2]);
  if (!n.is_none()) cloud.normals = to_points(n, "normals");
  const py::handle c = either(colors, parts[3]);
  if (!c.is_none()) cloud.colors = to_colors(c, "colors");
  cloud.origin = to_vector3(either(origin, parts[4]), "origin");
  cloud.up = up_of(parts);
  if (cloud.normals.rows() != 0 && cloud.normals.rows() != cloud.size())
    throw OptionError("normals must have one row per point");
  if (cloud.colors.rows() != 0 && cloud.colors.rows() != cloud.size())
    throw OptionError("colors must have one row per point");
  // Which scan saw each point, with or without where the scans stood (then each index names one).
  if (!parts[6].is_none()) {
    if (!parts[5].is_none()) cloud.scanner_positions = to_points(parts[5], "scanner_positions");
    const auto which = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(parts[6]);
    if (!which || which.ndim() != 1 || which.shape(0) != cloud.size())
      throw OptionError("scanner_of_point must have one entry per point");
    const std::int64_t scans =
        parts[5].is_none() ? std::int64_t{0xFFFFFFFF} : static_cast<std::int64_t>(cloud.scanner_positions.rows());
    cloud.scanner_of_point.reserve(static_cast<std::size_t>(which.shape(0)));
    const std::int64_t* index = which.data();
    for (py::ssize_t i = 0; i < which.shape(0); ++i) {
      const std::int64_t s = index[i];
      if (s < 0 || s >= scans)
        throw OptionError("scanner_of_point has a scan index outside [0, " + std::to_string(scans) + ")");
      cloud.scanner_of_point.push_back(static_cast<std::uint32_t>(s));
    }
  }
  // A PointCloud's attributes (intensity, classification) come along: "intensity" colors.
  if (is_surface_object(object) && py::hasattr(object, "attributes") &&
      py::isinstance<py::dict>(object.attr("attributes"))) {
    for (const auto& [key, value] : object.attr("attributes").cast<py::dict>()) {
      const auto values = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
      if (!values || values.ndim() != 1 || values.shape(0) != cloud.size()) continue;
      cloud.attributes.push_back({py::str(key), Eigen::Map<const Eigen::VectorXf>(values.data(), cloud.size())});
    }
  }
  return cloud;
}

py::dict json_dict(const std::string& json) { return py::module_::import("json").attr("loads")(json); }

}  // namespace clustersurf::python
