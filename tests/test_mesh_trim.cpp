// Trimming a mesh to its input points: the part beyond the data goes, the rest stays as it was.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/mesh/mesh_trim.hpp>
#include <clustersurf/surface/implicit_surface.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <gtest/gtest.h>

#include <numbers>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

TriangleMesh sphere_mesh() {
  const PointCloud c = test::sample_sphere(20000);
  ClusterTree t = build_cluster_tree(c, {});
  orient_tree(t, c);
  MeshOptions o;
  o.resolution = 64;
  return extract_mesh(ImplicitSurface(t), o);
}

/// The rows of the sphere samples with z > 0: data that stops at the equator.
Points upper_half() {
  const PointCloud c = test::sample_sphere(20000);
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < c.size(); ++i)
    if (c.positions(i, 2) > 0) rows.push_back(i);
  return c.positions(rows, Eigen::all);
}

}  // namespace

TEST(MeshTrim, DropsWhatLiesBeyondTheDataAndKeepsTheRest) {
  const TriangleMesh full = sphere_mesh();
  const Points data = upper_half();
  TrimReport report;
  const TriangleMesh trimmed = trim_to_points(full, data, {}, &report);
  EXPECT_GT(report.removed_triangles, static_cast<std::size_t>(full.triangles.rows()) / 3);
  EXPECT_EQ(static_cast<std::size_t>(full.triangles.rows() - trimmed.triangles.rows()), report.removed_triangles);
  EXPECT_EQ(static_cast<std::size_t>(full.vertices.rows() - trimmed.vertices.rows()), report.removed_vertices);
  // The sample spacing is about 0.025: nothing stays more than a few spacings below the data.
  EXPECT_GT(trimmed.vertices.col(2).minCoeff(), -0.1);
  // Every triangle well inside the data is kept.
  std::size_t inside_full = 0, inside_trimmed = 0;
  auto count_inside = [](const TriangleMesh& m) {
    std::size_t n = 0;
    for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
      bool inside = true;
      for (int k = 0; k < 3; ++k) inside = inside && m.vertices(m.triangles(t, k), 2) > 0.1;
      n += inside;
    }
    return n;
  };
  inside_full = count_inside(full);
  inside_trimmed = count_inside(trimmed);
  EXPECT_EQ(inside_trimmed, inside_full);
  EXPECT_EQ(trimmed.normals.rows(), trimmed.vertices.rows());
}

TEST(MeshTrim, DataEverywhereOrFactorZeroKeepsTheMeshAsItIs) {
  const TriangleMesh full = sphere_mesh();
  const PointCloud c = test::sample_sphere(20000);
  TrimReport report;
  const TriangleMesh same = trim_to_points(full, c.positions, {}, &report);
  EXPECT_EQ(report.removed_triangles, 0u);
  EXPECT_EQ(same.vertices, full.vertices);
  EXPECT_EQ(same.triangles, full.triangles);
  TrimOptions off;
  off.spread_factor = 0;
  EXPECT_EQ(trim_to_points(full, upper_half(), off).triangles, full.triangles);
  TrimOptions bad;
  bad.spread_factor = -1;
  EXPECT_THROW(trim_to_points(full, c.positions, bad), OptionError);
}

namespace {

/// `mesh` with a copy of itself scaled by `scale` and moved to `offset` appended: a second,
/// disjoint component.
TriangleMesh with_fragment(const TriangleMesh& mesh, double scale, const Eigen::Vector3d& offset) {
  TriangleMesh out = mesh;
  const Eigen::Index nv = mesh.vertices.rows(), nt = mesh.triangles.rows();
  out.vertices.conservativeResize(2 * nv, 3);
  out.normals.conservativeResize(2 * nv, 3);
  out.triangles.conservativeResize(2 * nt, 3);
  for (Eigen::Index v = 0; v < nv; ++v) {
    out.vertices.row(nv + v) = scale * mesh.vertices.row(v) + offset.transpose();
    out.normals.row(nv + v) = mesh.normals.row(v);
  }
  out.triangles.bottomRows(nt) = mesh.triangles.array() + static_cast<std::int32_t>(nv);
  return out;
}

/// The sphere's samples plus `extra` points on a sphere of radius `radius` around `center`.
Points sphere_points_and(int extra, double radius, const Eigen::Vector3d& center) {
  const PointCloud c = test::sample_sphere(20000);
  const PointCloud e = test::sample_sphere(extra, radius, center);
  Points p(c.size() + e.size(), 3);
  p << c.positions, e.positions;
  return p;
}

}  // namespace

TEST(MeshTrim, DropsAFragmentTheDataDoesNotSupport) {
  const TriangleMesh sphere = sphere_mesh();
  const Eigen::Vector3d far(3, 0, 0);
  const TriangleMesh two = with_fragment(sphere, 0.1, far);
  ASSERT_EQ(mesh_topology(two).components, 2u);
  // Debris: a few stray points near the small shell, fewer than any proxy rests on.
  TrimReport report;
  const TriangleMesh cleaned = trim_to_points(two, sphere_points_and(12, 0.1, far), {}, &report);
  EXPECT_EQ(report.removed_components, 1u);
  EXPECT_EQ(mesh_topology(cleaned).components, 1u);
  EXPECT_EQ(cleaned.triangles, sphere.triangles);
  EXPECT_EQ(cleaned.vertices, sphere.vertices);
  // A small real part, sampled as densely as the rest, stays.
  const TriangleMesh kept = trim_to_points(two, sphere_points_and(200, 0.1, far), {}, &report);
  EXPECT_EQ(report.removed_components, 0u);
  EXPECT_EQ(kept.triangles.rows(), two.triangles.rows());
  // 0 keeps every fragment.
  TrimOptions all;
  all.min_component_points = 0;
  EXPECT_EQ(trim_to_points(two, sphere_points_and(12, 0.1, far), all).triangles.rows(), two.triangles.rows());
}

TEST(MeshTrim, TheBestSupportedComponentAlwaysStays) {
  // Fewer input points than a fragment needs: the component they lie on is still the surface.
  const TriangleMesh sphere = sphere_mesh();
  const TriangleMesh two = with_fragment(sphere, 0.1, Eigen::Vector3d(3, 0, 0));
  const PointCloud few = test::sample_sphere(20);
  TrimOptions no_spread;
  no_spread.spread_factor = 0;
  TrimReport report;
  const TriangleMesh kept = trim_to_points(two, few.positions, no_spread, &report);
  EXPECT_EQ(report.removed_components, 1u);
  EXPECT_EQ(kept.triangles, sphere.triangles);
}

namespace {

/// `mesh` without the triangles that touch vertex `v`: a pinhole.
TriangleMesh punched(const TriangleMesh& mesh, std::int32_t v) {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    if ((mesh.triangles.row(t).array() != v).all()) rows.push_back(t);
  TriangleMesh out = mesh;
  out.triangles = mesh.triangles(rows, Eigen::all);
  return out;
}

}  // namespace

TEST(MeshTrim, ClosesPinholesTheDataCoversAndNotRealHoles) {
  const TriangleMesh sphere = sphere_mesh();
  ASSERT_EQ(mesh_topology(sphere).boundary_edges, 0u);
  TriangleMesh holed = punched(punched(sphere, 10), 500);
  ASSERT_GT(mesh_topology(holed).boundary_edges, 0u);
  const PointCloud c = test::sample_sphere(20000);
  TrimOptions close;
  close.close_pinholes = true;
  TrimReport report;
  const TriangleMesh closed = trim_to_points(holed, c.positions, close, &report);
  EXPECT_EQ(report.closed_pinholes, 2u);
  const MeshTopology topo = mesh_topology(closed);
  EXPECT_EQ(topo.boundary_edges, 0u);
  EXPECT_EQ(topo.non_manifold_edges, 0u);
  EXPECT_EQ(topo.inconsistent_edges, 0u);  // the fans face like the triangles around them
  // Every added vertex lies near the sphere (within a grid cell of 2/64).
  for (Eigen::Index v = holed.vertices.rows(); v < closed.vertices.rows(); ++v)
    EXPECT_NEAR(closed.vertices.row(v).norm(), 1, 2.0 / 64);
  // Off by default.
  EXPECT_GT(mesh_topology(trim_to_points(holed, c.positions)).boundary_edges, 0u);
  // Where no data is, the hole stays: the lower half of the sphere without its data.
  const TriangleMesh half = trim_to_points(sphere, upper_half(), close, &report);
  EXPECT_EQ(report.closed_pinholes, 0u);
  EXPECT_GT(mesh_topology(half).boundary_edges, 0u);
}

namespace {

/// The sphere's samples without those within `radius` of the pole (0, 0, 1): a gap in the data.
Points sphere_points_without_cap(double radius) {
  const PointCloud c = test::sample_sphere(20000);
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < c.size(); ++i)
    if ((c.positions.row(i) - Eigen::RowVector3d(0, 0, 1)).norm() > radius) rows.push_back(i);
  return c.positions(rows, Eigen::all);
}

/// How many of `mesh`'s triangles have a vertex within `radius` of the pole.
std::size_t triangles_near_pole(const TriangleMesh& mesh, double radius) {
  std::size_t n = 0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    bool near = false;
    for (int k = 0; k < 3; ++k)
      near = near || (mesh.vertices.row(mesh.triangles(t, k)) - Eigen::RowVector3d(0, 0, 1)).norm() < radius;
    n += near;
  }
  return n;
}

}  // namespace

TEST(MeshTrim, KeepsTheSurfaceOverAGapBetweenSamplesButNotPastTheDataOrOffIt) {
  // 20 k samples of the unit sphere are about 0.025 apart: the trim's reach (2 spreads) is
  // about 0.06. A gap of radius 0.1 in the samples (under 3 spreads from the nearest point), a
  // size random sampling leaves here and there, is surface the data surrounds: it stays (the
  // nearest point's reach alone cut a hole there).
  const TriangleMesh sphere = sphere_mesh();
  const std::size_t over_gap = triangles_near_pole(sphere, 0.1);
  ASSERT_GT(over_gap, 10u);
  const TriangleMesh kept = trim_to_points(sphere, sphere_points_without_cap(0.1));
  EXPECT_EQ(triangles_near_pole(kept, 0.1), over_gap);
  EXPECT_EQ(mesh_topology(kept).boundary_edges, 0u);
  // A hole in the data several times the reach wide stays a hole.
  EXPECT_EQ(triangles_near_pole(trim_to_points(sphere, sphere_points_without_cap(0.3)), 0.1), 0u);
  // Past the data's edge (all of it to one side) the old reach still holds: no vertex of the
  // lower half stays farther below the equator than the reach of the rim's points (about 0.08,
  // their neighbours all on one side; 1.5 reaches: 0.12).
  EXPECT_GT(trim_to_points(sphere, upper_half()).vertices.col(2).minCoeff(), -0.09);
  // A bulge lifted 0.07 off the data, with data all around it below, is cut.
  TriangleMesh bulge = sphere;
  for (Eigen::Index v = 0; v < bulge.vertices.rows(); ++v)
    if ((bulge.vertices.row(v) - Eigen::RowVector3d(0, 0, 1)).norm() < 0.06) bulge.vertices.row(v) *= 1.07;
  const auto lifted = [](const TriangleMesh& m) {
    std::size_t n = 0;
    for (Eigen::Index t = 0; t < m.triangles.rows(); ++t)
      n += m.vertices.row(m.triangles(t, 0)).norm() > 1.05 || m.vertices.row(m.triangles(t, 1)).norm() > 1.05 ||
           m.vertices.row(m.triangles(t, 2)).norm() > 1.05;
    return n;
  };
  ASSERT_GT(lifted(bulge), 0u);
  const PointCloud all = test::sample_sphere(20000);
  EXPECT_EQ(lifted(trim_to_points(bulge, all.positions)), 0u);
}

namespace {

/// A grid mesh of `rows` x `columns` vertices at `corner` + i `down` + j `across`, every normal
/// `normal`.
TriangleMesh grid_mesh(int rows, int columns, const Eigen::RowVector3d& corner, const Eigen::RowVector3d& down,
                       const Eigen::RowVector3d& across, const Eigen::RowVector3d& normal) {
  TriangleMesh m;
  m.vertices.resize(rows * columns, 3);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < columns; ++j) m.vertices.row(i * columns + j) = corner + i * down + j * across;
  m.triangles.resize(2 * (rows - 1) * (columns - 1), 3);
  Eigen::Index t = 0;
  for (int i = 0; i + 1 < rows; ++i)
    for (int j = 0; j + 1 < columns; ++j) {
      const int a = i * columns + j;
      m.triangles.row(t++) << a, a + columns, a + 1;
      m.triangles.row(t++) << a + 1, a + columns, a + columns + 1;
    }
  m.normals = normal.replicate(m.vertices.rows(), 1);
  return m;
}

/// The meshes `a` and `b` as one (b's rows after a's).
TriangleMesh joined(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh both = a;
  both.vertices.conservativeResize(a.vertices.rows() + b.vertices.rows(), 3);
  both.vertices.bottomRows(b.vertices.rows()) = b.vertices;
  both.normals.conservativeResize(both.vertices.rows(), 3);
  both.normals.bottomRows(b.normals.rows()) = b.normals;
  both.triangles.conservativeResize(a.triangles.rows() + b.triangles.rows(), 3);
  both.triangles.bottomRows(b.triangles.rows()) = b.triangles.array() + static_cast<std::int32_t>(a.vertices.rows());
  return both;
}

}  // namespace

// A sheet midway between two layers of data (a slot's two walls, two scans apart), 2.5 reaches
// from each: its neighbours surround it in projection, but they lie on two sheets, not one.
TEST(MeshTrim, CutsASheetBetweenTwoLayersOfData) {
  const double spacing = 0.025, gap = 0.16;
  Points layers(2 * 41 * 41, 3);
  Eigen::Index row = 0;
  for (const double z : {-gap / 2, gap / 2})
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j) layers.row(row++) << (i - 20) * spacing, (j - 20) * spacing, z;
  const TriangleMesh sheet =  // the mid-plane, 0.3 wide
      grid_mesh(13, 13, {-6 * spacing, -6 * spacing, 0}, {spacing, 0, 0}, {0, spacing, 0}, {0, 0, 1});
  TrimOptions reach_only;
  reach_only.min_component_points = 0;
  EXPECT_EQ(trim_to_points(sheet, layers, reach_only).triangles.rows(), 0);
}

// A flap standing up off a flat sheet of data, all of it within the reach of the data's points
// (as the blend raises one between two close parts of a sparse scan), is not the data's surface:
// it goes; the sheet's own surface, level with the data, stays.
TEST(MeshTrim, CutsAFlapStandingOffTheDataAndKeepsTheSheet) {
  const double spacing = 0.025;  // the points' spread (mean distance to 8 neighbours): about 0.03
  Points data(41 * 41, 3);
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) data.row(i * 41 + j) << (i - 20) * spacing, (j - 20) * spacing, 0;
  const TriangleMesh sheet =
      grid_mesh(13, 13, {-6 * spacing, -6 * spacing, 0}, {spacing, 0, 0}, {0, spacing, 0}, {0, 0, 1});
  // The flap: 0.02 to 0.05 above the data, between two columns of points (under 0.052 from
  // the nearest point: within the reach of 2 spreads); its rows at 0.035 and 0.05 lie more
  // than a spread off the data's plane, next to each other.
  const TriangleMesh flap =
      grid_mesh(3, 9, {spacing / 2, -4 * spacing, 0.02}, {0, 0, 0.015}, {0, spacing, 0}, {1, 0, 0});
  const TriangleMesh both = joined(sheet, flap);
  TrimOptions reach_only;
  reach_only.min_component_points = 0;
  const TriangleMesh kept = trim_to_points(both, data, reach_only);
  EXPECT_EQ(kept.triangles.rows(), sheet.triangles.rows());
  EXPECT_LT(kept.vertices.col(2).cwiseAbs().maxCoeff(), 1e-12);
  // The same flap laid level, 0.01 above the data, is the data's surface: it stays.
  const TriangleMesh level =
      grid_mesh(3, 9, {spacing / 2, -4 * spacing, 0.01}, {0.015, 0, 0}, {0, spacing, 0}, {0, 0, 1});
  EXPECT_EQ(trim_to_points(level, data, reach_only).triangles.rows(), level.triangles.rows());
}

// A flap standing off a thin tube of sparse data (a leg of a sparse scan): the 16 points
// nearest to it wrap around the tube, so they are no one sheet; the 8 nearest, on the tube's
// near side, are, and the flap stands off them: it goes; the tube's own surface stays.
TEST(MeshTrim, CutsAFlapStandingOffAThinTube) {
  // Rings of 6 points, each turned half a step from the last, 1.5 chords apart: the spread
  // (mean distance to 8 neighbours) is about 0.019, the reach 0.037.
  const double radius = 0.012, chord = radius, pitch = 1.5 * chord;
  const int rings = 41, around = 6;
  Points data(rings * around, 3);
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < around; ++j) {
      const double a = (j + 0.5 * (i % 2)) * 2 * std::numbers::pi / around;
      data.row(i * around + j) << (i - rings / 2) * pitch, radius * std::cos(a), radius * std::sin(a);
    }
  // The tube's surface, 24 facets around, over its middle.
  const int segments = 24, stations = 21;
  TriangleMesh tube;
  tube.vertices.resize(stations * segments, 3);
  tube.normals.resize(stations * segments, 3);
  for (int i = 0; i < stations; ++i)
    for (int j = 0; j < segments; ++j) {
      const double a = j * 2 * std::numbers::pi / segments;
      tube.vertices.row(i * segments + j) << (i - stations / 2) * pitch / 2, radius * std::cos(a), radius * std::sin(a);
      tube.normals.row(i * segments + j) << 0, std::cos(a), std::sin(a);
    }
  tube.triangles.resize(2 * (stations - 1) * segments, 3);
  Eigen::Index t = 0;
  for (int i = 0; i + 1 < stations; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      tube.triangles.row(t++) << a, a + segments, b;
      tube.triangles.row(t++) << b, a + segments, b + segments;
    }
  // The flap: 0.024 to 0.032 above the tube's top, within the reach, more than a spread off
  // the plane of the points under it.
  const TriangleMesh flap = grid_mesh(3, 9, {-4 * pitch, 0, radius + 0.024}, {0, 0, 0.004}, {pitch, 0, 0}, {0, 1, 0});
  const TriangleMesh both = joined(tube, flap);
  TrimOptions reach_only;
  reach_only.min_component_points = 0;
  const TriangleMesh kept = trim_to_points(both, data, reach_only);
  EXPECT_EQ(kept.triangles.rows(), tube.triangles.rows());
  EXPECT_LT(kept.vertices.col(2).maxCoeff(), radius + 1e-12);
}

TEST(MeshTrim, GivenSpreadsAreUsedAndMeasuredOnesAreTheSame) {
  const TriangleMesh full = sphere_mesh();
  const Points data = upper_half();
  const KdTree index(data);
  const TrimOptions options;
  std::vector<double> spread(index.size());
  std::vector<Neighbor> nb;
  for (std::size_t i = 0; i < spread.size(); ++i) {
    index.neighbors_of(static_cast<Eigen::Index>(i), options.neighbors, nb);
    double sum = 0;
    for (const Neighbor& q : nb) sum += std::sqrt(q.distance_squared);
    spread[i] = sum / static_cast<double>(nb.size());
  }
  TrimReport measured, given;
  const TriangleMesh a = trim_to_points(full, index, options, &measured);
  const TriangleMesh b = trim_to_points(full, index, options, &given, spread);
  ASSERT_GT(measured.removed_triangles, 0u);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(measured.removed_triangles, given.removed_triangles);
  // Smaller spreads reach less far: the given ones are the ones used.
  for (double& s : spread) s *= 0.5;
  TrimReport narrower;
  trim_to_points(full, index, options, &narrower, spread);
  EXPECT_GT(narrower.removed_triangles, measured.removed_triangles);
  spread.pop_back();
  EXPECT_THROW(trim_to_points(full, index, options, nullptr, spread), OptionError);
}

// Where the points thin out past the dense part of a scan (a rim seen at a grazing angle), their
// spread, and with it the reach, grows; the reach stays within max_reach_spreads typical spreads
// (measured at the mesh's vertices, or given), and without the bound the mesh runs on past them.
TEST(MeshTrim, ReachIsBoundedWhereThePointsThinOut) {
  const double dense = 0.02, sparse = 0.1;  // the strip's points lie 5 spacings apart
  std::vector<Eigen::RowVector3d> rows;
  for (int i = 0; i <= 50; ++i)
    for (int j = 0; j <= 50; ++j) rows.emplace_back(-1 + i * dense, -0.5 + j * dense, 0);
  for (int i = 1; i <= 2; ++i)
    for (int j = 0; j <= 10; ++j) rows.emplace_back(i * sparse, -0.5 + j * sparse, 0);
  Points data(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t r = 0; r < rows.size(); ++r) data.row(static_cast<Eigen::Index>(r)) = rows[r];
  // x in [-1, 0.6], y in [-0.5, 0.5], 0.01 apart: most of it over the dense part
  const TriangleMesh plane = grid_mesh(161, 101, {-1, -0.5, 0}, {0.01, 0, 0}, {0, 0.01, 0}, {0, 0, 1});
  const auto farthest = [&](const TrimOptions& options) {
    return trim_to_points(plane, data, options).vertices.col(0).maxCoeff();
  };
  // The typical spread is the dense part's (about 0.024): past the last column (x = 0.2) the
  // reach is at most 3 x 0.024, and 1.5 times that where data lies all around.
  const TrimOptions bounded;
  EXPECT_LT(farthest(bounded), 0.2 + 1.5 * 3 * 0.025 + 0.01);
  EXPECT_GT(farthest(bounded), 0.2);
  TrimOptions unbounded;
  unbounded.max_reach_spreads = 0;
  EXPECT_GT(farthest(unbounded), 0.2 + 2 * sparse);  // the sparse points' spread is about 0.13
  // A typical spread given (a whole cloud's, in a tile of it) is the one the bound counts in.
  TrimOptions given;
  given.typical_spread = 2 * dense;
  EXPECT_GT(farthest(given), farthest(bounded));
  given.max_reach_spreads = -1;
  EXPECT_THROW(farthest(given), OptionError);
}
