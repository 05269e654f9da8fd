// E57 points a block of records at a time: each scan's packets decoded as far as the block
// needs, the values kept only until they are taken; see E57Points in readers.hpp.

#include "io/e57_scans.hpp"
#include "io/readers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace clustersurf::io {

/// Decoded values are moved to the front of their buffers once this many have been taken.
constexpr std::size_t kCompactValues = std::size_t{1} << 16;

struct E57Points::Impl {
  Impl(const std::filesystem::path& file, std::string_view bytes) : pages(file, bytes), scans(e57::read_scans(pages)) {
    colors = !scans.scans.empty() &&
             std::all_of(scans.scans.begin(), scans.scans.end(), [](const e57::Scan& s) { return s.has_colors(); });
  }

  e57::PagedFile pages;
  e57::Scans scans;
  std::size_t scan = 0;     // the scan being read
  std::uint64_t taken = 0;  // its records taken
  std::optional<e57::RecordDecoder> decoder;
  bool colors = false;  // every scan has colors: they are decoded too
  /// Decoded and not yet taken from `head` on: x, y, z, invalid state, red, green, blue.
  std::array<std::vector<double>, 7> values;
  std::array<std::optional<double>, 7> constant;  // the value of a field stored in no bits
  std::size_t head = 0;
  /// The records of the scan not yet taken that were decoded with a non-finite coordinate, and
  /// where (logical offset) the first such value of each is.
  std::map<std::uint64_t, std::uint64_t> non_finite;
  /// The physical bytes no read touches again, not yet handed out by finished_bytes().
  std::vector<std::pair<std::uint64_t, std::uint64_t>> finished;
  std::uint64_t released = 0;  // physical offset up to which the current scan's bytes are handed out

  /// Starts decoding scan `scan` (if any is left), first handing out the rest of the one before.
  void open_scan();
  /// Records decoded and not yet taken.
  std::size_t ready() const {
    const e57::Scan& s = scans.scans[scan];
    std::size_t n = static_cast<std::size_t>(s.records - taken);
    for (std::size_t k = 0; k < values.size(); ++k)
      if (used(k) && !constant[k]) n = std::min(n, values[k].size() - head);
    return n;
  }
  /// Whether field k (of `values`) is decoded for the current scan.
  bool used(std::size_t k) const { return k < 3 || (k == 3 ? scans.scans[scan].invalid >= 0 : colors); }
  /// Field k's value of the i-th record held.
  double value(std::size_t k, std::size_t i) const { return constant[k] ? *constant[k] : values[k][i]; }
  /// Hands out the current scan's bytes up to physical offset `to`.
  void finish_up_to(std::uint64_t to) {
    if (to > released) finished.emplace_back(released, to);
    released = std::max(released, to);
  }
};

void E57Points::Impl::open_scan() {
  if (decoder) finish_up_to(pages.to_physical(scans.scans[scan - 1].section.end));
  decoder.reset();
  for (auto& v : values) v.clear();
  constant.fill(std::nullopt);
  head = 0;
  taken = 0;
  non_finite.clear();
  if (scan >= scans.scans.size()) return;
  const e57::Scan& s = scans.scans[scan];
  if (s.records == 0) return;
  released = pages.to_physical(s.section.begin);
  std::vector<e57::StreamField> streams = s.streams();
  const int fields[7] = {s.coord[0], s.coord[1], s.coord[2], s.invalid, s.color[0], s.color[1], s.color[2]};
  for (std::size_t k = 0; k < 7; ++k) {
    if (fields[k] < 0 || !used(k)) continue;
    e57::StreamField& f = streams[static_cast<std::size_t>(fields[k])];
    if (f.codec.bits == 0) {  // a constant, not decoded record by record
      constant[k] = f.codec.value(0);
      continue;
    }
    f.sink = [this, k](std::uint64_t r, double v, std::uint64_t logical) {
      values[k].push_back(v);
      if (k < 3 && !std::isfinite(v)) non_finite.emplace(r, logical);  // keeps the first field's
    };
  }
  decoder.emplace(pages, s.section, s.records, std::move(streams));
}

E57Points::E57Points(const std::filesystem::path& file, std::string_view bytes)
    : impl_(std::make_unique<Impl>(file, bytes)) {
  impl_->open_scan();
}

E57Points::~E57Points() = default;

std::uint64_t E57Points::records() const noexcept { return impl_->scans.records; }
bool E57Points::has_colors() const noexcept { return impl_->colors; }

void E57Points::read(std::uint64_t n, Points& out, std::vector<std::optional<std::uint64_t>>& located, Colors* colors) {
  Impl& d = *impl_;
  out.resize(static_cast<Eigen::Index>(std::min<std::uint64_t>(n, d.scans.records)), 3);
  if (colors != nullptr) colors->resize(d.colors ? out.rows() : 0, 3);
  located.clear();
  Eigen::Index kept = 0;
  while (n > 0 && d.scan < d.scans.scans.size()) {
    const e57::Scan& s = d.scans.scans[d.scan];
    if (d.taken == s.records) {
      ++d.scan;
      d.open_scan();
      continue;
    }
    const std::uint64_t want = std::min(n, s.records - d.taken);
    while (d.ready() < want && d.decoder->next_packet()) {}
    const std::size_t m = static_cast<std::size_t>(std::min<std::uint64_t>(want, d.ready()));
    for (std::size_t i = d.head; i < d.head + m; ++i) {
      if (s.invalid >= 0 && d.value(3, i) != 0) continue;
      const std::uint64_t record = d.taken + (i - d.head);
      if (colors != nullptr && d.colors)
        for (int k = 0; k < 3; ++k) (*colors)(kept, k) = s.color_byte(k, d.value(4 + static_cast<std::size_t>(k), i));
      out.row(kept++) = s.position({d.value(0, i), d.value(1, i), d.value(2, i)}).transpose();
      std::optional<std::uint64_t> where;
      if (const auto it = d.non_finite.find(record); it != d.non_finite.end())
        where = d.pages.to_physical(it->second);
      else if (d.constant[0] || d.constant[1] || d.constant[2])
        for (std::size_t k = 0; k < 3 && !where; ++k)
          if (d.constant[k] && !std::isfinite(*d.constant[k])) where = d.pages.to_physical(s.section.begin);
      located.push_back(where);
    }
    d.non_finite.erase(d.non_finite.begin(), d.non_finite.lower_bound(d.taken + m));
    d.head += m;
    d.taken += m;
    n -= m;
    if (d.head >= kCompactValues) {
      for (auto& v : d.values) v.erase(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(std::min(d.head, v.size())));
      d.head = 0;
    }
  }
  if (d.decoder) d.finish_up_to(d.pages.to_physical(d.decoder->position()));
  out.conservativeResize(kept, 3);
  if (colors != nullptr && d.colors) colors->conservativeResize(kept, 3);
}

std::vector<std::pair<std::uint64_t, std::uint64_t>> E57Points::finished_bytes() {
  return std::exchange(impl_->finished, {});
}

void E57Points::rewind() {
  impl_->decoder.reset();  // nothing of the scan being read is handed out again
  impl_->finished.clear();
  impl_->scan = 0;
  impl_->open_scan();
}

}  // namespace clustersurf::io
