// numpy <-> Eigen conversions, integer options and the progress bridge of the bindings.

#include "bindings.hpp"

#include <clustersurf/errors.hpp>

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

py::object cloud_object(PointCloud&& cloud) {
  const py::object make = py::module_::import("clustersurf._types").attr("PointCloud");
  return make(to_array(std::move(cloud.positions)), to_array_or_none(std::move(cloud.normals)),
              to_array_or_none(std::move(cloud.colors)));
}

py::object mesh_object(TriangleMesh&& mesh) {
  const py::object make = py::module_::import("clustersurf._types").attr("Mesh");
  return make(to_array(std::move(mesh.vertices)), to_array(std::move(mesh.triangles)),
              to_array_or_none(std::move(mesh.normals)), to_array_or_none(std::move(mesh.colors)));
}

}  // namespace clustersurf::python
