// libFuzzer target: the .cstree loader. Each input is tried as it is (the checksum rejects almost
// every mutation) and with its trailing CRC-32 recomputed, so that the fuzzer reaches the
// validation of the header, the nodes, the topology and the point-leaf table.

#include "fuzz_checks.hpp"

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>

#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace {

/// A loaded tree's structure as the loader promises it: children in range and after their
/// parent (pre-order), parents and depths consistent, point-leaf entries naming leaves, extents
/// and spacing not negative. The corpus holds files of both versions.
void check_tree(const clustersurf::ClusterTree& t) {
  using clustersurf::fuzz::require;
  const auto n = static_cast<std::int64_t>(t.nodes.size());
  require(n > 0 && t.nodes[0].parent < 0);
  require(t.point_spacing >= 0);
  for (std::int64_t i = 0; i < n; ++i) {
    const auto& node = t.nodes[static_cast<std::size_t>(i)];
    require(node.extent >= 0);
    if (node.is_leaf()) continue;
    for (std::int32_t c : {node.left, node.right}) {
      require(c > i && c < n);
      const auto& child = t.nodes[static_cast<std::size_t>(c)];
      require(child.parent == i && child.depth == node.depth + 1);
    }
  }
  for (std::int32_t leaf : t.point_leaf)
    require(leaf >= 0 && leaf < n && t.nodes[static_cast<std::size_t>(leaf)].is_leaf());
}

void load(std::string_view bytes) {
  try {
    check_tree(clustersurf::deserialize_tree(bytes, "fuzz.cstree"));
  } catch (const clustersurf::InputError&) {}
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  load(bytes);
  if (size < 8) return 0;
  std::string fixed(bytes);
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(fixed.data()), static_cast<uInt>(fixed.size() - 4)));
  std::memcpy(fixed.data() + fixed.size() - 4, &crc, 4);
  load(fixed);
  return 0;
}
