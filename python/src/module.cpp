// The extension module `clustersurf._clustersurf`: exception classes and the bindings. The
// package `clustersurf` (python/clustersurf/__init__.py) re-exports everything.

#include "bindings.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/version.hpp>

#include <new>

namespace clustersurf::python {

namespace {

constexpr const char* kModule = "clustersurf._clustersurf";

/// Creates the class `name(*bases)` in module `m`, as `class name(*bases)` would in Python.
py::object add_exception(py::module_& m, const char* name, const py::tuple& bases, const char* doc) {
  py::dict namespace_;
  namespace_["__module__"] = "clustersurf";
  namespace_["__doc__"] = doc;
  const auto type = py::reinterpret_borrow<py::object>(reinterpret_cast<PyObject*>(&PyType_Type));
  py::object cls = type(name, bases, namespace_);
  m.attr(name) = cls;
  return cls;
}

/// Raises the module's exception class `name` with `message` (the C++ what(), unchanged).
void set_python_error(const char* name, const char* message) {
  const py::object cls = py::module_::import(kModule).attr(name);
  PyErr_SetString(cls.ptr(), message);
}

void translate(std::exception_ptr error) {
  try {
    if (error) std::rethrow_exception(error);
  } catch (const InputError& e) {
    set_python_error("InputError", e.what());
  } catch (const IoError& e) {
    set_python_error("IoError", e.what());
  } catch (const OptionError& e) {
    set_python_error("OptionError", e.what());
  } catch (const Cancelled& e) {
    set_python_error("Cancelled", e.what());
  } catch (const Error& e) {
    set_python_error("Error", e.what());
  }
}

}  // namespace

}  // namespace clustersurf::python

PYBIND11_MODULE(_clustersurf, m) {
  using namespace clustersurf::python;
  m.doc() = "Native part of the clustersurf package; import `clustersurf` instead.";
  m.attr("__version__") = clustersurf::kVersion;

  const py::object error = add_exception(m, "Error", py::make_tuple(py::handle(PyExc_Exception)),
                                         "Base of every clustersurf error; str(e) is the message the CLI prints.");
  add_exception(m, "InputError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                "A file's content is malformed or unsupported; the message names the file and the line or byte.");
  add_exception(m, "IoError", py::make_tuple(error, py::handle(PyExc_OSError)),
                "The operating system refused an I/O operation (missing file, permission, disk full).");
  add_exception(m, "OptionError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                "An invalid option or argument (out of range, wrong array shape, inconsistent).");
  add_exception(m, "Cancelled", py::make_tuple(error),
                "A progress callback returned False; the operation left no partial output.");
  py::register_exception_translator(&translate);

  bind_io(m);
  py::class_<TreeRef> tree_class(m, "Tree", R"doc(
A cluster tree: binary tree of point clusters, each with a fitted proxy surface and support
sphere; its leaves blend into the implicit surface f (positive outside). Immutable. Made by
reconstruct() or load(); saved bit-exactly with save(). Pickles as its .cstree bytes.)doc");
  bind_node(m);
  bind_tree(m, tree_class);
  bind_render(tree_class);
  bind_tiles(m);
  bind_option_schema(m);
}
