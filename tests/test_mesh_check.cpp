// Print-ready checks: topology, genus and volume of closed and open meshes, and the
// self-intersection test (shared corners and edges, folds, flat regions, duplicates), against a
// brute-force count and across thread counts.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_check.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <tuple>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

using Vec = Eigen::Vector3d;

/// Every triangle turned over when the mesh encloses a negative volume (outward-facing result).
void face_outward(TriangleMesh& m) {
  if (mesh_topology(m).signed_volume < 0) m.triangles.col(1).swap(m.triangles.col(2));
}

/// A latitude–longitude sphere: `slices` around, `stacks` from pole to pole.
TriangleMesh uv_sphere(int slices, int stacks, double radius = 1.0, const Vec& center = Vec::Zero()) {
  TriangleMesh m;
  const int rings = stacks - 1;
  m.vertices.resize(2 + rings * slices, 3);
  m.vertices.row(0) = (center + Vec(0, 0, radius)).transpose();
  for (int k = 0; k < rings; ++k) {
    const double theta = std::numbers::pi * (k + 1) / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2 * std::numbers::pi * j / slices;
      m.vertices.row(1 + k * slices + j) =
          (center + radius * Vec(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)))
              .transpose();
    }
  }
  const int south = 1 + rings * slices;
  m.vertices.row(south) = (center + Vec(0, 0, -radius)).transpose();
  std::vector<std::array<int, 3>> t;
  const auto at = [slices](int k, int j) { return 1 + k * slices + (j % slices); };
  for (int j = 0; j < slices; ++j) {
    t.push_back({0, at(0, j), at(0, j + 1)});
    t.push_back({south, at(rings - 1, j + 1), at(rings - 1, j)});
    for (int k = 0; k + 1 < rings; ++k) {
      t.push_back({at(k, j), at(k + 1, j), at(k, j + 1)});
      t.push_back({at(k, j + 1), at(k + 1, j), at(k + 1, j + 1)});
    }
  }
  m.triangles.resize(static_cast<Eigen::Index>(t.size()), 3);
  for (std::size_t f = 0; f < t.size(); ++f)
    for (int c = 0; c < 3; ++c) m.triangles(static_cast<Eigen::Index>(f), c) = t[f][static_cast<std::size_t>(c)];
  face_outward(m);
  return m;
}

/// A torus around z (major radius R, minor r) on an n × m grid.
TriangleMesh grid_torus(int n, int m, double R = 1.0, double r = 0.35) {
  TriangleMesh t;
  t.vertices.resize(n * m, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
      t.vertices.row(i * m + j) << (R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
          r * std::sin(v);
    }
  t.triangles.resize(2 * n * m, 3);
  const auto at = [n, m](int i, int j) { return (i % n) * m + (j % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      t.triangles.row(2 * (i * m + j)) << at(i, j), at(i + 1, j), at(i + 1, j + 1);
      t.triangles.row(2 * (i * m + j) + 1) << at(i, j), at(i + 1, j + 1), at(i, j + 1);
    }
  face_outward(t);
  return t;
}

/// The surface of a cube of side n (unit squares, two triangles each), every face flat, turned
/// by `rotation` and moved by `offset`: a mesh made of flat fans.
TriangleMesh grid_cube(int n, const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity(),
                       const Vec& offset = Vec::Zero()) {
  std::map<std::tuple<int, int, int>, int> index;
  std::vector<Vec> vertices;
  std::vector<std::array<int, 3>> triangles;
  const auto vertex = [&](const std::array<int, 3>& p) {
    const auto key = std::make_tuple(p[0], p[1], p[2]);
    const auto it = index.find(key);
    if (it != index.end()) return it->second;
    const int id = static_cast<int>(vertices.size());
    index.emplace(key, id);
    vertices.push_back(rotation * Vec(p[0], p[1], p[2]) + offset);
    return id;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int s = 0; s < 2; ++s)
      for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) {
          const int b = (axis + 1) % 3, c = (axis + 2) % 3;
          const auto corner = [&](int du, int dv) {
            std::array<int, 3> p{};
            p[static_cast<std::size_t>(axis)] = s * n;
            p[static_cast<std::size_t>(b)] = u + du;
            p[static_cast<std::size_t>(c)] = v + dv;
            return vertex(p);
          };
          const int p00 = corner(0, 0), p10 = corner(1, 0), p11 = corner(1, 1), p01 = corner(0, 1);
          if (s == 1) {
            triangles.push_back({p00, p10, p11});
            triangles.push_back({p00, p11, p01});
          } else {
            triangles.push_back({p00, p11, p10});
            triangles.push_back({p00, p01, p11});
          }
        }
  TriangleMesh m;
  m.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    m.vertices.row(static_cast<Eigen::Index>(i)) = vertices[i].transpose();
  m.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k)
      m.triangles(static_cast<Eigen::Index>(f), k) = triangles[f][static_cast<std::size_t>(k)];
  return m;
}

/// The two meshes as one (b's vertices after a's).
TriangleMesh join(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m;
  m.vertices.resize(a.vertices.rows() + b.vertices.rows(), 3);
  m.vertices << a.vertices, b.vertices;
  m.triangles.resize(a.triangles.rows() + b.triangles.rows(), 3);
  m.triangles << a.triangles, (b.triangles.array() + static_cast<std::int32_t>(a.vertices.rows())).matrix();
  return m;
}

/// A mesh of the triangles given by their corners (no vertex shared by index).
TriangleMesh soup(const std::vector<std::array<Vec, 3>>& triangles) {
  TriangleMesh m;
  m.vertices.resize(static_cast<Eigen::Index>(3 * triangles.size()), 3);
  m.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<Eigen::Index>(3 * f) + k;
      m.vertices.row(v) = triangles[f][static_cast<std::size_t>(k)].transpose();
      m.triangles(static_cast<Eigen::Index>(f), k) = static_cast<std::int32_t>(v);
    }
  return m;
}

std::array<Vec, 3> corners(const TriangleMesh& m, Eigen::Index f) {
  return {m.vertices.row(m.triangles(f, 0)).transpose(), m.vertices.row(m.triangles(f, 1)).transpose(),
          m.vertices.row(m.triangles(f, 2)).transpose()};
}

/// Intersecting pairs by testing every pair.
std::size_t brute_force_count(const TriangleMesh& m) {
  std::size_t n = 0;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    for (Eigen::Index g = f + 1; g < m.triangles.rows(); ++g) n += triangles_intersect(corners(m, f), corners(m, g));
  return n;
}

/// A tetrahedron with outward faces.
TriangleMesh tetrahedron(const Vec& a, const Vec& b, const Vec& c, const Vec& d) {
  TriangleMesh m;
  m.vertices.resize(4, 3);
  m.vertices << a.transpose(), b.transpose(), c.transpose(), d.transpose();
  m.triangles.resize(4, 3);
  m.triangles << 0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3;
  face_outward(m);
  return m;
}

}  // namespace

TEST(MeshCheck, ClosedSphereIsPrintable) {
  const TriangleMesh sphere = uv_sphere(96, 48);
  const MeshCheck c = check_mesh(sphere);
  EXPECT_TRUE(c.watertight);
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_EQ(c.topology.boundary_edges, 0u);
  EXPECT_EQ(c.topology.non_manifold_edges, 0u);
  EXPECT_EQ(c.topology.components, 1u);
  EXPECT_EQ(c.topology.euler_characteristic, 2);
  EXPECT_EQ(c.genus, 0);
  // The inscribed polyhedron falls short of 4/3 π by about 2 (π/48)² ≈ 0.9 %.
  EXPECT_NEAR(c.volume, 4.0 / 3.0 * std::numbers::pi, 0.015 * 4.0 / 3.0 * std::numbers::pi);
  EXPECT_LT(c.volume, 4.0 / 3.0 * std::numbers::pi);
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_TRUE(c.intersecting_pairs.empty());
  EXPECT_TRUE(c.printable);
}

TEST(MeshCheck, InsideOutSphereIsNotPrintable) {
  TriangleMesh sphere = uv_sphere(32, 16);
  sphere.triangles.col(1).swap(sphere.triangles.col(2));
  const MeshCheck c = check_mesh(sphere);
  EXPECT_TRUE(c.watertight);
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_EQ(c.genus, 0);
  EXPECT_LT(c.volume, 0);
  EXPECT_FALSE(c.printable);
}

TEST(MeshCheck, TorusHasGenusOne) {
  const MeshCheck c = check_mesh(grid_torus(64, 24));
  EXPECT_TRUE(c.watertight);
  EXPECT_EQ(c.topology.euler_characteristic, 0);
  EXPECT_EQ(c.genus, 1);
  // 2π²Rr² for the smooth torus; the polyhedron is a little smaller.
  const double smooth = 2 * std::numbers::pi * std::numbers::pi * 1.0 * 0.35 * 0.35;
  EXPECT_NEAR(c.volume, smooth, 0.03 * smooth);
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_TRUE(c.printable);
}

TEST(MeshCheck, GenusIsSummedOverComponents) {
  const TriangleMesh torus = grid_torus(48, 16);
  TriangleMesh other = torus;
  other.vertices.col(0).array() += 5.0;
  const MeshCheck c = check_mesh(join(torus, other));
  EXPECT_EQ(c.topology.components, 2u);
  EXPECT_EQ(c.genus, 2);
  EXPECT_TRUE(c.printable);
}

TEST(MeshCheck, TwoDisjointSpheres) {
  const TriangleMesh a = uv_sphere(48, 24, 1.0);
  const TriangleMesh b = uv_sphere(48, 24, 0.5, Vec(3, 0, 0));
  const MeshCheck c = check_mesh(join(a, b));
  EXPECT_EQ(c.topology.components, 2u);
  EXPECT_EQ(c.topology.euler_characteristic, 4);
  EXPECT_EQ(c.genus, 0);
  EXPECT_NEAR(c.volume, check_mesh(a).volume + check_mesh(b).volume, 1e-12);
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_TRUE(c.printable);
}

TEST(MeshCheck, OpenMeshIsNotPrintable) {
  TriangleMesh sphere = uv_sphere(32, 16);
  // Without its first triangle: one hole of three edges.
  sphere.triangles = sphere.triangles.bottomRows(sphere.triangles.rows() - 1).eval();
  const MeshCheck c = check_mesh(sphere);
  EXPECT_EQ(c.topology.boundary_edges, 3u);
  EXPECT_FALSE(c.watertight);
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_EQ(c.genus, -1);
  EXPECT_TRUE(std::isnan(c.volume));
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_FALSE(c.printable);
}

TEST(MeshCheck, FlippedTriangleIsInconsistent) {
  TriangleMesh sphere = uv_sphere(32, 16);
  std::swap(sphere.triangles(7, 1), sphere.triangles(7, 2));
  const MeshCheck c = check_mesh(sphere);
  EXPECT_TRUE(c.watertight);
  EXPECT_EQ(c.topology.inconsistent_edges, 3u);
  EXPECT_FALSE(c.consistently_oriented);
  EXPECT_EQ(c.genus, -1);
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_FALSE(c.printable);
}

TEST(MeshCheck, OneTrianglePushedThroughAnother) {
  const std::array<Vec, 3> flat{Vec(0, 0, 0), Vec(2, 0, 0), Vec(0, 2, 0)};
  const std::array<Vec, 3> through{Vec(0.4, 0.4, -1), Vec(0.6, 0.4, 1), Vec(0.5, 0.6, 1)};
  const std::array<Vec, 3> above{Vec(0.4, 0.4, 0.1), Vec(0.6, 0.4, 1), Vec(0.5, 0.6, 1)};
  EXPECT_TRUE(triangles_intersect(flat, through));
  EXPECT_TRUE(triangles_intersect(through, flat));
  EXPECT_FALSE(triangles_intersect(flat, above));
  const MeshCheck c = check_mesh(soup({flat, through, above}));
  EXPECT_EQ(c.self_intersections, 1u);
  ASSERT_EQ(c.intersecting_pairs.size(), 1u);
  EXPECT_EQ(c.intersecting_pairs[0], (std::array<std::int32_t, 2>{0, 1}));
  EXPECT_FALSE(c.printable);
}

TEST(MeshCheck, TetrahedronPokedIntoAnother) {
  // b's apex pokes through the interior of a's bottom face (z = 0): b's three faces at the
  // apex cross it, nothing else meets.
  const TriangleMesh a = tetrahedron(Vec(0, 0, 0), Vec(4, 0, 0), Vec(0, 4, 0), Vec(0, 0, 4));
  const TriangleMesh b = tetrahedron(Vec(1, 1, 0.3), Vec(0.5, 0.5, -2), Vec(1.5, 0.6, -2), Vec(0.8, 1.6, -2));
  const MeshCheck c = check_mesh(join(a, b));
  EXPECT_TRUE(c.watertight);
  EXPECT_EQ(c.genus, 0);
  EXPECT_EQ(c.self_intersections, 3u);
  EXPECT_FALSE(c.printable);
  // Touching only (the apex on the face) counts too; a little below it does not.
  const TriangleMesh touching = tetrahedron(Vec(1, 1, 0), Vec(0.5, 0.5, -2), Vec(1.5, 0.6, -2), Vec(0.8, 1.6, -2));
  EXPECT_EQ(check_mesh(join(a, touching)).self_intersections, 3u);
  const TriangleMesh below = tetrahedron(Vec(1, 1, -1e-3), Vec(0.5, 0.5, -2), Vec(1.5, 0.6, -2), Vec(0.8, 1.6, -2));
  EXPECT_EQ(check_mesh(join(a, below)).self_intersections, 0u);
}

TEST(MeshCheck, TrianglesFoldedFlatOntoTheirEdge) {
  TriangleMesh folded;
  folded.vertices.resize(4, 3);
  folded.vertices << 0, 0, 0, 1, 0, 0, 0.2, 1, 0, 0.6, 0.8, 0;
  folded.triangles.resize(2, 3);
  folded.triangles << 0, 1, 2, 1, 0, 3;
  MeshCheck c = check_mesh(folded);
  EXPECT_EQ(c.self_intersections, 1u);
  EXPECT_EQ(c.topology.inconsistent_edges, 0u);  // oriented consistently, and still folded
  // Unfolded (the other side of the edge): flat, no intersection; bent up: none either.
  folded.vertices.row(3) << 0.6, -0.8, 0;
  EXPECT_EQ(check_mesh(folded).self_intersections, 0u);
  folded.vertices.row(3) << 0.6, 0.8, 0.5;
  EXPECT_EQ(check_mesh(folded).self_intersections, 0u);
  // Folded nearly flat, 1e-12 off the plane: still folded.
  folded.vertices.row(3) << 0.6, 0.8, 1e-12;
  EXPECT_EQ(check_mesh(folded).self_intersections, 1u);
}

TEST(MeshCheck, TrianglesSharingAVertex) {
  const Vec v(0, 0, 0);
  const std::array<Vec, 3> a{v, Vec(1, 0, 0), Vec(0, 1, 0)};
  EXPECT_FALSE(triangles_intersect(a, {v, Vec(-1, 0, 0), Vec(0, -1, 0)}));       // the opposite quadrant, flat
  EXPECT_FALSE(triangles_intersect(a, {v, Vec(-1, 0, 1), Vec(0, -1, 1)}));       // bent away
  EXPECT_TRUE(triangles_intersect(a, {v, Vec(0.5, 0.2, 0), Vec(0.2, 0.5, 0)}));  // inside it, flat
  EXPECT_TRUE(triangles_intersect(a, {v, Vec(1, 1, 1), Vec(1, 1, -1)}));         // through it
  EXPECT_FALSE(triangles_intersect(a, {v, Vec(1, 1, 1), Vec(-1, 1, 1)}));        // touching at v only
}

TEST(MeshCheck, DuplicatedFaceCounts) {
  TriangleMesh sphere = uv_sphere(16, 8);
  TriangleMesh twice = sphere;
  twice.triangles.conservativeResize(sphere.triangles.rows() + 1, 3);
  twice.triangles.row(sphere.triangles.rows()) = sphere.triangles.row(5);
  const MeshCheck c = check_mesh(twice);
  EXPECT_EQ(c.self_intersections, 1u);
  EXPECT_EQ(c.topology.non_manifold_edges, 3u);
  EXPECT_FALSE(c.watertight);
  EXPECT_FALSE(c.printable);
}

TEST(MeshCheck, TopologyRejectsATriangleOfAMissingVertex) {
  for (const int bad : {-1, 4}) {
    TriangleMesh t = tetrahedron(Vec(0, 0, 0), Vec(1, 0, 0), Vec(0, 1, 0), Vec(0, 0, 1));
    t.triangles(2, 1) = bad;
    EXPECT_THROW((void)mesh_topology(t), OptionError) << bad;
  }
}

TEST(MeshCheck, FlatFacesOfATurnedCubeDoNotIntersect) {
  // Every face a flat fan, off every axis: the triangles sharing a vertex in one plane must not
  // count, however the rounding falls.
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.7, Vec(1, 2, 3).normalized()) * Eigen::AngleAxisd(0.3, Vec::UnitX())).toRotationMatrix();
  const TriangleMesh cube = grid_cube(12, 0.1 * turn, Vec(1e3, -2e3, 5e2));
  const MeshCheck c = check_mesh(cube);
  EXPECT_TRUE(c.watertight);
  EXPECT_EQ(c.genus, 0);
  EXPECT_NEAR(c.volume, 1.2 * 1.2 * 1.2, 1e-6);
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_TRUE(c.printable);
  // Other turns, far from zero, and rounded to float as a PLY file stores them.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> angle(0, 2 * std::numbers::pi), coordinate(-1, 1);
  for (int k = 0; k < 12; ++k) {
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(angle(rng), Vec(coordinate(rng), coordinate(rng), coordinate(rng)).normalized())
            .toRotationMatrix();
    TriangleMesh turned = grid_cube(10, 0.01 * r, 100.0 * Vec(coordinate(rng), coordinate(rng), coordinate(rng)));
    if (k % 2 == 1) turned.vertices = turned.vertices.cast<float>().cast<double>().eval();
    const MeshCheck t = check_mesh(turned);
    EXPECT_EQ(t.self_intersections, 0u) << "turn " << k;
    EXPECT_EQ(t.genus, 0) << "turn " << k;
  }
}

TEST(MeshCheck, TriangleSoupCountsAsWelded) {
  const TriangleMesh sphere = uv_sphere(32, 16);
  std::vector<std::array<Vec, 3>> triangles;
  for (Eigen::Index f = 0; f < sphere.triangles.rows(); ++f) triangles.push_back(corners(sphere, f));
  const MeshCheck c = check_mesh(soup(triangles));
  EXPECT_FALSE(c.watertight);  // by index, every edge is a boundary
  EXPECT_EQ(c.self_intersections, 0u);
}

TEST(MeshCheck, SameCountAsEveryPairTested) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0, 1), jitter(-0.15, 0.15);
  // Loose triangles in a box: many crossings.
  std::vector<std::array<Vec, 3>> loose;
  for (int f = 0; f < 300; ++f) {
    const Vec c(unit(rng), unit(rng), unit(rng));
    loose.push_back({c + Vec(jitter(rng), jitter(rng), jitter(rng)), c + Vec(jitter(rng), jitter(rng), jitter(rng)),
                     c + Vec(jitter(rng), jitter(rng), jitter(rng))});
  }
  const TriangleMesh a = soup(loose);
  const SelfIntersections sa = find_self_intersections(a);
  EXPECT_GT(sa.count, 100u);
  EXPECT_EQ(sa.count, brute_force_count(a));
  // Triangles on a jittered grid's corners: shared vertices and edges, duplicates, folds.
  const int n = 5;
  TriangleMesh b;
  b.vertices.resize(n * n * n, 3);
  for (int i = 0; i < n * n * n; ++i)
    b.vertices.row(i) << i % n + 0.3 * jitter(rng), (i / n) % n + 0.3 * jitter(rng), i / (n * n) + 0.3 * jitter(rng);
  std::uniform_int_distribution<int> cell(0, n - 2), corner(0, 7);
  b.triangles.resize(400, 3);
  for (Eigen::Index f = 0; f < b.triangles.rows(); ++f) {
    const int x = cell(rng), y = cell(rng), z = cell(rng);
    std::array<int, 3> k{};
    do {
      for (int& c : k) c = corner(rng);
    } while (k[0] == k[1] || k[1] == k[2] || k[0] == k[2]);
    for (int c = 0; c < 3; ++c)
      b.triangles(f, c) = (x + (k[static_cast<std::size_t>(c)] & 1)) +
                          n * (y + ((k[static_cast<std::size_t>(c)] >> 1) & 1)) +
                          n * n * (z + (k[static_cast<std::size_t>(c)] >> 2));
  }
  const SelfIntersections sb = find_self_intersections(b);
  EXPECT_GT(sb.count, 100u);
  EXPECT_EQ(sb.count, brute_force_count(b));
  // The listed pairs are the first ones, sorted.
  MeshCheckOptions few;
  few.max_pairs = 5;
  const SelfIntersections s5 = find_self_intersections(b, few);
  EXPECT_EQ(s5.count, sb.count);
  ASSERT_EQ(s5.pairs.size(), 5u);
  EXPECT_TRUE(std::equal(s5.pairs.begin(), s5.pairs.end(), sb.pairs.begin()));
  EXPECT_TRUE(std::is_sorted(sb.pairs.begin(), sb.pairs.end()));
}

TEST(MeshCheck, SuspectsFindThePairsTheyAreIn) {
  // Two overlapping spheres, one of them small enough that its triangles' boxes are far smaller
  // than the other's: every pair found with some triangles suspected is a pair of the full
  // search with a suspect in it, and every such pair is found.
  const TriangleMesh mesh = join(uv_sphere(64, 32), uv_sphere(16, 8, 0.5, Vec(0.9, 0.1, 0.05)));
  MeshCheckOptions all;
  all.max_pairs = 100'000;
  const SelfIntersections full = find_self_intersections(mesh, all);
  ASSERT_GT(full.count, 50u);
  std::mt19937_64 rng(3);
  std::bernoulli_distribution pick(0.1);
  std::vector<std::uint8_t> suspect(static_cast<std::size_t>(mesh.triangles.rows()));
  for (auto& s : suspect) s = pick(rng);
  std::vector<std::array<std::int32_t, 2>> expected;
  for (const auto& p : full.pairs)
    if (suspect[static_cast<std::size_t>(p[0])] != 0 || suspect[static_cast<std::size_t>(p[1])] != 0)
      expected.push_back(p);
  ASSERT_GT(expected.size(), 5u);
  ASSERT_LT(expected.size(), full.count);
  const SelfIntersections found = find_self_intersections(mesh, suspect, all);
  EXPECT_EQ(found.count, expected.size());
  EXPECT_EQ(found.pairs, expected);
  // No suspect, no pair; every triangle suspected, the full search.
  EXPECT_EQ(find_self_intersections(mesh, std::vector<std::uint8_t>(suspect.size(), 0), all).count, 0u);
  EXPECT_EQ(find_self_intersections(mesh, std::vector<std::uint8_t>(suspect.size(), 1), all).pairs, full.pairs);
  EXPECT_THROW(find_self_intersections(mesh, std::vector<std::uint8_t>(3, 1), all), OptionError);
}

TEST(MeshCheck, SameResultWithOneThread) {
  const TriangleMesh overlapping = join(uv_sphere(64, 32), uv_sphere(64, 32, 0.8, Vec(0.9, 0.1, 0.05)));
  const SelfIntersections many = find_self_intersections(overlapping);
  EXPECT_GT(many.count, 50u);
  SelfIntersections one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = find_self_intersections(overlapping);
  }
  EXPECT_EQ(one.count, many.count);
  EXPECT_EQ(one.pairs, many.pairs);
}

TEST(MeshCheck, ReconstructedSphereHasNoSelfIntersections) {
  const Reconstruction r = reconstruct(test::sample_sphere(20000));
  ASSERT_TRUE(r.mesh.has_value());
  const MeshCheck c = check_mesh(r.mesh->mesh);
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_EQ(c.topology.components, 1u);
  if (c.watertight) {
    EXPECT_EQ(c.genus, 0);
    EXPECT_NEAR(c.volume, 4.0 / 3.0 * std::numbers::pi, 0.02 * 4.0 / 3.0 * std::numbers::pi);
    EXPECT_TRUE(c.printable);
  }
}

TEST(MeshCheck, EmptyAndInvalid) {
  const MeshCheck empty = check_mesh(TriangleMesh{});
  EXPECT_FALSE(empty.watertight);
  EXPECT_FALSE(empty.printable);
  EXPECT_EQ(empty.self_intersections, 0u);
  MeshCheckOptions bad;
  bad.tolerance = -1;
  EXPECT_THROW(check_mesh(uv_sphere(8, 4), bad), OptionError);
  TriangleMesh broken = uv_sphere(8, 4);
  broken.triangles(0, 0) = 1000;
  EXPECT_THROW(find_self_intersections(broken), OptionError);
  // Non-finite corners: those triangles are left out, the others still tested.
  TriangleMesh nan = join(uv_sphere(16, 8), uv_sphere(16, 8, 0.5, Vec(0.8, 0, 0)));
  const std::size_t crossing = find_self_intersections(nan).count;
  ASSERT_GT(crossing, 0u);
  nan.vertices(0, 0) = std::numeric_limits<double>::quiet_NaN();  // the north pole of the first
  nan.vertices(1, 1) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(find_self_intersections(nan).count, crossing);
}
