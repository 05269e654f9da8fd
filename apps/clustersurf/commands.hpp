#pragma once
// The subcommands of the CLI. Each takes its parsed arguments and returns the exit code;
// failures are thrown as clustersurf::Error and turned into messages once, in main().

#include "console.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace clustersurf::cli {

/// Arguments shared by commands that read a point cloud.
struct InputArgs {
  std::string file;
  bool drop_non_finite = false;
};

struct ConvertArgs {
  InputArgs input;
  std::string output;
  std::optional<std::size_t> subsample;
  std::optional<double> voxel;
  std::uint64_t seed = 1;
  bool ascii = false;
  bool double_precision = false;
};
int run_convert(Console& console, const ConvertArgs& args);

struct StatsArgs {
  InputArgs input;
};
int run_stats(Console& console, const StatsArgs& args);

}  // namespace clustersurf::cli
