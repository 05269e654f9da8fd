// The .cstree binary format (docs/file-format.md): little-endian, versioned, CRC-32 protected,
// every field validated on load.

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>

#include "cluster/tree_codec.hpp"

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace clustersurf {

using detail::crc_of;
using detail::get_enum;
using detail::get_proxy;
using detail::get_sphere;
using detail::put_proxy;
using detail::Reader;
using detail::Writer;

namespace {

static_assert(std::endian::native == std::endian::little, "the tree file codec assumes a little-endian host");

constexpr char kMagic[8] = {'\x89', 'C', 'S', 'T', 'R', 'E', 'E', '\n'};
constexpr std::uint32_t kEndianTag = 0x01020304u;

/// The option flags of the header (version 2; the reserved 0 of version 1).
constexpr std::uint32_t kFlagCreases = 1;
constexpr std::uint32_t kFlagZUp = 2;  ///< ClusterTree::up is z

/// Number of doubles that encode each proxy kind (indexed by ProxyKind).
constexpr std::size_t kProxyDoubles[kProxyKinds] = {3, 6, 18, 14, 13};

/// Bytes of one node record for a proxy kind (for the "absurd count" check: the smallest).
constexpr std::size_t kNodeFixedBytes = 4 + 4 + 4 + 4 + 2 * 8 + 2 * 4 * 8;

}  // namespace

namespace {

void write_tree(Writer& w, const ClusterTree& tree) {
  w.raw(kMagic, sizeof kMagic);
  w.put(kTreeFileVersion);
  w.put(kEndianTag);
  const TreeParameters& p = tree.parameters;
  w.put(static_cast<std::uint8_t>(p.proxy)), w.put(static_cast<std::uint8_t>(p.splitter));
  w.put(static_cast<std::uint8_t>(p.metric)), w.put(static_cast<std::uint8_t>(p.threshold_mode));
  w.put(p.tolerance), w.put(p.noise_factor);
  w.put(p.min_points), w.put(p.max_depth);
  w.put(p.alpha);
  w.put(p.kstep), w.put(p.lloyd_restarts), w.put(p.proxy_lloyd_iterations);
  w.put((p.creases ? kFlagCreases : std::uint32_t{0}) | (tree.up == UpAxis::Z ? kFlagZUp : std::uint32_t{0}));
  w.put(p.support_factor);
  w.put(p.seed);
  w.put(tree.noise_sigma), w.put(tree.error_threshold);
  w.put_vec(tree.bbox.min), w.put_vec(tree.bbox.max);
  w.put(tree.input_points);
  w.put(tree.point_spacing);
  w.put_vec(tree.origin);
  w.put(static_cast<std::uint64_t>(tree.nodes.size()));
  for (const ClusterNode& n : tree.nodes) {
    w.put(n.left), w.put(n.right), w.put(n.point_count);
    w.put(static_cast<std::uint8_t>(n.proxy.kind())), w.put(std::uint8_t{0}), w.put(std::uint16_t{0});
    w.put(n.rms_error), w.put(n.max_error), w.put(n.extent);
    w.put_vec(n.support.center), w.put(n.support.radius);
    w.put_vec(n.bound.center), w.put(n.bound.radius);
    put_proxy(w, n.proxy);
  }
  w.put(static_cast<std::uint64_t>(tree.point_leaf.size()));
  for (std::int32_t leaf : tree.point_leaf) w.put(leaf);
  w.put(w.crc());
}

/// The tree in `bytes` (of `file`); with its mapping, the pages read are released as it goes.
ClusterTree parse_tree(std::string_view bytes, const std::filesystem::path& file, const io::MappedFile* mapped);

}  // namespace

std::string serialize_tree(const ClusterTree& tree) {
  Writer w;
  write_tree(w, tree);
  return std::move(w.bytes());
}

ClusterTree deserialize_tree(std::string_view bytes, const std::filesystem::path& file) {
  return parse_tree(bytes, file, nullptr);
}

namespace {

/// Checks the magic number, version, endianness tag and checksum of `bytes`; returns the version.
std::uint32_t read_header(Reader& r, std::string_view bytes, const io::MappedFile* mapped) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    r.fail_at(0, "not a clustersurf tree file (bad magic number)");
  for (std::size_t k = 0; k < sizeof kMagic; ++k) r.get<char>("magic");
  const std::size_t version_at = r.pos();
  const auto version = r.get<std::uint32_t>("format version");
  if (version < 1 || version > kTreeFileVersion)
    r.fail_at(version_at, "unsupported tree file version " + std::to_string(version) +
                              " (this build reads versions 1 to " + std::to_string(kTreeFileVersion) + ")");
  const std::size_t endian_at = r.pos();
  if (r.get<std::uint32_t>("endianness tag") != kEndianTag)
    r.fail_at(endian_at, "endianness tag mismatch (file written on an incompatible machine or corrupted)");
  if (bytes.size() < r.pos() + 4) r.fail("file is truncated");
  std::uint32_t stored_crc;
  std::memcpy(&stored_crc, bytes.data() + bytes.size() - 4, 4);
  const std::uint32_t crc = crc_of(bytes.substr(0, bytes.size() - 4), 0, mapped);
  if (crc != stored_crc) r.fail_at(bytes.size() - 4, "checksum mismatch: the file is corrupted or truncated");
  return version;
}

/// The build parameters and the tree's header fields.
void read_parameters(Reader& r, std::uint32_t version, ClusterTree& tree) {
  TreeParameters& p = tree.parameters;
  p.proxy = get_enum<ProxyKind>(r, 4, "proxy kind");
  p.splitter = get_enum<SplitterKind>(r, 2, "splitter");
  p.metric = get_enum<ErrorMetric>(r, 2, "error metric");
  p.threshold_mode = get_enum<ThresholdMode>(r, 3, "threshold mode");
  p.tolerance = r.finite("tolerance");
  p.noise_factor = r.finite("noise factor");
  p.min_points = r.get<std::uint32_t>("min points");
  p.max_depth = r.get<std::uint32_t>("max depth");
  p.alpha = r.finite("alpha");
  p.kstep = r.get<std::uint32_t>("kstep");
  p.lloyd_restarts = r.get<std::uint32_t>("lloyd restarts");
  p.proxy_lloyd_iterations = r.get<std::uint32_t>("proxy lloyd iterations");
  const std::size_t flags_at = r.pos();
  const auto flags = r.get<std::uint32_t>("flags");
  if ((flags & ~(kFlagCreases | kFlagZUp)) != 0 || (version < 2 && flags != 0))
    r.fail_at(flags_at, "unknown option flags " + std::to_string(flags));
  p.creases = (flags & kFlagCreases) != 0;
  tree.up = (flags & kFlagZUp) != 0 ? UpAxis::Z : UpAxis::Y;
  p.support_factor = r.finite("support factor");
  p.seed = r.get<std::uint64_t>("seed");
  tree.noise_sigma = r.finite("noise sigma");
  tree.error_threshold = r.finite("error threshold");
  tree.bbox.min = r.vec("bounding box");
  tree.bbox.max = r.vec("bounding box");
  tree.input_points = r.get<std::uint64_t>("input point count");
  if (version >= 2) {
    const std::size_t at = r.pos();
    tree.point_spacing = r.finite("point spacing");
    if (tree.point_spacing < 0) r.fail_at(at, "point spacing is negative");
  }
  if (version >= 3) tree.origin = r.vec("origin");
}

/// The nodes, each checked on its own; returns where each one starts in the file.
std::vector<std::size_t> read_nodes(Reader& r, std::uint32_t version, ClusterTree& tree, const io::MappedFile* mapped) {
  const TreeParameters& p = tree.parameters;
  const std::size_t count_at = r.pos();
  const auto node_count = r.get<std::uint64_t>("node count");
  if (node_count == 0) r.fail_at(count_at, "tree has no nodes");
  if (node_count > r.remaining() / (kNodeFixedBytes + (version >= 2 ? 8 : 0) + 3 * 8))
    r.fail_at(count_at, "node count " + std::to_string(node_count) + " is larger than the file can hold");
  tree.nodes.resize(node_count);
  const auto nodes = static_cast<std::int64_t>(node_count);
  std::vector<std::size_t> node_at(node_count);
  for (std::int64_t i = 0; i < nodes; ++i) {
    ClusterNode& n = tree.nodes[static_cast<std::size_t>(i)];
    if (mapped != nullptr && (i & 0xffff) == 0) mapped->release(0, r.pos());
    node_at[static_cast<std::size_t>(i)] = r.pos();
    n.left = r.get<std::int32_t>("node child");
    n.right = r.get<std::int32_t>("node child");
    if ((n.left < 0) != (n.right < 0) || (n.left >= 0 && (n.left != i + 1 || n.right <= n.left || n.right >= nodes)) ||
        n.left < -1 || n.right < -1)
      r.fail_at(node_at[static_cast<std::size_t>(i)], "node " + std::to_string(i) + " has invalid children " +
                                                          std::to_string(n.left) + ", " + std::to_string(n.right));
    n.point_count = r.get<std::uint32_t>("node point count");
    const ProxyKind kind = get_enum<ProxyKind>(r, version >= 2 ? kProxyKinds : 4, "proxy kind");
    r.get<std::uint8_t>("padding"), r.get<std::uint16_t>("padding");
    n.rms_error = r.finite("node error");
    n.max_error = r.finite("node error");
    if (version >= 2) {
      const std::size_t at = r.pos();
      n.extent = r.finite("cluster extent");
      if (n.extent < 0) r.fail_at(at, "cluster extent is negative");
    }
    n.support = get_sphere(r, "support sphere");
    // Version 1 stored no extent: the support radius was alpha × extent but where it grew to
    // cover enough points or shrank where the proxy failed.
    if (version < 2) n.extent = p.alpha > 0 ? n.support.radius / p.alpha : 0.0;
    n.bound = get_sphere(r, "bounding sphere");
    if (kProxyDoubles[static_cast<std::size_t>(kind)] * 8 > r.remaining()) r.fail("file is truncated inside a proxy");
    n.proxy = get_proxy(r, kind);
  }
  return node_at;
}

/// The nodes' topology: every node but the root is the child of exactly one node; parents and
/// depths follow; counts add up.
void check_topology(const Reader& r, ClusterTree& tree, const std::vector<std::size_t>& node_at) {
  const auto node_count = tree.nodes.size();
  const auto nodes = static_cast<std::int64_t>(node_count);
  std::vector<std::uint8_t> referenced(node_count, 0);
  for (std::int64_t i = 0; i < nodes; ++i) {
    ClusterNode& n = tree.nodes[static_cast<std::size_t>(i)];
    if (n.is_leaf()) {
      if (n.point_count == 0)
        r.fail_at(node_at[static_cast<std::size_t>(i)], "leaf " + std::to_string(i) + " has no points");
      continue;
    }
    for (std::int32_t c : {n.left, n.right}) {
      auto& child = tree.nodes[static_cast<std::size_t>(c)];
      if (referenced[static_cast<std::size_t>(c)]++ != 0)
        r.fail_at(node_at[static_cast<std::size_t>(i)], "node " + std::to_string(c) + " has two parents");
      child.parent = static_cast<std::int32_t>(i);
      child.depth = n.depth + 1;
    }
  }
  for (std::int64_t i = 1; i < nodes; ++i)
    if (referenced[static_cast<std::size_t>(i)] == 0)
      r.fail_at(node_at[static_cast<std::size_t>(i)], "node " + std::to_string(i) + " is not reachable from the root");
  // Pre-order: children come after parents, so sums can be checked in reverse.
  for (std::int64_t i = nodes - 1; i >= 0; --i) {
    const ClusterNode& n = tree.nodes[static_cast<std::size_t>(i)];
    if (n.is_leaf()) continue;
    const std::uint64_t sum = std::uint64_t{tree.nodes[static_cast<std::size_t>(n.left)].point_count} +
                              tree.nodes[static_cast<std::size_t>(n.right)].point_count;
    if (sum != n.point_count)
      r.fail_at(node_at[static_cast<std::size_t>(i)], "node " + std::to_string(i) + " counts " +
                                                          std::to_string(n.point_count) + " points but its children " +
                                                          std::to_string(sum));
  }
  if (tree.nodes[0].point_count > tree.input_points)
    r.fail_at(node_at[0], "root counts " + std::to_string(tree.nodes[0].point_count) + " points but the header says " +
                              std::to_string(tree.input_points) + " input points");
}

/// The point-leaf table, checked against the leaves' counts.
void read_point_leaves(Reader& r, ClusterTree& tree) {
  const auto node_count = tree.nodes.size();
  const auto nodes = static_cast<std::int64_t>(node_count);
  const std::size_t leaf_at = r.pos();
  const auto leaf_count = r.get<std::uint64_t>("point-leaf count");
  if (leaf_count != 0 && leaf_count != tree.input_points)
    r.fail_at(leaf_at, "point-leaf table has " + std::to_string(leaf_count) + " entries for " +
                           std::to_string(tree.input_points) + " points");
  if (leaf_count > (r.remaining() - 4) / 4) r.fail_at(leaf_at, "file is truncated inside the point-leaf table");
  tree.point_leaf.resize(leaf_count);
  std::vector<std::uint32_t> per_leaf(leaf_count != 0 ? node_count : 0, 0);
  std::uint64_t outliers = 0;  // entries -1: input points in no cluster
  for (auto& leaf : tree.point_leaf) {
    const std::size_t at = r.pos();
    leaf = r.get<std::int32_t>("point leaf");
    if (leaf == -1) {
      ++outliers;
      continue;
    }
    if (leaf < 0 || leaf >= nodes || !tree.nodes[static_cast<std::size_t>(leaf)].is_leaf())
      r.fail_at(at, "point-leaf entry " + std::to_string(leaf) + " is neither a leaf nor -1 (outlier)");
    ++per_leaf[static_cast<std::size_t>(leaf)];
  }
  if (leaf_count != 0 && outliers != tree.input_points - tree.nodes[0].point_count)
    r.fail_at(leaf_at, "point-leaf table marks " + std::to_string(outliers) + " outliers but the root leaves out " +
                           std::to_string(tree.input_points - tree.nodes[0].point_count) + " input points");
  for (std::size_t i = 0; i < per_leaf.size(); ++i)
    if (tree.nodes[i].is_leaf() && per_leaf[i] != tree.nodes[i].point_count)
      r.fail_at(leaf_at, "leaf " + std::to_string(i) + " has " + std::to_string(tree.nodes[i].point_count) +
                             " points but the point-leaf table gives it " + std::to_string(per_leaf[i]));
}

ClusterTree parse_tree(std::string_view bytes, const std::filesystem::path& file, const io::MappedFile* mapped) {
  Reader r(bytes, file);
  const std::uint32_t version = read_header(r, bytes, mapped);
  ClusterTree tree;
  read_parameters(r, version, tree);
  const std::vector<std::size_t> node_at = read_nodes(r, version, tree, mapped);
  check_topology(r, tree, node_at);
  read_point_leaves(r, tree);
  if (r.remaining() != 4) r.fail(std::to_string(r.remaining() - 4) + " unexpected bytes before the checksum");
  return tree;
}

}  // namespace

void save_tree(const std::filesystem::path& file, const ClusterTree& tree) {
  io::AtomicFile out(file);
  Writer w(&out);
  write_tree(w, tree);
  w.flush();
  out.commit();
}

ClusterTree load_tree(const std::filesystem::path& file) {
  const io::MappedFile mapped(file);
  return parse_tree(mapped.view(), file, &mapped);
}

}  // namespace clustersurf
