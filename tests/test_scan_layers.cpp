// Reconstruction of what registered and sparse scans deliver (reconstruct() end to end): two
// scans of one surface that interleave a spacing apart give one sheet, and a sparse closed scan
// with a share of flipped normals gives one closed surface facing out.

#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

constexpr double kRadius = 1.0;  // the cylinder the sheet is part of
constexpr double kHalfAngle = 0.8, kHalfLength = 1.0;

/// A scan of the cylinder patch (angle within ±kHalfAngle, z within ±kHalfLength): a grid of
/// n × n points jittered within their cells, moved `offset` along the normal (a scan's
/// misregistration), with its grid's normals and range noise `sigma`.
PointCloud patch_scan(int n, double offset, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(0, 1);
  std::normal_distribution<double> g(0, 1);
  PointCloud c;
  c.positions.resize(n * n, 3);
  c.normals.resize(n * n, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double a = -kHalfAngle + 2 * kHalfAngle * (i + jitter(rng)) / n;
      const double z = -kHalfLength + 2 * kHalfLength * (j + jitter(rng)) / n;
      const Eigen::Vector3d normal(std::cos(a), std::sin(a), 0);
      const double r = kRadius + offset + sigma * g(rng);
      c.positions.row(i * n + j) = Eigen::Vector3d(r * normal.x(), r * normal.y(), z).transpose();
      c.normals.row(i * n + j) = normal.transpose();
    }
  return c;
}

PointCloud joined(const PointCloud& a, const PointCloud& b) {
  PointCloud c;
  c.positions.resize(a.size() + b.size(), 3);
  c.normals.resize(a.size() + b.size(), 3);
  c.positions << a.positions, b.positions;
  c.normals << a.normals, b.normals;
  return c;
}

}  // namespace

TEST(ScanLayers, TwoScansASpacingApartAreOneSheet) {
  // Two scans of 60 × 60 points: spacing about 0.027 along the arc and 0.033 along z; the
  // second lies one spacing (0.03) outside the first.
  constexpr int kGrid = 60;
  constexpr double kOffset = 0.03, kSigma = 0.002;
  const PointCloud one = patch_scan(kGrid, 0, kSigma, 1);
  const PointCloud both = joined(one, patch_scan(kGrid, kOffset, kSigma, 2));
  const Reconstruction single = reconstruct(one);
  const Reconstruction layered = reconstruct(both);
  ASSERT_TRUE(single.mesh && layered.mesh);
  const MeshTopology a = mesh_topology(single.mesh->mesh), b = mesh_topology(layered.mesh->mesh);
  double mean = 0, worst = 0;
  const TriangleMesh& mesh = layered.mesh->mesh;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const double d = std::abs(mesh.vertices.row(v).head<2>().norm() - (kRadius + kOffset / 2));
    mean += d;
    worst = std::max(worst, d);
  }
  mean /= static_cast<double>(std::max<Eigen::Index>(1, mesh.vertices.rows()));
  std::cout << "one scan: " << a.components << " component(s), boundary " << a.boundary_length
            << "; two interleaved: " << b.components << " component(s), boundary " << b.boundary_length
            << ", distance to the middle surface mean " << mean << ", largest " << worst << "\n";
  EXPECT_EQ(b.components, 1u);
  // The boundary is the patch's rim, as long as one scan's (a jittered grid's ragged edge; the
  // straight rim would be 2 × (1.6 + 2) = 7.2), not flaps or holes.
  EXPECT_LT(b.boundary_length, 1.15 * a.boundary_length);
  // One sheet between the layers, not two sheets nor a blend torn between them.
  EXPECT_LT(mean, 0.5 * kOffset);
  EXPECT_LT(worst, 1.5 * kOffset);
}

TEST(ScanLayers, ASparseSphereWithFlippedNormalsIsOneClosedSurfaceFacingOut) {
  PointCloud cloud = test::sample_sphere(1000);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  int flipped = 0;
  for (Eigen::Index i = 0; i < cloud.normals.rows(); ++i)
    if (u(rng) < 0.05) cloud.normals.row(i) *= -1, ++flipped;
  const Reconstruction r = reconstruct(cloud);
  ASSERT_TRUE(r.mesh);
  const MeshTopology t = mesh_topology(r.mesh->mesh);
  std::cout << flipped << " of 1,000 normals flipped: " << t.components << " component(s), " << t.boundary_edges
            << " boundary edges, signed volume " << t.signed_volume << " (the sphere's 4.19)\n";
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.boundary_edges, 0u);
  // Outward, and within the chords' deficit of the sphere's volume (a mesh of cells of two
  // spacings lies inside it).
  EXPECT_NEAR(t.signed_volume, 4 * M_PI / 3, 0.15);
}
