// The library's option structs from Python keyword arguments (the CLI's names with _ for -).

#include "bindings.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>

#include <cmath>

namespace clustersurf::python {

namespace {

/// A tolerance given as "auto", a number, or a number as text (parse_tolerance()); nullopt: auto.
std::optional<double> tolerance_option(const py::handle& value) {
  if (py::isinstance<py::str>(value)) return parse_tolerance(value.cast<std::string>());
  double number = 0;
  try {
    number = py::cast<double>(value);
  } catch (const py::cast_error&) {
    throw OptionError("tolerance must be \"auto\" or a non-negative fraction of the diagonal");
  }
  if (!(number >= 0) || !std::isfinite(number))
    throw OptionError("tolerance must be \"auto\" or a non-negative fraction of the diagonal, not " +
                      std::to_string(number));
  return number;
}

template <class T>
T as(const py::handle& value, const std::string& key) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw OptionError("option " + key + " has the wrong type");
  }
}

/// min_points given as "auto" or a whole number (parse_min_points()).
std::uint32_t min_points_option(const py::handle& value) {
  if (py::isinstance<py::str>(value)) return parse_min_points(value.cast<std::string>());
  if (!py::isinstance<py::int_>(value))
    throw OptionError("min points must be \"auto\" or a whole number from 1 to 2^30");
  return parse_min_points(std::to_string(value.cast<std::int64_t>()));
}

}  // namespace

ReconstructOptions reconstruct_options(const py::dict& options) {
  ReconstructOptions o;
  BuildOptions& b = o.build;
  SurfaceMeshOptions& m = o.meshing;
  std::optional<double> absolute;
  for (const auto& [k, value] : options) {
    const std::string key = py::str(k);
    if (key == "proxy")
      b.proxy = parse_proxy_kind(as<std::string>(value, key));
    else if (key == "splitter")
      b.splitter = parse_splitter(as<std::string>(value, key));
    else if (key == "tolerance") {
      if (const auto t = tolerance_option(value)) b.tolerance = *t;
    } else if (key == "absolute_tolerance") {
      if (!value.is_none()) absolute = as<double>(value, key);
    } else if (key == "error")
      b.metric = parse_error_metric(as<std::string>(value, key));
    else if (key == "min_points")
      b.min_points = min_points_option(value);
    else if (key == "max_depth")
      b.max_depth = to_uint32(as<std::int64_t>(value, key), "max_depth");
    else if (key == "alpha")
      b.alpha = as<double>(value, key);
    else if (key == "kstep")
      b.kstep = to_uint32(as<std::int64_t>(value, key), "kstep");
    else if (key == "lloyd_restarts")
      b.lloyd_restarts = to_uint32(as<std::int64_t>(value, key), "lloyd_restarts");
    else if (key == "proxy_lloyd")
      b.proxy_lloyd_iterations = to_uint32(as<std::int64_t>(value, key), "proxy_lloyd");
    else if (key == "noise_factor")
      b.noise_factor = as<double>(value, key);
    else if (key == "support_factor")
      b.support_factor = as<double>(value, key);
    else if (key == "seed")
      b.seed = as<std::uint64_t>(value, key);
    else if (key == "ignore_normals")
      b.use_normals = !as<bool>(value, key);
    else if (key == "no_point_leaves")
      b.keep_point_leaves = !as<bool>(value, key);
    else if (key == "keep_outliers")
      b.remove_outliers = !as<bool>(value, key);
    else if (key == "creases")
      b.creases = as<bool>(value, key);
    else if (key == "resolution") {
      const std::string text =
          py::isinstance<py::str>(value) ? as<std::string>(value, key) : std::to_string(as<std::int64_t>(value, key));
      if (const auto cells = parse_resolution(text)) m.auto_resolution = false, m.grid.resolution = *cells;
    } else if (key == "voxel_size") {
      if (!value.is_none()) {
        const double h = as<double>(value, key);
        if (!(h > 0) || !std::isfinite(h)) throw OptionError("voxel_size must be positive");
        m.grid.voxel_size = h;
      }
    } else if (key == "lod_depth") {
      if (!value.is_none()) m.lod_depth = to_uint32(as<std::int64_t>(value, key), "lod_depth");
    } else if (key == "lod_error") {
      if (!value.is_none()) m.lod_error = as<double>(value, key);
    } else if (key == "trim")
      m.trim.spread_factor = as<double>(value, key);
    else if (key == "min_component_points")
      m.trim.min_component_points = as<std::size_t>(value, key);
    else if (key == "close_pinholes")
      m.trim.close_pinholes = as<bool>(value, key);
    else if (key == "color")
      m.coloring = parse_mesh_coloring(as<std::string>(value, key));
    else if (key == "watertight")
      m.closing.enabled = as<bool>(value, key);
    else if (key == "fill_holes")
      m.closing.max_hole_size = as<double>(value, key);
    else if (key == "decimate")
      m.decimation.target_triangles = as<std::size_t>(value, key);
    else if (key == "decimate_tolerance")
      m.decimation.max_deviation = as<double>(value, key);
    else
      throw OptionError("unknown option \"" + key + "\"");
  }
  if (b.lloyd_restarts < 1) throw OptionError("lloyd_restarts must be at least 1");
  if (absolute) {
    if (!(*absolute >= 0) || !std::isfinite(*absolute)) throw OptionError("absolute_tolerance must be >= 0");
    b.threshold_mode = ThresholdMode::Absolute;
    b.tolerance = *absolute;
  }
  return o;
}

}  // namespace clustersurf::python
