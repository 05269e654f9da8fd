// Thin parts under noise (reconstruct() end to end): a blade whose two faces lie a few noise σ
// apart is one consistently oriented piece without holes: with normals both faces, each facing
// out; without, one sheet inside the blade.

#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

using namespace clustersurf;

namespace {

constexpr double kHalfSide = 0.5;  // the blade spans [-0.5, 0.5]² in x and y

/// A blade of thickness `thickness`: `n` points spread evenly over the faces of the box
/// [-0.5, 0.5]² × [-thickness/2, thickness/2] (its rim too), moved by noise of `sigma` along
/// their face's normal, with those normals or none.
PointCloud noisy_blade(int n, double thickness, double sigma, bool normals, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-kHalfSide, kHalfSide), t(-thickness / 2, thickness / 2);
  std::normal_distribution<double> g(0, sigma);
  const double face = 4 * kHalfSide * kHalfSide, rim = 4 * 2 * kHalfSide * thickness;
  PointCloud c;
  c.positions.resize(n, 3);
  c.normals.resize(n, 3);
  std::uniform_real_distribution<double> pick(0, 2 * face + rim);
  for (int i = 0; i < n; ++i) {
    const double where = pick(rng);
    Eigen::Vector3d p, normal;
    if (where < 2 * face) {
      const double side = where < face ? 1 : -1;
      normal = Eigen::Vector3d(0, 0, side);
      p = Eigen::Vector3d(u(rng), u(rng), side * thickness / 2);
    } else {
      const int k = static_cast<int>(4 * (where - 2 * face) / rim) % 4;
      const double along = u(rng), side = k < 2 ? 1 : -1;
      normal = k % 2 == 0 ? Eigen::Vector3d(side, 0, 0) : Eigen::Vector3d(0, side, 0);
      p = k % 2 == 0 ? Eigen::Vector3d(side * kHalfSide, along, t(rng))
                     : Eigen::Vector3d(along, side * kHalfSide, t(rng));
    }
    c.positions.row(i) = (p + g(rng) * normal).transpose();
    c.normals.row(i) = normal.transpose();
  }
  if (!normals) c.normals.resize(0, 3);
  return c;
}

/// What the mesh of a blade shows over the blade's inner part (away from its rim), in the cells
/// of a 16 × 16 grid there.
struct BladeMesh {
  double covered = 0;     ///< the share of cells whose centre a triangle covers, seen along z
  double both_faces = 0;  ///< the share of cells with vertices beyond a quarter thickness on both sides
  double facing_out = 0;  ///< the share of triangles whose normal faces away from the mid-plane
  double off_face = 0;    ///< the vertices' mean distance from the nearer face
  double inside = 0;      ///< the share of vertices within the blade
  std::size_t inconsistent_edges = 0;
  std::size_t components = 0;
};

BladeMesh inspect(const TriangleMesh& mesh, double thickness) {
  constexpr int kCells = 16;
  constexpr double kInner = 0.8 * kHalfSide;
  const auto cell = [&](double c) { return static_cast<int>((c + kInner) / (2 * kInner) * kCells); };
  std::vector<int> above(kCells * kCells, 0), below(kCells * kCells, 0);
  BladeMesh out;
  std::size_t vertices = 0, inside = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const Eigen::Vector3d p = mesh.vertices.row(v).transpose();
    if (std::abs(p.x()) >= kInner || std::abs(p.y()) >= kInner) continue;
    const int k = cell(p.y()) * kCells + cell(p.x());
    above[k] += p.z() > thickness / 4;
    below[k] += p.z() < -thickness / 4;
    out.off_face += std::abs(std::abs(p.z()) - thickness / 2);
    inside += std::abs(p.z()) <= thickness / 2;
    ++vertices;
  }
  // A cell is covered where a triangle, seen along z, holds its centre: merged flat blocks
  // leave cells without a vertex, not without a surface.
  std::vector<int> hit(kCells * kCells, 0);
  const auto centre = [&](int i) { return -kInner + (i + 0.5) * (2 * kInner / kCells); };
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector2d a = mesh.vertices.row(mesh.triangles(t, 0)).head<2>().transpose();
    const Eigen::Vector2d b = mesh.vertices.row(mesh.triangles(t, 1)).head<2>().transpose();
    const Eigen::Vector2d c = mesh.vertices.row(mesh.triangles(t, 2)).head<2>().transpose();
    const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (area == 0) continue;
    for (int j = 0; j < kCells; ++j)
      for (int i = 0; i < kCells; ++i) {
        const Eigen::Vector2d p(centre(i), centre(j));
        const double u = ((b - p).x() * (c - p).y() - (b - p).y() * (c - p).x()) / area;
        const double v = ((c - p).x() * (a - p).y() - (c - p).y() * (a - p).x()) / area;
        if (u >= 0 && v >= 0 && u + v <= 1) hit[j * kCells + i] = 1;
      }
  }
  int covered = 0, both = 0;
  for (int k = 0; k < kCells * kCells; ++k) covered += hit[k], both += above[k] > 0 && below[k] > 0;
  out.covered = static_cast<double>(covered) / (kCells * kCells);
  out.both_faces = static_cast<double>(both) / (kCells * kCells);
  out.off_face /= static_cast<double>(std::max<std::size_t>(1, vertices));
  out.inside = static_cast<double>(inside) / static_cast<double>(std::max<std::size_t>(1, vertices));
  std::size_t inner = 0, out_facing = 0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose();
    const Eigen::Vector3d centre = (a + b + c) / 3;
    if (std::abs(centre.x()) >= kInner || std::abs(centre.y()) >= kInner) continue;
    ++inner;
    out_facing += (b - a).cross(c - a).z() * centre.z() > 0;
  }
  out.facing_out = inner > 0 ? static_cast<double>(out_facing) / static_cast<double>(inner) : 0.0;
  const MeshTopology topology = mesh_topology(mesh);
  out.inconsistent_edges = topology.inconsistent_edges;
  out.components = topology.components;
  return out;
}

}  // namespace

TEST(ThinParts, ANoisyBladeFourSigmaThickStaysOneConsistentlyOrientedSheet) {
  // 40,000 points, about 0.008 apart on each face; the faces 0.02 apart, the noise σ 0.005 (a
  // quarter of the thickness): each face's points reach well into the other's.
  constexpr double kThickness = 0.02, kSigma = 0.005;
  for (const bool normals : {true, false}) {
    const Reconstruction r = reconstruct(noisy_blade(40000, kThickness, kSigma, normals, 7));
    ASSERT_TRUE(r.mesh);
    const BladeMesh m = inspect(r.mesh->mesh, kThickness);
    std::cout << (normals ? "with" : "without") << " normals: " << m.components << " component(s), cover " << m.covered
              << ", both faces over " << m.both_faces << ", " << m.facing_out
              << " of the triangles facing out, mean distance from the nearer face " << m.off_face / kSigma
              << " sigma, " << m.inside << " of the vertices inside the blade, " << m.inconsistent_edges
              << " inconsistent edges\n";
    EXPECT_EQ(m.components, 1u);
    EXPECT_EQ(m.inconsistent_edges, 0u);
    EXPECT_EQ(m.covered, 1.0);  // no hole in the inner part
    if (normals) {
      // The normals tell the faces apart: both are kept, each facing out, the noise averaged to
      // under half its σ.
      EXPECT_GT(m.both_faces, 0.95);
      EXPECT_GT(m.facing_out, 0.99);
      EXPECT_LT(m.off_face, 0.5 * kSigma);
    } else {
      // Without them the faces are one sheet of points: one sheet inside the blade.
      EXPECT_LT(m.both_faces, 0.05);
      EXPECT_GT(m.inside, 0.99);
    }
  }
}
