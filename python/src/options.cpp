// The library's options from Python keyword arguments: each value as the option schema's text
// (reconstruct_option_schema()), checked and set by the library.

#include "bindings.hpp"

#include <clustersurf/core/errors.hpp>

#include <pybind11/stl.h>

#include <algorithm>

namespace clustersurf::python {

namespace {

/// A keyword's value as the schema's text: True/False as "true"/"false", numbers as the shortest
/// text that reads back the same, strings as given.
std::string option_text(const std::string& key, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  if (py::isinstance<py::float_>(value)) return number_text(value.cast<double>());
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  throw OptionError("option " + key + " takes a number, a bool or a word, not a " +
                    py::str(py::type::of(value).attr("__name__")).cast<std::string>());
}

/// The schema's default text as the Python value a keyword takes.
py::object default_value(const OptionSpec& spec) {
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
  }
  return "word";
}

}  // namespace

ReconstructOptions reconstruct_options(const py::dict& options, std::vector<OptionStage> stages) {
  OptionValues values;
  for (const auto& [k, value] : options) {
    const std::string key = py::str(k);
    if (!value.is_none()) values.emplace_back(key, option_text(key, value));
  }
  ReconstructOptions o;
  set_options(o, values, std::move(stages));
  return o;
}

std::string options_doc(OptionStage stage) {
  std::string out;
  for (const OptionSpec& spec : reconstruct_option_schema()) {
    if (spec.stage != stage) continue;
    const py::object value = default_value(spec);
    out += "``" + spec.name + "`` (default " + py::repr(value).cast<std::string>() + "): " + spec.help;
    if (!spec.alias.empty()) out += " (older name ``" + spec.alias + "``)";
    out += ".\n";
  }
  return out;
}

void bind_option_schema(py::module_& m) {
  m.def(
      "option_schema",
      [] {
        py::list out;
        for (const OptionSpec& spec : reconstruct_option_schema()) {
          py::dict d;
          d["name"] = spec.name;
          d["alias"] = spec.alias.empty() ? py::object(py::none()) : py::object(py::str(spec.alias));
          d["stage"] = spec.stage == OptionStage::Build ? "build" : "mesh";
          d["kind"] = kind_name(spec.kind);
          d["words"] = spec.words;
          d["default"] = default_value(spec);
          d["help"] = spec.help;
          out.append(std::move(d));
        }
        return out;
      },
      R"doc(
The keyword options of reconstruct(), reconstruct_mesh(), Tree.mesh() and the tiled runs, as
the library describes them once for the CLI and this module: a list of dicts with ``name``,
``alias`` (an older name, or None), ``stage`` ("build": the tree; "mesh": its mesh), ``kind``
("flag", "whole", "number" or "word"), ``words`` (the words it takes: choices, "auto"),
``default`` (None: unset) and ``help``.)doc");
}

}  // namespace clustersurf::python
