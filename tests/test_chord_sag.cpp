// Vertices offset by their triangles' mean chord sag (src/mesh/chord_sag.cpp): on a sphere the
// mesh's mean distance and volume error fall; flat parts, creases and fixed vertices stay; the
// same bits for any numbering.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/mesh/mesh_check.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <vector>

#include "mesh/chord_sag.hpp"
#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// test::icosphere(levels) with its exact normals.
TriangleMesh icosphere(int levels) {
  TriangleMesh mesh = test::icosphere(levels);
  mesh.normals = mesh.vertices;
  return mesh;
}

/// The area-weighted mean distance to the unit sphere of points spread over the triangles.
double mean_distance_to_unit_sphere(const TriangleMesh& mesh) {
  constexpr int kSteps = 12;
  double sum = 0, area = 0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose(),
                          b = mesh.vertices.row(mesh.triangles(t, 1)).transpose(),
                          c = mesh.vertices.row(mesh.triangles(t, 2)).transpose();
    const double w = 0.5 * (b - a).cross(c - a).norm();
    double d = 0;
    int count = 0;
    for (int i = 0; i < kSteps; ++i)
      for (int j = 0; i + j < kSteps; ++j, ++count) {
        const double u = (i + 1.0 / 3) / kSteps, s = (j + 1.0 / 3) / kSteps;
        d += std::abs((a + u * (b - a) + s * (c - a)).norm() - 1);
      }
    sum += w * d / count;
    area += w;
  }
  return sum / area;
}

}  // namespace

TEST(ChordSag, BringsASphereMeshCloserAndKeepsItsVolume) {
  TriangleMesh mesh = icosphere(4);  // 5,120 triangles
  const double before = mean_distance_to_unit_sphere(mesh);
  const double volume_error_before = std::abs(mesh_topology(mesh).signed_volume - 4 * std::numbers::pi / 3);
  const double mean_offset = detail::offset_chord_sag(mesh);
  const double after = mean_distance_to_unit_sphere(mesh);
  const double volume_error_after = std::abs(mesh_topology(mesh).signed_volume - 4 * std::numbers::pi / 3);
  // The chords lie inside: every vertex goes out, by about the mean sag e²/(8R) of an edge e.
  double shortest = INFINITY, longest = 0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const double e =
          (mesh.vertices.row(mesh.triangles(t, k)) - mesh.vertices.row(mesh.triangles(t, (k + 1) % 3))).norm();
      shortest = std::min(shortest, e), longest = std::max(longest, e);
    }
  EXPECT_GT(mean_offset, 0.8 * shortest * shortest / 8);
  EXPECT_LT(mean_offset, 1.2 * longest * longest / 8);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) EXPECT_GT(mesh.vertices.row(v).norm(), 1);
  std::cout << "icosphere: mean distance " << before << " -> " << after << ", volume error " << volume_error_before
            << " -> " << volume_error_after << "\n";
  EXPECT_LT(after, 0.3 * before);
  EXPECT_LT(volume_error_after, 0.01 * volume_error_before)
      << "volume error " << volume_error_before << " -> " << volume_error_after;
}

TEST(ChordSag, LeavesFlatPartsCreasesAndFixedVerticesInPlace) {
  // Two planes meeting at a right angle along x: z = 0 for y <= 0, the wall y = 0 above it...
  // folded: a grid over (x, s) mapped to z = 0 for s <= 0 and to y = 0, z = s for s > 0.
  constexpr int kN = 8;
  TriangleMesh mesh;
  mesh.vertices.resize((kN + 1) * (2 * kN + 1), 3);
  mesh.normals.resize(mesh.vertices.rows(), 3);
  const auto id = [&](int i, int j) { return i * (2 * kN + 1) + j; };
  for (int i = 0; i <= kN; ++i)
    for (int j = 0; j <= 2 * kN; ++j) {
      const double x = i, s = j - kN;
      mesh.vertices.row(id(i, j)) = s <= 0 ? Eigen::RowVector3d(x, s, 0) : Eigen::RowVector3d(x, 0, s);
      // The floor's normal +z, the wall's -y; the fold's own vertices lean between them.
      mesh.normals.row(id(i, j)) = s < 0   ? Eigen::RowVector3d(0, 0, 1)
                                   : s > 0 ? Eigen::RowVector3d(0, -1, 0)
                                           : Eigen::RowVector3d(0, -1, 1).normalized();
    }
  std::vector<Eigen::RowVector3i> faces;
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < 2 * kN; ++j) {
      faces.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t t = 0; t < faces.size(); ++t) mesh.triangles.row(static_cast<Eigen::Index>(t)) = faces[t];
  const Points before = mesh.vertices;
  EXPECT_EQ(detail::offset_chord_sag(mesh), 0);
  EXPECT_EQ(mesh.vertices, before);

  // On the sphere, the fixed vertices stay and the others move.
  TriangleMesh sphere = icosphere(2);
  std::vector<float> fixed(static_cast<std::size_t>(sphere.vertices.rows()), 0.0f);
  for (std::size_t v = 0; v < fixed.size(); v += 3) fixed[v] = 1;
  const Points on_sphere = sphere.vertices;
  detail::offset_chord_sag(sphere, fixed);
  for (Eigen::Index v = 0; v < sphere.vertices.rows(); ++v) {
    if (fixed[static_cast<std::size_t>(v)] > 0)
      EXPECT_EQ(sphere.vertices.row(v), on_sphere.row(v));
    else
      EXPECT_NE(sphere.vertices.row(v), on_sphere.row(v));
  }
}

TEST(ChordSag, SameBitsForAnyNumbering) {
  const TriangleMesh mesh = icosphere(3);
  TriangleMesh offset = mesh;
  detail::offset_chord_sag(offset);
  test::Renumbered other = test::renumbered(mesh, 7);
  detail::offset_chord_sag(other.mesh);
  for (std::size_t v = 0; v < other.new_index.size(); ++v)
    EXPECT_EQ(other.mesh.vertices.row(other.new_index[v]), offset.vertices.row(static_cast<Eigen::Index>(v)));
}

TEST(ChordSag, TheReconstructedSphereComesCloser) {
  // 20,000 exact points of the unit sphere, meshed at the defaults with and without the offset:
  // the triangles' mean distance to the sphere falls, the vertices go out.
  const PointCloud cloud = test::sample_sphere(20000);
  ReconstructOptions options;
  const SurfaceMesh offset = *reconstruct(cloud, options).mesh;
  options.meshing.refit.chord_offset = false;
  const SurfaceMesh on_fits = *reconstruct(cloud, options).mesh;
  ASSERT_EQ(offset.mesh.triangles, on_fits.mesh.triangles);
  EXPECT_GT(offset.refit.mean_chord_offset, 0);
  EXPECT_EQ(on_fits.refit.mean_chord_offset, 0);
  const double with = mean_distance_to_unit_sphere(offset.mesh), without = mean_distance_to_unit_sphere(on_fits.mesh);
  std::cout << "mean distance to the sphere: " << without << " on the fits, " << with << " offset\n";
  EXPECT_LT(with, 0.5 * without);
}
