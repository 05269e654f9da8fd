// Deflate in parallel bands, joined into one zlib stream.

#include "render/banded_deflate.hpp"

#include <clustersurf/core/errors.hpp>

#include <tbb/parallel_for.h>
#include <zlib.h>

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

namespace clustersurf::render {

namespace {

/// Each band holds this many input bytes: large enough that its sync flush and dictionary
/// priming cost nothing measurable, small enough that an image of a few megabytes keeps every
/// core busy.
constexpr std::size_t kBand = std::size_t{1} << 19;
/// Deflate's window: a band is primed with this much of the input before it.
constexpr std::size_t kWindow = std::size_t{1} << 15;

/// The raw deflate (no header) of `band`, primed with `dictionary`, ending in a sync flush or,
/// for the last band, the final block.
std::vector<unsigned char> deflate_band(std::span<const unsigned char> band, std::span<const unsigned char> dictionary,
                                        int level, bool last) {
  z_stream z{};
  if (deflateInit2(&z, level, Z_DEFLATED, -MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw IoError("zlib could not start a deflate stream (out of memory?)");
  std::vector<unsigned char> out(deflateBound(&z, static_cast<uLong>(band.size())) + 16);
  int status = Z_OK;
  if (!dictionary.empty()) status = deflateSetDictionary(&z, dictionary.data(), static_cast<uInt>(dictionary.size()));
  if (status == Z_OK) {
    z.next_in = const_cast<Bytef*>(band.data());  // zlib's API is not const-correct; it only reads
    z.avail_in = static_cast<uInt>(band.size());
    z.next_out = out.data();
    z.avail_out = static_cast<uInt>(out.size());
    status = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
  }
  const std::size_t written = out.size() - z.avail_out;
  deflateEnd(&z);
  if (status != (last ? Z_STREAM_END : Z_OK) || z.avail_in != 0)
    throw IoError("zlib could not deflate an image band (out of memory?)");
  out.resize(written);
  return out;
}

}  // namespace

std::vector<unsigned char> banded_deflate(std::span<const unsigned char> data, int level) {
  const std::size_t bands = std::max<std::size_t>(1, (data.size() + kBand - 1) / kBand);
  std::vector<std::vector<unsigned char>> parts(bands);
  std::vector<uLong> checks(bands);
  tbb::parallel_for(std::size_t{0}, bands, [&](std::size_t b) {
    const std::size_t begin = b * kBand, end = std::min(data.size(), begin + kBand);
    const std::size_t primed = begin - std::min(begin, kWindow);
    parts[b] =
        deflate_band(data.subspan(begin, end - begin), data.subspan(primed, begin - primed), level, b + 1 == bands);
    checks[b] = adler32(adler32(0, nullptr, 0), data.data() + begin, static_cast<uInt>(end - begin));
  });
  // The zlib header: deflate with a 32 KiB window, the level's flag, the check bits (RFC 1950).
  const unsigned level_flag = level < 2 ? 0 : level < 6 ? 1 : level == 6 ? 2 : 3;
  const unsigned header = 0x7800 | (level_flag << 6);
  std::vector<unsigned char> out;
  std::size_t total = 6;
  for (const auto& p : parts) total += p.size();
  out.reserve(total);
  const unsigned checked = header % 31 == 0 ? header : header + 31 - header % 31;
  out.push_back(static_cast<unsigned char>(checked >> 8));
  out.push_back(static_cast<unsigned char>(checked & 0xff));
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  // The Adler-32 of the whole data, combined from the bands'.
  uLong adler = checks[0];
  for (std::size_t b = 1; b < bands; ++b) {
    const std::size_t length = std::min(data.size(), (b + 1) * kBand) - b * kBand;
    adler = adler32_combine(adler, checks[b], static_cast<z_off_t>(length));
  }
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<unsigned char>((adler >> shift) & 0xff));
  return out;
}

}  // namespace clustersurf::render
