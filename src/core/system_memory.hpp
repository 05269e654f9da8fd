#pragma once
// How much memory the machine can give a run.

#include <cstdint>

namespace clustersurf::detail {

/// The memory the machine can give without swapping, in bytes: MemAvailable of /proc/meminfo
/// (free memory plus the page cache it can reclaim), else the free physical pages; 0 when
/// neither is known.
std::uint64_t available_memory();

}  // namespace clustersurf::detail
