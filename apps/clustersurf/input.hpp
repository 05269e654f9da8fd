#pragma once
// Reading a command's input cloud with the CLI's warning channel.

#include "commands.hpp"

#include <clustersurf/point_cloud_io.hpp>

namespace clustersurf::cli {

inline PointCloud read_input(Console& console, const InputArgs& input) {
  ReadOptions options;
  options.drop_non_finite = input.drop_non_finite;
  options.warn = [&console](const std::string& message) { console.warn(message); };
  return read_point_cloud(input.file, options);
}

}  // namespace clustersurf::cli
