#pragma once
// Reading a command's input cloud with the CLI's warning channel.

#include "commands.hpp"

#include <clustersurf/io/point_cloud_io.hpp>

namespace clustersurf::cli {

/// How a command reads its input, warnings to the console.
inline ReadOptions read_options(Console& console, const InputArgs& input) {
  ReadOptions options;
  options.drop_non_finite = input.drop_non_finite;
  options.mesh_samples = input.mesh_samples;
  options.warn = [&console](const std::string& message) { console.warn(message); };
  return options;
}

inline PointCloud read_input(Console& console, const InputArgs& input) {
  return read_point_cloud(input.file, read_options(console, input));
}

/// A cloud named by a command's option (--points): read as `reconstruct` reads its input by
/// default, so the tree's input is found again.
inline PointCloud read_input(Console& console, const std::string& file) {
  InputArgs input;
  input.file = file;
  return read_input(console, input);
}

}  // namespace clustersurf::cli
