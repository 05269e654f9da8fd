// Entry point of the `clustersurf` command-line tool: the command line parsed
// (command_line.cpp), the subcommand run, and the single place where errors become messages
// and exit codes.

#include "command_line.hpp"
#include "commands.hpp"
#include "interrupt.hpp"

#include <clustersurf/core/errors.hpp>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cstdio>
#include <limits>
#include <memory>
#include <new>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {

// Exit codes, documented in the README.
constexpr int kExitUsage = 2;
constexpr int kExitInput = 3;
constexpr int kExitIo = 4;
constexpr int kExitMemory = 5;
constexpr int kExitCancelled = 130;
constexpr int kExitInternal = 70;

/// The exit code of the exception in flight, its message logged: the one place where errors
/// become messages and exit codes.
int report_failure(clustersurf::cli::Console& console) {
  console.end_progress();
  try {
    throw;
  } catch (const clustersurf::InputError& e) {
    spdlog::error("{}", e.what());
    return kExitInput;
  } catch (const clustersurf::IoError& e) {
    spdlog::error("{}", e.what());
    return kExitIo;
  } catch (const clustersurf::OptionError& e) {
    spdlog::error("{}", e.what());
    return kExitUsage;
  } catch (const clustersurf::Cancelled&) {
    spdlog::error("{}", clustersurf::cli::interrupt_requested()
                            ? "interrupted: stopped before writing any output (files already there are unchanged)"
                            : "cancelled");
    return kExitCancelled;
  } catch (const std::bad_alloc&) {
    spdlog::error("out of memory");
    return kExitMemory;
  } catch (const std::exception& e) {
    spdlog::error("internal error: {}", e.what());
    return kExitInternal;
  }
}

/// Large blocks come from the heap and freed memory stays with the process until it exits.
/// glibc's defaults map each block over 32 MB afresh and unmap it when freed, so a pipeline
/// that frees and reallocates arrays of a million vertices or cells pays every page fault again
/// (about a fifth of a 1 M-point run); a one-shot tool gains nothing by returning the memory
/// early. The top of the heap is returned only beyond mallopt's largest threshold (2 GB): the
/// out-of-core join reads tile after tile of 300 MB into new arrays, and with a lower threshold
/// each read faults every page in again (a 10 M-point run's join: 6.7 s, 38-50 s at 1 GB). The
/// peak grows by what the heap cannot reuse (a few percent).
void keep_freed_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
#endif
}

}  // namespace

int main(int argc, char** argv) {
  using namespace clustersurf::cli;
  keep_freed_memory();
  const CommandLine line = parse_command_line(argc, argv, kExitUsage);
  if (line.exit) return *line.exit;
  const Commands& c = line.commands;
  const int threads =
      line.global.threads > 0 ? line.global.threads : static_cast<int>(tbb::info::default_concurrency());
  tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  Console console(line.global);
  install_interrupt_handlers();
  try {
    if (line.command == "convert") return run_convert(console, c.convert);
    if (line.command == "stats") return run_stats(console, c.stats);
    if (line.command == "reconstruct") return run_reconstruct(console, c.reconstruct);
    if (line.command == "info") return run_info(console, c.info);
    if (line.command == "mesh") return run_mesh(console, c.mesh);
    if (line.command == "sample") return run_sample(console, c.sample);
    if (line.command == "eval") return run_eval(console, c.eval);
    if (line.command == "check") return run_check(console, c.check);
    if (line.command == "render") return run_render(console, c.render);
    if (line.command == "view") return run_view(console, c.view);
    return kExitUsage;
  } catch (...) {
    return report_failure(console);
  }
}
