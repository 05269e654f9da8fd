// The library's options from Python keyword arguments: each value as the option schema's text
// (reconstruct_option_schema()), checked and set by the library.

#include "bindings.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/render_option_schema.hpp>

#include <pybind11/stl.h>

#include <algorithm>

namespace clustersurf::python {

namespace {

/// A keyword's value as the schema's text: True/False as "true"/"false", numbers as the shortest
/// text that reads back the same, strings as given, three numbers (a sequence or array) as "x,y,z".
std::string option_text(const std::string& key, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  if (py::isinstance<py::float_>(value)) return number_text(value.cast<double>());
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::sequence>(value) || py::hasattr(value, "__array__")) {
    std::vector<double> v;
    try {
      v = py::cast<std::vector<double>>(py::module_::import("numpy").attr("asarray")(value, "float64").attr("ravel")());
    } catch (const py::error_already_set&) {
      v.clear();
    }
    if (v.size() == 3) return vector_text(v[0], v[1], v[2]);
  }
  throw OptionError("option " + key + " takes a number, a bool, a word or (x, y, z), not a " +
                    py::str(py::type::of(value).attr("__name__")).cast<std::string>());
}

/// The schema's default text as the Python value a keyword takes.
template <class Options>
py::object default_value(const OptionSpecOf<Options>& spec) {
  const std::string text = default_text(spec);
  if (text.empty()) return py::none();
  if (std::find(spec.words.begin(), spec.words.end(), text) != spec.words.end()) return py::str(text);
  switch (spec.kind) {
    case OptionKind::Flag:
      return py::bool_(text == "true");
    case OptionKind::Whole:
      return py::int_(std::stoull(text));
    case OptionKind::Number:
      return py::float_(std::stod(text));
    case OptionKind::Vector: {
      const std::array<double, 3> v = parse_vector(spec.name, text);
      return py::make_tuple(v[0], v[1], v[2]);
    }
    case OptionKind::Word:
      break;
  }
  return py::str(text);
}

const char* kind_name(OptionKind kind) {
  switch (kind) {
    case OptionKind::Flag:
      return "flag";
    case OptionKind::Whole:
      return "whole";
    case OptionKind::Number:
      return "number";
    case OptionKind::Word:
      return "word";
    case OptionKind::Vector:
      return "vector";
  }
  return "word";
}

/// The keyword arguments that are not None, as the schema's text.
OptionValues option_values(const py::dict& options) {
  OptionValues values;
  for (const auto& [k, value] : options) {
    const std::string key = py::str(k);
    if (!value.is_none()) values.emplace_back(key, option_text(key, value));
  }
  return values;
}

/// Docstring lines of the options of `stage` in `schema`.
template <class Options>
std::string schema_doc(const std::vector<OptionSpecOf<Options>>& schema, OptionStage stage) {
  std::string out;
  for (const OptionSpecOf<Options>& spec : schema) {
    if (spec.stage != stage) continue;
    const py::object value = default_value(spec);
    out += "``" + spec.name + "`` (default " + py::repr(value).cast<std::string>() + "): " + spec.help;
    if (!spec.alias.empty()) out += " (older name ``" + spec.alias + "``)";
    out += ".\n";
  }
  return out;
}

/// The schema as a list of dicts (option_schema()).
template <class Options>
void append_schema(py::list& out, const std::vector<OptionSpecOf<Options>>& schema) {
  for (const OptionSpecOf<Options>& spec : schema) {
    py::dict d;
    d["name"] = spec.name;
    d["alias"] = spec.alias.empty() ? py::object(py::none()) : py::object(py::str(spec.alias));
    d["stage"] = spec.stage == OptionStage::Build ? "build" : spec.stage == OptionStage::Mesh ? "mesh" : "render";
    d["kind"] = kind_name(spec.kind);
    d["words"] = spec.words;
    d["default"] = default_value(spec);
    d["help"] = spec.help;
    out.append(std::move(d));
  }
}

}  // namespace

ReconstructOptions reconstruct_options(const py::dict& options, std::vector<OptionStage> stages) {
  ReconstructOptions o;
  set_options(o, option_values(options), std::move(stages));
  return o;
}

RenderOptions render_options(const py::dict& options) {
  RenderOptions o;
  set_options(o, option_values(options));
  return o;
}

std::string options_doc(OptionStage stage) {
  return stage == OptionStage::Render ? schema_doc(render_option_schema(), stage)
                                      : schema_doc(reconstruct_option_schema(), stage);
}

void bind_option_schema(py::module_& m) {
  m.def(
      "option_schema",
      [] {
        py::list out;
        append_schema(out, reconstruct_option_schema());
        append_schema(out, render_option_schema());
        return out;
      },
      R"doc(
The keyword options of reconstruct(), reconstruct_mesh(), Tree.mesh(), the tiled runs and
Tree.render(), as the library describes them once for the CLI and this module: a list of dicts
with ``name``, ``alias`` (an older name, or None), ``stage`` ("build": the tree; "mesh": its
mesh; "render": a picture), ``kind`` ("flag", "whole", "number", "word" or "vector": (x, y, z)), ``words`` (the words it takes: choices, "auto"),
``default`` (None: unset) and ``help``.)doc");
}

}  // namespace clustersurf::python
