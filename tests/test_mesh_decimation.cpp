// decimate(): a triangle budget and a distance bound on a meshed sphere, rims kept in place on
// an open hemisphere, attributes carried, the same result every time.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_decimation.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <gtest/gtest.h>

#include <array>
#include <set>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

/// The sphere of radius 1 reconstructed and meshed finely (about 20 k triangles).
const TriangleMesh& sphere_mesh() {
  static const TriangleMesh mesh = [] {
    ReconstructOptions o;
    o.meshing.auto_resolution = false;
    o.meshing.grid.resolution = 60;
    return reconstruct(test::sample_sphere(20000), o).mesh->mesh;
  }();
  return mesh;
}

/// Largest distance from the unit sphere over the triangles' vertices and centroids.
double off_sphere(const TriangleMesh& m) {
  double worst = 0;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d v = m.vertices.row(m.triangles(f, k));
      worst = std::max(worst, std::abs(v.norm() - 1));
      centroid += v / 3;
    }
    worst = std::max(worst, std::abs(centroid.norm() - 1));
  }
  return worst;
}

}  // namespace

TEST(MeshDecimation, TriangleBudgetKeepsVerticesInPlaceAndTheMeshClosed) {
  const TriangleMesh& m = sphere_mesh();
  ASSERT_GT(m.triangles.rows(), 5000);
  DecimationOptions o;
  o.target_triangles = 1000;
  DecimationReport report;
  const TriangleMesh d = decimate(m, o, &report);
  EXPECT_LE(d.triangles.rows(), 1000);
  EXPECT_GT(d.triangles.rows(), 500);
  EXPECT_EQ(report.triangles_before, static_cast<std::size_t>(m.triangles.rows()));
  EXPECT_EQ(report.triangles_after, static_cast<std::size_t>(d.triangles.rows()));
  // Every vertex is one of the input's, with its normal.
  ASSERT_EQ(d.normals.rows(), d.vertices.rows());
  std::set<std::array<double, 3>> input;
  for (Eigen::Index v = 0; v < m.vertices.rows(); ++v)
    input.insert({m.vertices(v, 0), m.vertices(v, 1), m.vertices(v, 2)});
  for (Eigen::Index v = 0; v < d.vertices.rows(); ++v)
    EXPECT_TRUE(input.count({d.vertices(v, 0), d.vertices(v, 1), d.vertices(v, 2)}));
  const MeshTopology topo = mesh_topology(d);
  EXPECT_EQ(topo.boundary_edges, 0u);
  EXPECT_EQ(topo.euler_characteristic, 2);
  EXPECT_LT(off_sphere(d), 0.05);  // 1,000 triangles still hold a sphere
  const TriangleMesh again = decimate(m, o);
  EXPECT_EQ(again.vertices, d.vertices);
  EXPECT_EQ(again.triangles, d.triangles);
}

TEST(MeshDecimation, DistanceBoundHoldsAndRimsStay) {
  const TriangleMesh& m = sphere_mesh();
  const double before = off_sphere(m);
  for (const double bound : {0.002, 0.01}) {
    DecimationOptions o;
    o.max_deviation = bound;
    DecimationReport report;
    const TriangleMesh d = decimate(m, o, &report);
    EXPECT_LT(d.triangles.rows(), m.triangles.rows());
    EXPECT_LE(report.deviation, bound * 1.0001);
    // The bound is the simplifier's estimate (distances to the planes of the triangles it
    // merged), not a strict Hausdorff bound: within twice it here.
    EXPECT_LT(off_sphere(d), before + 2 * bound) << bound;
  }
  // An open hemisphere: every boundary vertex survives, the rim is unchanged.
  TriangleMesh half;
  std::vector<Eigen::Index> keep;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    if (m.vertices(m.triangles(f, 0), 2) > 0 && m.vertices(m.triangles(f, 1), 2) > 0 &&
        m.vertices(m.triangles(f, 2), 2) > 0)
      keep.push_back(f);
  half.vertices = m.vertices;
  half.triangles = m.triangles(keep, Eigen::all);
  DecimationOptions o;
  o.target_triangles = static_cast<std::size_t>(half.triangles.rows() / 10);
  const TriangleMesh d = decimate(half, o);
  EXPECT_EQ(mesh_topology(d).boundary_edges, mesh_topology(half).boundary_edges);
  EXPECT_THROW(decimate(m, DecimationOptions{0, -1.0, true}), OptionError);
}
