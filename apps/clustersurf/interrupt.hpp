#pragma once
// Ctrl-C (SIGINT) and SIGTERM for the CLI: the first one asks the running operation to stop at
// its next progress report (it then throws Cancelled, and no output is written: outputs are
// atomic); a second one terminates the process at once.

namespace clustersurf::cli {

/// Installs the handlers. The request is the CLI's one piece of process-wide state: a signal
/// handler can reach nothing else.
void install_interrupt_handlers();

/// True once SIGINT or SIGTERM has arrived.
bool interrupt_requested();

}  // namespace clustersurf::cli
