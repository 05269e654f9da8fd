// Tree files: bit-exact round trips, reproducible bytes, and a table of corruptions that must
// each be rejected with a clear error.

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <limits>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

ClusterTree sample_tree(ProxyKind proxy) {
  BuildOptions o;
  o.proxy = proxy;
  o.threshold_mode = ThresholdMode::Relative;
  return build_cluster_tree(test::sample_torus(5000), o);
}

void fix_crc(std::string& b) {
  const auto crc =
      static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(b.data()), static_cast<uInt>(b.size() - 4)));
  std::memcpy(b.data() + b.size() - 4, &crc, 4);
}

template <class T>
void poke(std::string& b, std::size_t offset, T value) {
  std::memcpy(b.data() + offset, &value, sizeof(T));
}

// Offsets of fields in version 3 (docs/file-format.md).
constexpr std::size_t kVersionOffset = 8;
constexpr std::size_t kProxyKindOffset = 16;
constexpr std::size_t kSpacingOffset = 16 + 4 + 8 + 8 + 4 + 4 + 8 + 16 + 8 + 8 + 16 + 48 + 8;
constexpr std::size_t kOriginOffset = kSpacingOffset + 8;
constexpr std::size_t kNodeCountOffset = kOriginOffset + 24;
constexpr std::size_t kFirstNode = kNodeCountOffset + 8;
constexpr std::size_t kFlagsOffset = 16 + 4 + 8 + 8 + 4 + 4 + 8 + 4 + 4 + 4;

}  // namespace

TEST(TreeFile, RoundTripIsBitExactForEveryProxy) {
  for (ProxyKind kind : {ProxyKind::Plane, ProxyKind::Poly, ProxyKind::Quadric}) {
    const ClusterTree t = sample_tree(kind);
    const std::string bytes = serialize_tree(t);
    const ClusterTree u = deserialize_tree(bytes);
    EXPECT_EQ(serialize_tree(u), bytes);
    EXPECT_TRUE(u.parameters == t.parameters);
    ASSERT_EQ(u.nodes.size(), t.nodes.size());
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
      const auto &a = t.nodes[i], &b = u.nodes[i];
      EXPECT_EQ(a.parent, b.parent);
      EXPECT_EQ(a.depth, b.depth);
      EXPECT_EQ(a.point_count, b.point_count);
      EXPECT_EQ(a.rms_error, b.rms_error);
      EXPECT_EQ(a.extent, b.extent);
      EXPECT_EQ(a.support.radius, b.support.radius);
      EXPECT_EQ(a.bound.center, b.bound.center);
      const Eigen::Vector3d x(0.3, -0.2, 0.1);
      EXPECT_EQ(a.proxy.value(x), b.proxy.value(x));
    }
    EXPECT_EQ(u.point_leaf, t.point_leaf);
    EXPECT_EQ(u.point_spacing, t.point_spacing);
    EXPECT_GT(t.point_spacing, 0);
  }
}

// A crease leaf's side is 0 (concave, min) or 1 (convex, max), nothing else.
TEST(TreeFile, CreaseSideMustBeZeroOrOne) {
  PointCloud roof;
  roof.positions.resize(400, 3);
  for (int i = 0; i < 400; ++i) {
    const double x = (i % 20) / 9.5 - 1, y = (i / 20) / 9.5 - 1;
    roof.positions.row(i) << x, y, -0.5 * std::abs(x);
  }
  BuildOptions o;
  o.threshold_mode = ThresholdMode::Relative;
  const ClusterTree t = build_cluster_tree(roof, o);
  ASSERT_EQ(t.nodes.size(), 1u);
  ASSERT_EQ(t.nodes[0].proxy.kind(), ProxyKind::Crease);
  std::string b = serialize_tree(t);
  EXPECT_EQ(serialize_tree(deserialize_tree(b)), b);
  // The side is the crease's last number: node record (104 bytes before the proxy) + 12 doubles.
  poke<double>(b, kFirstNode + 104 + 12 * 8, 0.5);
  fix_crc(b);
  try {
    deserialize_tree(b, "bad.cstree");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("crease side must be 0 (concave) or 1 (convex)"), std::string::npos)
        << e.what();
  }
}

// Version 2 stores the input's median spacing, the one compute_stats() measures, so meshing at
// --resolution auto needs no points.
TEST(TreeFile, StoresTheInputsPointSpacing) {
  const PointCloud cloud = test::sample_torus(5000);
  const ClusterTree t = deserialize_tree(serialize_tree(build_cluster_tree(cloud)));
  EXPECT_EQ(t.point_spacing, compute_stats(cloud).median_spacing);
  for (const ClusterNode& n : t.nodes) EXPECT_GT(n.extent, 0);
}

// Version 3 stores the input's origin: a cloud far from zero is built next to zero, and its
// tree (and its meshes) know where it came from, bit for bit. A version-2 file (the same bytes
// without the origin) still loads, at origin 0.
TEST(TreeFile, StoresTheInputsOriginAndReadsVersion2) {
  PointCloud cloud = test::sample_torus(3000);
  cloud.positions.rowwise() += Eigen::RowVector3d(636590.49, 849216.55, 0.25);
  const Points far = cloud.positions;
  const Eigen::Vector3d shift = shift_to_origin(cloud);
  EXPECT_NEAR(shift.x(), 636590.49, 1.0);
  EXPECT_NEAR(shift.y(), 849216.55, 1.0);
  EXPECT_EQ(shift.z(), 0);  // near zero already
  EXPECT_LT(cloud.positions.cwiseAbs().maxCoeff(), 2.0);
  EXPECT_EQ(Points(cloud.positions.rowwise() + cloud.origin.transpose()), far);  // exact
  const ClusterTree built = build_cluster_tree(cloud);
  const std::string bytes = serialize_tree(built);
  const ClusterTree t = deserialize_tree(bytes);
  EXPECT_EQ(t.origin, cloud.origin);
  EXPECT_EQ(serialize_tree(t), bytes);
  std::string v2 = bytes;
  v2.erase(kOriginOffset, 24);
  poke<std::uint32_t>(v2, kVersionOffset, 2);
  fix_crc(v2);
  const ClusterTree old = deserialize_tree(v2);
  EXPECT_EQ(old.origin, Eigen::Vector3d::Zero());
  EXPECT_EQ(old.nodes.size(), t.nodes.size());
}

// The input's up axis (a survey's z) is kept, as a header flag: a tree of a z-up cloud loads
// z-up, and flipping the flag changes only that.
TEST(TreeFile, StoresTheInputsUpAxis) {
  PointCloud cloud = test::sample_torus(2000);
  const std::string y_up = serialize_tree(build_cluster_tree(cloud));
  cloud.up = UpAxis::Z;
  const ClusterTree built = build_cluster_tree(cloud);
  EXPECT_EQ(built.up, UpAxis::Z);
  const std::string z_up = serialize_tree(built);
  EXPECT_EQ(deserialize_tree(z_up).up, UpAxis::Z);
  EXPECT_EQ(deserialize_tree(y_up).up, UpAxis::Y);
  EXPECT_EQ(serialize_tree(deserialize_tree(z_up)), z_up);
  EXPECT_EQ(y_up.size(), z_up.size());
}

// A file written by version 1 (tests/data/bunny400_v1.cstree, from tests/data/bunny400.ply)
// still loads: no spacing (0), extents from the support radii, and today's build of the same
// points with version 1's algorithm gives the same tree.
TEST(TreeFile, ReadsVersion1Files) {
  const std::filesystem::path data(CLUSTERSURF_TEST_DATA);
  const ClusterTree old = load_tree(data / "bunny400_v1.cstree");
  EXPECT_EQ(old.input_points, 400u);
  EXPECT_EQ(old.point_spacing, 0);
  for (const ClusterNode& n : old.nodes) EXPECT_DOUBLE_EQ(n.extent * old.parameters.alpha, n.support.radius);
  // Version 1's algorithm: no crease leaves, principal frames, no leaf below min_points, the
  // noise from the positions alone, never corrected for the noise narrow fits follow, one noise
  // level everywhere, supports grown to hold 30 points.
  BuildOptions version1;
  version1.creases = false;
  version1.frames_from_normals = false;
  version1.fit_normals = false;
  version1.min_points = old.parameters.min_points;
  version1.alpha = old.parameters.alpha;
  version1.noise.facing_normals = false;
  version1.noise.noisy_width_ratio = 0;
  version1.noise.local = false;
  version1.support_points = 30;
  version1.support_factor = old.parameters.support_factor;
  const ClusterTree now = build_cluster_tree(read_point_cloud(data / "bunny400.ply"), version1);
  EXPECT_GT(now.point_spacing, 0);
  ASSERT_EQ(now.nodes.size(), old.nodes.size());
  EXPECT_EQ(now.point_leaf, old.point_leaf);
  for (std::size_t i = 0; i < now.nodes.size(); ++i) {
    EXPECT_EQ(now.nodes[i].support.center, old.nodes[i].support.center);
    // The same least-squares fits, solved since by the normal equations: equal up to rounding.
    EXPECT_NEAR(now.nodes[i].rms_error, old.nodes[i].rms_error, 1e-9 * old.nodes[i].rms_error);
  }
  EXPECT_NEAR(old.noise_sigma, now.noise_sigma, 1e-9 * old.noise_sigma);
  EXPECT_NEAR(old.error_threshold, now.error_threshold, 1e-9 * old.error_threshold);
}

TEST(TreeFile, SaveLoadThroughDiskAndSameBytesForSameInput) {
  test::TempDir dir;
  const ClusterTree t = sample_tree(ProxyKind::Poly);
  save_tree(dir / "a.cstree", t);
  save_tree(dir / "b.cstree", sample_tree(ProxyKind::Poly));
  EXPECT_EQ(test::read_file(dir / "a.cstree"), test::read_file(dir / "b.cstree"));
  EXPECT_EQ(serialize_tree(load_tree(dir / "a.cstree")), test::read_file(dir / "a.cstree"));
}

// A tree file larger than the writer's 4 MiB buffer is written in pieces, its checksum kept
// across them, and read back while its pages are released: the same bytes as one string.
TEST(TreeFile, LargeTreeWrittenInPiecesIsTheSameFile) {
  test::TempDir dir;
  BuildOptions o;
  o.keep_point_leaves = true;
  ClusterTree t = build_cluster_tree(test::sample_torus(20000), o);
  // Input points in no cluster (point-leaf entries -1, as outliers are) make the file larger
  // than the writer's 4 MB flush without building a larger tree.
  t.input_points = 2'500'000;
  t.point_leaf.resize(t.input_points, -1);
  const std::string bytes = serialize_tree(t);
  ASSERT_GT(bytes.size(), std::size_t{9} << 20);
  save_tree(dir / "large.cstree", t);
  EXPECT_EQ(test::read_file(dir / "large.cstree"), bytes);
  EXPECT_EQ(serialize_tree(load_tree(dir / "large.cstree")), bytes);
}

TEST(TreeFile, TreesDeeperThan63LevelsRoundTrip) {
  // A caterpillar of depth 100 (a heap index would need 2^100): each internal node has a leaf
  // (one point) on the left and the rest of the chain on the right.
  constexpr int kDepth = 100;
  ClusterTree t;
  t.input_points = kDepth + 1;
  t.bbox.extend(Eigen::Vector3d::Zero());
  t.bbox.extend(Eigen::Vector3d::Ones());
  for (int d = 0; d <= kDepth; ++d) {
    const auto chain = static_cast<std::int32_t>(t.nodes.size());
    ClusterNode internal;
    internal.point_count = static_cast<std::uint32_t>(kDepth + 1 - d);
    internal.proxy = PlaneProxy{};
    internal.support.radius = internal.bound.radius = 1;
    if (d < kDepth) {
      internal.left = chain + 1;
      internal.right = chain + 2;
    }
    t.nodes.push_back(internal);
    if (d < kDepth) {
      ClusterNode leaf = internal;
      leaf.point_count = 1;
      leaf.left = leaf.right = -1;
      t.nodes.push_back(leaf);
    }
  }
  const std::string bytes = serialize_tree(t);
  const ClusterTree u = deserialize_tree(bytes);
  EXPECT_EQ(u.depth(), static_cast<std::uint32_t>(kDepth));
  EXPECT_EQ(serialize_tree(u), bytes);
}

struct Corruption {
  const char* name;
  std::string (*make)(const std::string& good);
  const char* message;  // expected substring
};

TEST(TreeFile, CorruptedFilesAreRejected) {
  const std::string good = serialize_tree(sample_tree(ProxyKind::Poly));
  const Corruption table[] = {
      {"empty", [](const std::string&) { return std::string(); }, "bad magic"},
      {"not a tree", [](const std::string&) { return std::string("ply\nformat ascii 1.0\n"); }, "bad magic"},
      {"truncated header", [](const std::string& g) { return g.substr(0, 12); }, "truncated"},
      {"truncated middle", [](const std::string& g) { return g.substr(0, g.size() / 2); }, "checksum"},
      {"truncated last byte", [](const std::string& g) { return g.substr(0, g.size() - 1); }, "checksum"},
      {"flipped byte in a node",
       [](const std::string& g) {
         std::string b = g;
         b[kFirstNode + 40] ^= 0x10;
         return b;
       },
       "checksum"},
      {"flipped byte in the checksum",
       [](const std::string& g) {
         std::string b = g;
         b[b.size() - 2] ^= 1;
         return b;
       },
       "checksum"},
      {"wrong version",
       [](const std::string& g) {
         std::string b = g;
         poke<std::uint32_t>(b, kVersionOffset, 99);
         fix_crc(b);
         return b;
       },
       "unsupported tree file version 99"},
      {"unknown proxy kind",
       [](const std::string& g) {
         std::string b = g;
         b[kProxyKindOffset] = 9;
         fix_crc(b);
         return b;
       },
       "unknown proxy kind 9"},
      {"absurd node count",
       [](const std::string& g) {
         std::string b = g;
         poke<std::uint64_t>(b, kNodeCountOffset, 50'000'000'000ULL);
         fix_crc(b);
         return b;
       },
       "larger than the file can hold"},
      {"zero nodes",
       [](const std::string& g) {
         std::string b = g;
         poke<std::uint64_t>(b, kNodeCountOffset, 0);
         fix_crc(b);
         return b;
       },
       "no nodes"},
      {"child index out of range",
       [](const std::string& g) {
         std::string b = g;
         poke<std::int32_t>(b, kFirstNode + 4, 1 << 30);
         fix_crc(b);
         return b;
       },
       "invalid children"},
      {"wrong point count",
       [](const std::string& g) {
         std::string b = g;
         poke<std::uint32_t>(b, kFirstNode + 8, 7);
         fix_crc(b);
         return b;
       },
       "points but"},
      {"NaN error",
       [](const std::string& g) {
         std::string b = g;
         poke<double>(b, kFirstNode + 16, std::nan(""));
         fix_crc(b);
         return b;
       },
       "not a finite number"},
      {"negative point spacing",
       [](const std::string& g) {
         std::string b = g;
         poke<double>(b, kSpacingOffset, -0.5);
         fix_crc(b);
         return b;
       },
       "point spacing is negative"},
      {"negative cluster extent",
       [](const std::string& g) {
         std::string b = g;
         poke<double>(b, kFirstNode + 32, -1.0);
         fix_crc(b);
         return b;
       },
       "cluster extent is negative"},
      {"unknown option flags",
       [](const std::string& g) {
         std::string b = g;
         poke<std::uint32_t>(b, kFlagsOffset, 6);
         fix_crc(b);
         return b;
       },
       "unknown option flags 6"},
      {"a version from the future",
       [](const std::string& g) {
         std::string b = g;
         poke<std::uint32_t>(b, kVersionOffset, kTreeFileVersion + 1);
         fix_crc(b);
         return b;
       },
       "(this build reads versions 1 to 3)"},
      {"a non-finite origin",
       [](const std::string& g) {
         std::string b = g;
         poke<double>(b, kOriginOffset + 8, std::numeric_limits<double>::infinity());
         fix_crc(b);
         return b;
       },
       "not a finite number"},
      {"trailing garbage",
       [](const std::string& g) {
         std::string b = g;
         b.insert(b.size() - 4, "xxxx");
         fix_crc(b);
         return b;
       },
       "unexpected bytes"},
  };
  for (const auto& row : table) {
    const std::string bad = row.make(good);
    try {
      deserialize_tree(bad, "bad.cstree");
      ADD_FAILURE() << row.name << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(row.message), std::string::npos) << row.name << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.cstree"), std::string::npos) << row.name;
      EXPECT_TRUE(e.where().byte_offset.has_value()) << row.name;
    }
  }
}

TEST(TreeFile, MissingFileIsAnIoError) { EXPECT_THROW(load_tree("/nonexistent/tree.cstree"), IoError); }
