#pragma once
// Terminal output of the CLI: human text on stdout, JSON on stdout with --json, warnings and a
// progress bar on stderr (the bar only when stderr is a terminal and neither --quiet nor --json).

#include <clustersurf/core/progress.hpp>

#include <chrono>
#include <mutex>
#include <string>

namespace clustersurf::cli {

/// Options every subcommand shares.
struct GlobalOptions {
  int threads = 0;  // 0: all cores
  bool quiet = false;
  bool json = false;
};

/// Output channel of one CLI run.
class Console {
 public:
  explicit Console(const GlobalOptions& options);
  ~Console();

  const GlobalOptions& options() const { return options_; }
  /// Prints a line of human-readable output on stdout (suppressed by --quiet and --json).
  void print(const std::string& line) const;
  /// Prints a warning on stderr (suppressed by --quiet).
  void warn(const std::string& message) const;
  /// A progress callback drawing a bar on stderr (when one is wanted) that asks the operation to
  /// stop once Ctrl-C or SIGTERM has arrived (interrupt.hpp).
  ProgressCallback progress();
  /// Erases the progress bar line, if one is shown.
  void end_progress();

 private:
  GlobalOptions options_;
  bool bar_ = false;
  std::mutex mutex_;
  std::string stage_;
  int last_permille_ = -1;
  std::chrono::steady_clock::time_point last_draw_{};
  bool drawn_ = false;
};

}  // namespace clustersurf::cli
