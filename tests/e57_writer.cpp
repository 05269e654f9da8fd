// The minimal E57 writer of the tests and benchmarks; see e57_writer.hpp.

#include "e57_writer.hpp"

#include <algorithm>
#include <bit>

namespace clustersurf::test {

std::uint32_t crc32c(const char* p, std::size_t n) {
  std::uint32_t c = 0xFFFFFFFFU;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= static_cast<unsigned char>(p[i]);
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0x82F63B78U & (0U - (c & 1U)));  // branch-free: the bit decides the xor
  }
  return c ^ 0xFFFFFFFFU;
}

void put_le(std::string& s, std::size_t at, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s[at + static_cast<std::size_t>(i)] = static_cast<char>((v >> (8 * i)) & 0xFF);
}

void append_le(std::string& s, std::uint64_t v, int bytes) {
  s.append(static_cast<std::size_t>(bytes), '\0');
  put_le(s, s.size() - static_cast<std::size_t>(bytes), v, bytes);
}

void refresh_crcs(std::string& file, std::size_t page) {
  for (std::size_t p = 0; p + page <= file.size(); p += page) {
    const std::uint32_t c = crc32c(file.data() + p, page - 4);
    for (int i = 0; i < 4; ++i) file[p + page - 4 + static_cast<std::size_t>(i)] = static_cast<char>(c >> (24 - 8 * i));
  }
}

TestField float_field(const std::string& name, const std::vector<double>& v, bool single) {
  TestField f{"<" + name + " type=\"Float\"" + (single ? " precision=\"single\"" : "") + "/>", single ? 32U : 64U, {}};
  f.raw.reserve(v.size());
  for (double x : v)
    f.raw.push_back(single ? std::bit_cast<std::uint32_t>(static_cast<float>(x)) : std::bit_cast<std::uint64_t>(x));
  return f;
}

TestField int_field(const std::string& name, std::int64_t lo, std::int64_t hi, const std::vector<std::int64_t>& v,
                    const std::string& scale) {
  const std::string type = scale.empty() ? "Integer" : "ScaledInteger";
  TestField f{"<" + name + " type=\"" + type + "\" minimum=\"" + std::to_string(lo) + "\" maximum=\"" +
                  std::to_string(hi) + "\" " + scale + "/>",
              static_cast<unsigned>(std::bit_width(static_cast<std::uint64_t>(hi - lo))),
              {}};
  f.raw.reserve(v.size());
  for (std::int64_t x : v) f.raw.push_back(static_cast<std::uint64_t>(x - lo));
  return f;
}

std::string pack(const TestField& f) {
  std::string out((f.raw.size() * f.bits + 7) / 8, '\0');
  std::uint64_t bit = 0;
  for (std::uint64_t v : f.raw) {
    // Up to 8 bits at a time: as many as are left of the value and of the current byte.
    for (unsigned b = 0; b < f.bits;) {
      const unsigned shift = static_cast<unsigned>(bit % 8), take = std::min(8U - shift, f.bits - b);
      const auto part = static_cast<unsigned>((v >> b) & ((1U << take) - 1U));
      out[bit / 8] = static_cast<char>(static_cast<unsigned char>(out[bit / 8]) | (part << shift));
      b += take;
      bit += take;
    }
  }
  return out;
}

TestFile write_e57(const std::vector<TestScan>& scans, const WriteOptions& o) {
  const std::size_t data = o.page - 4;
  const auto phys = [&](std::uint64_t l) { return l / data * o.page + l % data; };
  TestFile out;
  std::string logical(48, '\0');
  std::string xml =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<e57Root type=\"Structure\" "
      "xmlns=\"http://www.astm.org/COMMIT/E57/2010-e57-v1.0\">\n"
      "<formatName type=\"String\"><![CDATA[ASTM E57 3D Imaging Data File]]></formatName>\n"
      "<data3D type=\"Vector\" allowHeterogeneousChildren=\"1\">\n";
  for (const TestScan& scan : scans) {
    const std::size_t begin = logical.size(), records = scan.fields.front().raw.size();
    logical.append(32, '\0');
    std::vector<std::string> streams;
    std::size_t stream_bytes = 0;
    for (const TestField& f : scan.fields) streams.push_back(pack(f)), stream_bytes += streams.back().size();
    logical.reserve(logical.size() + stream_bytes + stream_bytes / 8 + 4096);
    // A packet holds at most 64 KiB: its header (6 bytes, 2 per buffer length), the buffers and
    // up to 3 bytes of padding.
    const std::size_t chunk =
        std::min(o.chunk, (65536 - 6 - 2 * streams.size() - 3) / std::max<std::size_t>(streams.size(), 1));
    std::vector<std::size_t> cursor(streams.size(), 0);
    bool first = true;
    std::string packet;
    for (bool more = true; more || first;) {
      const std::size_t start = logical.size();
      if (first) out.packets.push_back(phys(start));
      packet.assign("\x01\x00LL", 4);
      append_le(packet, streams.size(), 2);
      std::vector<std::size_t> n(streams.size());
      for (std::size_t i = 0; i < streams.size(); ++i) {
        n[i] = std::min(chunk, streams[i].size() - cursor[i]);
        append_le(packet, n[i], 2);
      }
      for (std::size_t i = 0; i < streams.size(); ++i) {
        packet.append(streams[i], cursor[i], n[i]);
        cursor[i] += n[i];
      }
      while (packet.size() % 4 != 0) packet.push_back('\0');
      put_le(packet, 2, packet.size() - 1, 2);
      logical += packet;
      if (first && o.extra_packets) {
        logical += std::string("\x02\x00\x07\x00\x00\x00\x00\x00", 8);  // empty packet, 8 bytes
        std::string index(16, '\0');                                    // index packet, no entries
        put_le(index, 2, 15, 2);
        logical += index;
      }
      first = false;
      more = false;
      for (std::size_t i = 0; i < streams.size(); ++i) more = more || cursor[i] < streams[i].size();
    }
    logical[begin] = 1;
    put_le(logical, begin + 8, logical.size() - begin, 8);
    put_le(logical, begin + 16, phys(begin + 32), 8);
    out.sections.push_back(phys(begin));
    xml += "<vectorChild type=\"Structure\">\n" + scan.extra + "\n<points type=\"CompressedVector\" fileOffset=\"" +
           std::to_string(phys(begin)) + "\" recordCount=\"" + scan.record_count.value_or(std::to_string(records)) +
           "\">\n<prototype type=\"Structure\">\n";
    for (const TestField& f : scan.fields) xml += f.xml + "\n";
    xml += "</prototype>\n<codecs type=\"Vector\" allowHeterogeneousChildren=\"1\"/>\n</points>\n</vectorChild>\n";
  }
  xml += "</data3D>\n" + o.xml_tail + "</e57Root>\n";
  const std::size_t xml_start = logical.size();
  logical += xml;
  const std::size_t pages = (logical.size() + data - 1) / data;
  logical.resize(pages * data, '\0');
  logical.replace(0, 8, "ASTM-E57");
  put_le(logical, 8, 1, 4);
  put_le(logical, 16, pages * o.page, 8);
  put_le(logical, 24, phys(xml_start), 8);
  put_le(logical, 32, xml.size(), 8);
  put_le(logical, 40, o.page, 8);
  out.bytes.reserve(pages * o.page);
  for (std::size_t p = 0; p < pages; ++p) out.bytes.append(logical, p * data, data).append("CRC!");
  refresh_crcs(out.bytes, o.page);
  out.xml = phys(xml_start);
  return out;
}

}  // namespace clustersurf::test
