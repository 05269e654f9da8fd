#pragma once
// A minimal E57 writer for the tests and the benchmarks: one CompressedVector section per scan
// (Float, Integer and ScaledInteger fields, bit-packed), data packets of at most 64 KiB, the
// XML section, and pages with their CRC-32C. Fast enough for millions of points; it shares no
// code with the reader, so it can catch the reader's mistakes.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf::test {

/// CRC-32C (Castagnoli), bit by bit (independent of the reader's table-driven one).
std::uint32_t crc32c(const char* p, std::size_t n);

/// Stores the low `bytes` bytes of `v` little-endian at `s[at]`.
void put_le(std::string& s, std::size_t at, std::uint64_t v, int bytes);
/// Appends the low `bytes` bytes of `v` little-endian to `s`.
void append_le(std::string& s, std::uint64_t v, int bytes);

/// Rewrites every page's CRC (big-endian, as libE57 stores it) after a test patched bytes.
void refresh_crcs(std::string& file, std::size_t page = 1024);

/// A prototype field: its XML element, bits per record and the raw bits of every record.
struct TestField {
  std::string xml;
  unsigned bits;
  std::vector<std::uint64_t> raw;
};

/// A Float field (double precision, or single) holding `v`.
TestField float_field(const std::string& name, const std::vector<double>& v, bool single = false);

/// An Integer (scale empty) or ScaledInteger field holding the integers `v` in [lo, hi];
/// `scale` is more XML attributes (e.g. `scale="0.001" offset="10"`).
TestField int_field(const std::string& name, std::int64_t lo, std::int64_t hi, const std::vector<std::int64_t>& v,
                    const std::string& scale = "");

/// One scan: its fields (all with the same number of records) and more XML.
struct TestScan {
  TestScan(std::vector<TestField> f, std::string x = {}) : fields(std::move(f)), extra(std::move(x)) {}
  std::vector<TestField> fields;
  std::string extra;                        // XML inside the scan (pose, limits)
  std::optional<std::string> record_count;  // replaces the recordCount attribute
};

/// How write_e57 lays the file out.
struct WriteOptions {
  std::size_t page = 1024;
  std::size_t chunk = 4096;    // bytes of each bytestream per data packet, at most (fewer when
                               // a packet would otherwise exceed 64 KiB)
  bool extra_packets = false;  // an empty and an index packet after the first data packet
  std::string xml_tail;        // more XML inside <e57Root>
};

/// A written file and where its parts are.
struct TestFile {
  std::string bytes;
  std::vector<std::uint64_t> sections;  // physical offsets of the binary sections
  std::vector<std::uint64_t> packets;   // physical offsets of each section's first data packet
  std::uint64_t xml = 0;
};

/// `f`'s values bit-packed, least significant bit first, as libE57 writes a bytestream.
std::string pack(const TestField& f);

/// The E57 file of `scans`: header, one binary section per scan, the XML, page CRCs.
TestFile write_e57(const std::vector<TestScan>& scans, const WriteOptions& o = {});

}  // namespace clustersurf::test
