// E57 CompressedVector sections: header, data/index/empty packets, bit-unpacking of the
// bytestreams with values carried over from one packet to the next; see e57_bytestream.hpp.

#include "io/e57_bytestream.hpp"

#include <algorithm>
#include <bit>
#include <string>

namespace clustersurf::io::e57 {

namespace {

constexpr std::uint64_t kSectionHeaderBytes = 32;

/// The little-endian unsigned integer of sizeof(T) bytes at `p`.
template <class T>
T load_le(const unsigned char* p) {
  T v = 0;
  for (std::size_t i = sizeof(T); i-- > 0;) v = static_cast<T>((v << 8) | p[i]);
  return v;
}

/// A bytestream being decoded: the bytes not yet used (carried from earlier packets, then the
/// current packet's buffer), the next bit to read and how many records were produced.
struct StreamState {
  std::vector<unsigned char> pending;
  std::uint64_t bit = 0;
  std::uint64_t carried = 0;          // how many leading bytes of `pending` came from earlier packets
  std::uint64_t carried_logical = 0;  // where the first of those was
  std::uint64_t buffer_logical = 0;   // where the current packet's buffer starts
  std::uint64_t done = 0;

  std::uint64_t logical_of(std::uint64_t byte) const {
    return byte < carried ? carried_logical + byte : buffer_logical + (byte - carried);
  }
};

/// The `w` (<= 64) bits starting at bit `bit` of `p`, least significant first; the caller
/// guarantees they are inside the buffer.
std::uint64_t extract(const unsigned char* p, std::uint64_t bit, unsigned w) {
  const std::uint64_t byte = bit >> 3;
  const unsigned shift = static_cast<unsigned>(bit & 7U), need = (shift + w + 7) / 8;
  std::uint64_t lo = 0;
  for (unsigned i = 0; i < std::min(need, 8U); ++i) lo |= std::uint64_t{p[byte + i]} << (8 * i);
  std::uint64_t v = lo >> shift;
  if (need == 9) v |= std::uint64_t{p[byte + 8]} << (64 - shift);
  return w < 64 ? v & ((std::uint64_t{1} << w) - 1) : v;
}

/// Hands every whole value in `s.pending` (up to `record_count`) to the field's sink, then keeps
/// the unused tail bytes for the next packet.
void drain(StreamState& s, const StreamField& f, std::uint64_t record_count) {
  const unsigned w = f.codec.bits;
  const std::uint64_t total = s.pending.size() * 8;
  while (s.done < record_count && total - s.bit >= w) {
    f.sink(s.done, f.codec.value(extract(s.pending.data(), s.bit, w)), s.logical_of(s.bit / 8));
    s.bit += w;
    ++s.done;
  }
  const std::uint64_t used = s.bit / 8;
  s.carried_logical = s.logical_of(used);
  s.pending.erase(s.pending.begin(), s.pending.begin() + static_cast<std::ptrdiff_t>(used));
  s.carried = s.pending.size();
  s.bit %= 8;
}

}  // namespace

double FieldCodec::value(std::uint64_t raw) const noexcept {
  switch (kind) {
    case Kind::Float32:
      return static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(raw)));
    case Kind::Float64:
      return std::bit_cast<double>(raw);
    case Kind::Integer:
      break;
  }
  const auto v = static_cast<std::int64_t>(raw + static_cast<std::uint64_t>(minimum));  // wraps, never UB
  return static_cast<double>(v) * scale + offset;
}

Section open_section(const PagedFile& pages, std::uint64_t file_offset, std::uint64_t record_count,
                     std::uint64_t bits_per_record, std::uint64_t where) {
  Section s;
  s.begin = pages.to_logical(file_offset, "points fileOffset", where);
  const std::uint64_t physical = pages.to_physical(s.begin);
  unsigned char h[kSectionHeaderBytes];
  pages.read(s.begin, sizeof h, h);
  if (h[0] != 1) pages.fail(physical, "section id is " + std::to_string(h[0]) + ", not 1 (CompressedVector)");
  const auto length = load_le<std::uint64_t>(h + 8);
  if (length < kSectionHeaderBytes || length > pages.logical_size() - s.begin)
    pages.fail(physical + 8, "section length " + std::to_string(length) +
                                 " is shorter than its header or reaches past the end of the file");
  s.end = s.begin + length;
  const std::uint64_t capacity = (length - kSectionHeaderBytes) * 8 / std::max<std::uint64_t>(bits_per_record, 1);
  if (record_count > capacity)
    pages.fail(where, "recordCount " + std::to_string(record_count) + " is more than the " + std::to_string(length) +
                          "-byte section at byte " + std::to_string(file_offset) + " can hold (" +
                          std::to_string(bits_per_record) + " bits per record)");
  if (record_count == 0) return s;
  s.data = pages.to_logical(load_le<std::uint64_t>(h + 16), "dataPhysicalOffset", physical + 16);
  if (s.data < s.begin + kSectionHeaderBytes || s.data >= s.end)
    pages.fail(physical + 16, "dataPhysicalOffset is outside its section");
  return s;
}

struct RecordDecoder::State {
  const PagedFile& pages;
  const Section& section;
  std::uint64_t record_count;
  std::vector<StreamField> fields;
  std::vector<StreamState> streams;
  std::size_t remaining = 0;  // fields with a sink still short of values
  std::uint64_t pos = 0;      // logical offset of the next packet
  std::vector<unsigned char> lengths;

  /// Decodes the packet at `pos` and moves past it; true when it was a data packet.
  bool packet();
};

RecordDecoder::RecordDecoder(const PagedFile& pages, const Section& section, std::uint64_t record_count,
                             std::vector<StreamField> fields)
    : state_(std::make_unique<State>(State{pages, section, record_count, std::move(fields), {}, 0, section.data, {}})) {
  State& d = *state_;
  d.streams.resize(d.fields.size());
  for (std::size_t i = 0; i < d.fields.size(); ++i) {
    if (!d.fields[i].sink) continue;
    if (d.fields[i].codec.bits == 0) {  // a constant: no bytes in the stream
      for (std::uint64_t r = 0; r < record_count; ++r) d.fields[i].sink(r, d.fields[i].codec.value(0), section.begin);
      d.streams[i].done = record_count;
    } else if (record_count > 0) {
      ++d.remaining;
    }
  }
}

RecordDecoder::~RecordDecoder() = default;
RecordDecoder::RecordDecoder(RecordDecoder&&) noexcept = default;
RecordDecoder& RecordDecoder::operator=(RecordDecoder&&) noexcept = default;

std::uint64_t RecordDecoder::position() const noexcept { return state_->pos; }

bool RecordDecoder::next_packet() {
  State& d = *state_;
  while (d.remaining > 0)
    if (d.packet()) return true;
  return false;
}

bool RecordDecoder::State::packet() {
  const std::uint64_t at = pages.to_physical(pos);
  if (section.end - pos < 4)
    pages.fail(at, "section ends before all " + std::to_string(record_count) + " records were read");
  unsigned char h[6];
  pages.read(pos, 4, h);
  const std::uint64_t length = std::uint64_t{load_le<std::uint16_t>(h + 2)} + 1;
  if (length < 4 || length > section.end - pos)
    pages.fail(at, "packet of " + std::to_string(length) + " bytes reaches past the end of its section");
  if (h[0] == 0 || h[0] == 2) {  // index or empty packet
    pos += length;
    return false;
  }
  if (h[0] != 1) pages.fail(at, "unknown packet type " + std::to_string(h[0]));
  if (length < 6) pages.fail(at, "data packet of " + std::to_string(length) + " bytes is shorter than its header");
  pages.read(pos + 4, 2, h + 4);
  const std::uint64_t count = load_le<std::uint16_t>(h + 4);
  if (count != fields.size())
    pages.fail(at + 4, "data packet has " + std::to_string(count) + " bytestreams but the prototype has " +
                           std::to_string(fields.size()) + " fields");
  const std::uint64_t header = 6 + 2 * count;
  if (header > length) pages.fail(at + 4, "data packet header is longer than the packet");
  lengths.resize(2 * count);
  pages.read(pos + 6, lengths.size(), lengths.data());
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < count; ++i) sum += load_le<std::uint16_t>(lengths.data() + 2 * i);
  if (sum > length - header)
    pages.fail(at + 6, "bytestream buffers of " + std::to_string(sum) + " bytes do not fit in the " +
                           std::to_string(length) + "-byte packet");
  std::uint64_t buffer = pos + header;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t n = load_le<std::uint16_t>(lengths.data() + 2 * i);
    StreamState& s = streams[i];
    if (fields[i].sink && s.done < record_count && n > 0) {
      s.buffer_logical = buffer;
      const std::size_t old = s.pending.size();
      s.pending.resize(old + n);
      pages.read(buffer, n, s.pending.data() + old);
      drain(s, fields[i], record_count);
      if (s.done == record_count) --remaining;
    }
    buffer += n;
  }
  pos += length;
  return true;
}

void decode_records(const PagedFile& pages, const Section& section, std::uint64_t record_count,
                    const std::vector<StreamField>& fields) {
  RecordDecoder decoder(pages, section, record_count, fields);
  while (decoder.next_packet()) {}
}

}  // namespace clustersurf::io::e57
