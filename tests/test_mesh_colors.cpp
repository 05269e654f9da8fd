// Colors on a mesh: a scan's colors carried from its points (colors_from_points(), the pipeline's
// default), sharp where the colors change and blind to a stray point; on the real aerial LAS
// tile, each vertex's color close to the points' around it, through PLY and GLB; E57 and PTX
// scans' colors; the scanner's intensity as grey on request.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "e57_writer.hpp"
#include "test_support.hpp"

using namespace clustersurf;

namespace {

using Rgb = Eigen::Matrix<std::uint8_t, 1, 3>;
const Rgb kRed(220, 30, 30), kBlue(20, 40, 200);

/// A sphere of radius 1 whose points are red above z = 0 and blue below.
PointCloud two_color_sphere(int n) {
  PointCloud cloud = test::sample_sphere(n);
  cloud.colors.resize(cloud.size(), 3);
  for (Eigen::Index i = 0; i < cloud.size(); ++i) cloud.colors.row(i) = cloud.positions(i, 2) > 0 ? kRed : kBlue;
  return cloud;
}

}  // namespace

// The pipeline colors a mesh from its input by default: every vertex farther than two point
// spacings from the border between the colors has its side's color exactly, and the vertices
// of neither color lie within a spacing of the border.
TEST(MeshColors, TwoColorSphereHasASharpBorder) {
  const PointCloud cloud = two_color_sphere(20000);
  const Reconstruction r = reconstruct(cloud);
  ASSERT_TRUE(r.mesh.has_value());
  const TriangleMesh& mesh = r.mesh->mesh;
  ASSERT_EQ(mesh.colors.rows(), mesh.vertices.rows());
  const double spacing = r.tree.point_spacing;
  std::size_t far = 0, wrong = 0, mixed = 0;
  double widest_mix = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const double z = mesh.vertices(v, 2);
    const Rgb c = mesh.colors.row(v);
    if (std::abs(z) > 2 * spacing) {
      ++far;
      wrong += c != (z > 0 ? kRed : kBlue);
    }
    if (c != kRed && c != kBlue) ++mixed, widest_mix = std::max(widest_mix, std::abs(z));
  }
  EXPECT_GT(far, static_cast<std::size_t>(0.9 * static_cast<double>(mesh.vertices.rows())));
  EXPECT_EQ(wrong, 0u);
  EXPECT_LE(widest_mix, spacing) << mixed << " vertices of neither color";
}

// One point of another color among a patch's points changes no vertex: a median, not a mean.
TEST(MeshColors, AStrayPointChangesNothing) {
  PointCloud cloud = test::sample_plane(40, 40);
  cloud.colors = Colors::Constant(cloud.size(), 3, 90);
  cloud.colors.row(820) << 255, 255, 0;
  TriangleMesh mesh;
  mesh.vertices = cloud.positions;
  mesh.vertices.col(2).array() += 0.002;  // just off the plane, every vertex right at a point
  const KdTree index(cloud.positions);
  const Colors c = colors_from_points(mesh, index, cloud.colors);
  EXPECT_EQ(c, Colors::Constant(cloud.size(), 3, 90));
  EXPECT_THROW(colors_from_points(mesh, index, cloud.colors.topRows(10)), OptionError);
}

// Without colors in the input, or without the input, the mesh has none; "none" turns them off.
TEST(MeshColors, OnlyWhenTheInputHasThem) {
  PointCloud cloud = two_color_sphere(4000);
  ReconstructOptions options;
  options.meshing.coloring = MeshColoring::None;
  EXPECT_EQ(reconstruct(cloud, options).mesh->mesh.colors.rows(), 0);
  const Reconstruction colored = reconstruct(cloud);
  EXPECT_EQ(mesh_tree(colored.tree).mesh.colors.rows(), 0);  // no input given
  cloud.colors.resize(0, 3);
  EXPECT_EQ(reconstruct(cloud).mesh->mesh.colors.rows(), 0);
  EXPECT_EQ(parse_mesh_coloring("input"), MeshColoring::FromInput);
  EXPECT_EQ(SurfaceMeshOptions{}.coloring, MeshColoring::FromInput);
}

// The real aerial tile (110 k points with RGB): the mesh is colored, each vertex within a
// small distance of the colors of the points nearest it, and PLY and GLB keep the colors.
TEST(MeshColors, TheLasTileCarriesItsColors) {
  const auto file = test::shared_data("formats/las/autzen_trim.las");
  if (!file) GTEST_SKIP() << "the shared LAS sample formats/las/autzen_trim.las is not here";
  const PointCloud cloud = read_point_cloud(*file);
  ASSERT_TRUE(cloud.has_colors());
  const Reconstruction r = reconstruct(cloud);
  const TriangleMesh& mesh = r.mesh->mesh;
  ASSERT_EQ(mesh.colors.rows(), mesh.vertices.rows());
  EXPECT_EQ(mesh.up, UpAxis::Z);
  // Against the nearest point's color: the mean channel difference is well under the spread of
  // the colors among neighbouring points, and nearly every vertex is close.
  const KdTree index(cloud.positions);
  std::vector<double> gaps;
  std::vector<Neighbor> nb;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    index.knn(mesh.vertices.row(v).transpose(), 1, nb);
    const Eigen::Vector3i d = mesh.colors.row(v).cast<int>() - cloud.colors.row(nb[0].index).cast<int>();
    gaps.push_back(d.cwiseAbs().cast<double>().mean());
  }
  std::sort(gaps.begin(), gaps.end());
  double mean = 0;
  for (const double g : gaps) mean += g / static_cast<double>(gaps.size());
  EXPECT_LT(mean, 12.0);
  EXPECT_LT(gaps[gaps.size() * 9 / 10], 30.0);

  const test::TempDir dir;
  write_triangle_mesh(dir / "tile.ply", mesh);
  const TriangleMesh back = read_triangle_mesh(dir / "tile.ply");
  EXPECT_EQ(back.colors, mesh.colors);
  EXPECT_EQ(back.up, UpAxis::Z);
  write_triangle_mesh(dir / "tile.glb", mesh);
  const std::string glb = test::read_file(dir / "tile.glb");
  EXPECT_NE(glb.find("\"COLOR_0\""), std::string::npos);
  EXPECT_NE(glb.find("\"rotation\":[-0.7071067811865476,0,0,0.7071067811865476]"), std::string::npos);  // to +y up
}

// On request, the scanner's intensity as grey: robust to a few saturated returns, and carried
// onto the mesh like colors (equal channels, white where the intensity is high).
TEST(MeshColors, IntensityBecomesGreyOnRequest) {
  Eigen::VectorXf intensity(200);
  for (int i = 0; i < 200; ++i) intensity(i) = static_cast<float>(i);
  intensity(7) = 1e9f;  // a saturated return
  const Colors grey = intensity_grey(intensity);
  EXPECT_EQ(grey(0, 0), 0);
  EXPECT_EQ(grey(199, 0), 255);
  EXPECT_NEAR(grey(100, 0), 128, 2);  // the outlier does not squeeze the range
  EXPECT_EQ(grey(100, 0), grey(100, 2));

  PointCloud cloud = test::sample_sphere(8000);
  Eigen::VectorXf values(cloud.size());
  for (Eigen::Index i = 0; i < cloud.size(); ++i) values(i) = cloud.positions(i, 2) > 0 ? 3000.0f : 40.0f;
  cloud.attributes.push_back({"intensity", values});
  EXPECT_EQ(reconstruct(cloud).mesh->mesh.colors.rows(), 0);  // no RGB: no colors by default
  ReconstructOptions options;
  options.meshing.coloring = parse_mesh_coloring("intensity");
  const TriangleMesh mesh = reconstruct(cloud, options).mesh->mesh;
  ASSERT_EQ(mesh.colors.rows(), mesh.vertices.rows());
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    EXPECT_EQ(mesh.colors(v, 0), mesh.colors(v, 1));
    if (std::abs(mesh.vertices(v, 2)) > 0.1) {
      EXPECT_EQ(mesh.colors(v, 0), mesh.vertices(v, 2) > 0 ? 255 : 0);
    }
  }
}

// A terrestrial scanner's files: an E57 scan with colorRed/Green/Blue and the shared PTX sample
// with RGB give colored meshes, z-up, each vertex's color one of its points' neighbourhood's.
TEST(MeshColors, E57AndPtxScansCarryTheirColors) {
  using namespace clustersurf::test;
  const PointCloud sphere = two_color_sphere(6000);
  std::vector<double> x, y, z;
  std::vector<std::int64_t> r, g, b;
  for (Eigen::Index i = 0; i < sphere.size(); ++i) {
    x.push_back(sphere.positions(i, 0)), y.push_back(sphere.positions(i, 1)), z.push_back(sphere.positions(i, 2));
    r.push_back(sphere.colors(i, 0)), g.push_back(sphere.colors(i, 1)), b.push_back(sphere.colors(i, 2));
  }
  const TestScan scan{{float_field("cartesianX", x), float_field("cartesianY", y), float_field("cartesianZ", z),
                       int_field("colorRed", 0, 255, r), int_field("colorGreen", 0, 255, g),
                       int_field("colorBlue", 0, 255, b)}};
  const TempDir dir;
  write_file(dir / "sphere.e57", write_e57({scan}).bytes);
  const PointCloud e57 = read_point_cloud(dir / "sphere.e57");
  ASSERT_TRUE(e57.has_colors());
  EXPECT_EQ(e57.up, UpAxis::Z);
  const TriangleMesh mesh = reconstruct(e57).mesh->mesh;
  ASSERT_EQ(mesh.colors.rows(), mesh.vertices.rows());
  EXPECT_EQ(mesh.up, UpAxis::Z);
  std::size_t wrong = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    if (std::abs(mesh.vertices(v, 2)) > 0.1) {
      wrong += Rgb(mesh.colors.row(v)) != (mesh.vertices(v, 2) > 0 ? kRed : kBlue);
    }
  EXPECT_EQ(wrong, 0u);

  const auto ptx = shared_data("formats/ptx/1.2-with-color.ptx");
  if (!ptx) GTEST_SKIP() << "the shared PTX sample formats/ptx/1.2-with-color.ptx is not here";
  const PointCloud cloud = read_point_cloud(*ptx);
  ASSERT_TRUE(cloud.has_colors());
  const TriangleMesh scanned = reconstruct(cloud).mesh->mesh;
  ASSERT_EQ(scanned.colors.rows(), scanned.vertices.rows());
  EXPECT_EQ(scanned.up, UpAxis::Z);
  // Each channel of a vertex lies within the range of its 8 nearest points' (a median's; the
  // clustered points it was taken from are these but the few outliers).
  const KdTree index(cloud.positions);
  std::vector<Neighbor> nb;
  std::size_t outside = 0;
  for (Eigen::Index v = 0; v < scanned.vertices.rows(); ++v) {
    index.knn(scanned.vertices.row(v).transpose(), kColorNeighbors, nb);
    for (int k = 0; k < 3; ++k) {
      int lo = 255, hi = 0;
      for (const Neighbor& n : nb)
        lo = std::min<int>(lo, cloud.colors(n.index, k)), hi = std::max<int>(hi, cloud.colors(n.index, k));
      outside += scanned.colors(v, k) < lo || scanned.colors(v, k) > hi;
    }
  }
  EXPECT_LE(static_cast<double>(outside), 0.01 * 3 * static_cast<double>(scanned.vertices.rows()));
}
