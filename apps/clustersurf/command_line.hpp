#pragma once
// The command line of the `clustersurf` tool: every subcommand and its options, bound to the
// arguments the subcommands take (CLI11, confined to command_line.cpp: it is slow to compile).

#include "commands.hpp"

#include <optional>
#include <string>

namespace clustersurf::cli {

/// The arguments of every subcommand (CLI11 binds to them; the one parsed is run).
struct Commands {
  ConvertArgs convert;
  StatsArgs stats;
  ReconstructArgs reconstruct;
  InfoArgs info;
  MeshCommandArgs mesh;
  SampleArgs sample;
  EvalArgs eval;
  CheckArgs check;
  RenderArgs render;
  ViewArgs view;
};

/// What the command line asked for: the global options, the subcommand and its arguments.
struct CommandLine {
  GlobalOptions global;
  Commands commands;
  std::string command;      ///< the subcommand parsed ("reconstruct", ...)
  std::optional<int> exit;  ///< set when parsing printed help, the version or a usage error: exit with it
};

/// Parses `argv`; help, the version and usage errors are printed here (CommandLine::exit).
CommandLine parse_command_line(int argc, char** argv, int usage_exit_code);

}  // namespace clustersurf::cli
