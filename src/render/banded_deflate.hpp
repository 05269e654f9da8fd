#pragma once
// A zlib stream compressed in fixed bands at once (as pigz does): each band is deflated on its
// own thread, primed with the 32 KiB of input before it, and the bands are joined by
// sync flushes into one stream any zlib reader inflates.

#include <cstddef>
#include <span>
#include <vector>

namespace clustersurf::render {

/// The zlib stream (RFC 1950) of `data` at zlib `level` (0–9), its bands deflated in parallel.
/// The bands are fixed by the data's length alone, so the bytes never depend on the thread
/// count; each band after the first starts from its predecessor's last 32 KiB as dictionary,
/// so the stream is within a few hundred bytes per band of a one-piece deflate. Throws
/// IoError when zlib fails (out of memory).
std::vector<unsigned char> banded_deflate(std::span<const unsigned char> data, int level);

}  // namespace clustersurf::render
