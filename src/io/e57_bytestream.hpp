#pragma once
// E57 CompressedVector binary sections: the section header, data packets and the bit-packed
// bytestreams (one per prototype field) whose values run on from packet to packet.

#include "io/e57_pages.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace clustersurf::io::e57 {

/// How one prototype field is stored in its bytestream: raw little-endian IEEE floats, or
/// integers of `bits` bits packed least significant bit first (0 bits: a constant).
struct FieldCodec {
  enum class Kind { Float32, Float64, Integer };
  Kind kind = Kind::Float64;
  unsigned bits = 64;
  /// Integer and ScaledInteger: value = (raw + minimum) * scale + offset.
  std::int64_t minimum = 0;
  double scale = 1.0;
  double offset = 0.0;

  /// The value that the raw bits `raw` stand for (never undefined behaviour, any bits).
  double value(std::uint64_t raw) const noexcept;
};

/// Receives one value of a field: its record index, the value and the logical offset of the
/// value's first byte (for messages).
using FieldSink = std::function<void(std::uint64_t record, double value, std::uint64_t logical)>;

/// One bytestream: how it is coded and where its values go (an empty sink skips it).
struct StreamField {
  FieldCodec codec;
  FieldSink sink;
};

/// A CompressedVector's binary section in logical offsets: [begin, end), first data packet at data.
struct Section {
  std::uint64_t begin = 0;
  std::uint64_t end = 0;
  std::uint64_t data = 0;
};

/// Opens the binary section at physical offset `file_offset` and checks it: inside the file,
/// section id 1, first data packet inside it (when there are records), and room for
/// `record_count` records of `bits_per_record` bits (at least 1 counted), so that the caller
/// may allocate that many records. Errors name `where` (the XML element) or the section.
Section open_section(const PagedFile& pages, std::uint64_t file_offset, std::uint64_t record_count,
                     std::uint64_t bits_per_record, std::uint64_t where);

/// Decodes `record_count` records from the packets of `section` a data packet at a time: every
/// field with a sink gets each of its values once, in record order, the values of a packet as
/// it is decoded. `fields` are the bytestreams in prototype order. Throws InputError when a
/// packet or buffer reaches past its container or the data end too early. Holds references to
/// `pages` and `section`.
class RecordDecoder {
 public:
  RecordDecoder(const PagedFile& pages, const Section& section, std::uint64_t record_count,
                std::vector<StreamField> fields);
  ~RecordDecoder();
  RecordDecoder(RecordDecoder&&) noexcept;
  RecordDecoder& operator=(RecordDecoder&&) noexcept;

  /// Decodes packets up to and including the next data packet; false (and nothing decoded)
  /// once every field with a sink has had all its values.
  bool next_packet();
  /// The logical offset of the next packet: no byte before it in the section is read again.
  std::uint64_t position() const noexcept;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// RecordDecoder run to the end.
void decode_records(const PagedFile& pages, const Section& section, std::uint64_t record_count,
                    const std::vector<StreamField>& fields);

}  // namespace clustersurf::io::e57
