#pragma once
// Progress reporting and cancellation for long operations (OpenVDB's Interrupter is the model).

#include <functional>
#include <string_view>

namespace clustersurf {

/// Called by long operations with the name of the current stage and the fraction done in
/// [0, 1]. Return false to cancel: the operation then throws clustersurf::Cancelled. Calls are
/// serialized (never concurrent) but may come from any thread; keep them cheap.
using ProgressCallback = std::function<bool(std::string_view stage, double fraction)>;

}  // namespace clustersurf
