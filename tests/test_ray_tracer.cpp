// Ray tracer: the silhouette of a sphere matches the analytic disc, normals face the camera,
// implicit and brute force give the same picture, every view draws something where expected,
// results do not depend on the thread count, meshes and clouds render with the same camera,
// georeferenced geometry draws as it does next to zero.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/render/render.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>
#include <set>

#include "test_support.hpp"

using namespace clustersurf;

namespace {

constexpr double kDistance = 4.0;

const ClusterTree& sphere_tree() {
  static const ClusterTree tree = [] {
    const PointCloud c = test::sample_sphere(20000, 1.0);
    ClusterTree t = build_cluster_tree(c);
    orient_tree(t, c);
    return t;
  }();
  return tree;
}

/// Looking at the origin from +z at distance 4, transparent background.
RenderOptions front_view(int w, int h) {
  RenderOptions o;
  o.width = w, o.height = h;
  o.camera.eye = Eigen::Vector3d(0, 0, kDistance);
  o.camera.target = Eigen::Vector3d::Zero();
  o.camera.fov = 40;
  o.background = {255, 255, 255, 0};
  return o;
}

std::size_t covered(const Image& img) {
  std::size_t n = 0;
  for (const Rgba8& p : img.pixels) n += p.a > 0;
  return n;
}

/// Area in pixels of a unit sphere's silhouette seen by front_view().
double disc_area(const RenderOptions& o) {
  const double f = 0.5 * o.height / std::tan(0.5 * o.camera.fov * std::numbers::pi / 180);
  const double r = f * std::tan(std::asin(1.0 / kDistance));
  return std::numbers::pi * r * r;
}

}  // namespace

TEST(RayTracer, SphereSilhouetteMatchesAnalyticDisc) {
  const RenderOptions o = front_view(240, 240);
  RenderStats stats;
  const Image img = render_tree(sphere_tree(), o, &stats);
  const double expected = disc_area(o);
  EXPECT_NEAR(static_cast<double>(covered(img)), expected, 0.02 * expected);
  EXPECT_EQ(stats.rays, 240u * 240u);
  EXPECT_EQ(stats.hits, covered(img));
  // Corners are background, the center is covered.
  EXPECT_EQ(img.at(0, 0).a, 0);
  EXPECT_EQ(img.at(120, 120).a, 255);
}

TEST(RayTracer, CenterNormalFacesTheCamera) {
  const RenderOptions o = front_view(240, 240);
  const Camera cam = make_camera({}, o.camera, o.width, o.height);
  for (IntersectMode mode : {IntersectMode::Implicit, IntersectMode::HitBlend, IntersectMode::BruteForce}) {
    RenderOptions m = o;
    m.mode = mode;
    const auto hit = intersect_surface(sphere_tree(), cam.ray(120, 120), m);
    ASSERT_TRUE(hit.has_value()) << to_string(mode);
    EXPECT_NEAR(hit->t, kDistance - 1, 0.01) << to_string(mode);
    EXPECT_GT(hit->normal.dot(Eigen::Vector3d::UnitZ()), 0.99) << to_string(mode);
    EXPECT_GE(hit->node, 0);
  }
}

TEST(RayTracer, ImplicitAndBruteForceGiveTheSamePicture) {
  const PointCloud c = test::sample_torus(15000);
  ClusterTree t = build_cluster_tree(c);
  orient_tree(t, c);
  RenderOptions o;
  o.width = 160, o.height = 120;
  o.camera.elevation = 40;
  const Image a = render_tree(t, o);
  o.mode = IntersectMode::BruteForce;
  const Image b = render_tree(t, o);
  std::size_t same = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) same += a.pixels[i] == b.pixels[i];
  EXPECT_EQ(same, a.pixels.size());  // the tiles' and blocks' culls keep every support a ray crosses
  EXPECT_GT(covered(a), 0u);
}

TEST(RayTracer, HitBlendSilhouetteCloseToImplicit) {
  RenderOptions o = front_view(160, 160);
  o.mode = IntersectMode::HitBlend;
  const double expected = disc_area(o);
  EXPECT_NEAR(static_cast<double>(covered(render_tree(sphere_tree(), o))), expected, 0.03 * expected);
}

TEST(RayTracer, EveryViewDrawsInTheExpectedRegion) {
  const PointCloud points = test::sample_sphere(20000, 1.0);
  RenderOptions base = front_view(160, 160);
  base.background = {255, 255, 255, 255};
  const double r = std::sqrt(disc_area(base) / std::numbers::pi);
  for (ShowMode show : {ShowMode::Surface, ShowMode::Clusters, ShowMode::Spheres, ShowMode::Proxies, ShowMode::Error}) {
    RenderOptions o = base;
    o.show = show;
    o.reference_points = &points.positions;
    o.error_scale = 0.05;  // twice the sample spacing
    const Image img = render_tree(sphere_tree(), o);
    std::size_t inside = 0, inside_drawn = 0;
    std::set<std::uint32_t> colors;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const double d = std::hypot(x + 0.5 - 80, y + 0.5 - 80);
        const Rgba8 p = img.at(x, y);
        if (d < 0.9 * r) {
          ++inside;
          inside_drawn += !(p == base.background);
          colors.insert(static_cast<std::uint32_t>(p.r) << 16 | static_cast<std::uint32_t>(p.g) << 8 | p.b);
        }
      }
    EXPECT_GT(inside_drawn, 0.95 * static_cast<double>(inside)) << to_string(show);
    if (show != ShowMode::Spheres) {  // supports reach beyond the surface; everything else stays inside
      EXPECT_EQ(img.at(1, 1), base.background) << to_string(show);
      EXPECT_EQ(img.at(158, 1), base.background) << to_string(show);
    }
    if (show == ShowMode::Clusters || show == ShowMode::Proxies) {
      EXPECT_GT(colors.size(), 100u) << to_string(show);
    }
    if (show == ShowMode::Error) {
      // Near the input: mostly green; the legend is drawn in the bottom-left corner.
      std::size_t green = 0, legend = 0;
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
          const Rgba8 p = img.at(x, y);
          green += p.g > p.r + 40 && p.g > p.b + 40;
          if (x < 70 && y > 130) legend += !(p == base.background);
        }
      EXPECT_GT(green, inside / 2);
      EXPECT_GT(legend, 200u);
    }
  }
}

TEST(RayTracer, HighlightDrawsOneClusterInRed) {
  RenderOptions o = front_view(160, 160);
  const ClusterTree& t = sphere_tree();
  // The leaf nearest the camera.
  const auto hit = intersect_surface(t, make_camera({}, o.camera, 160, 160).ray(80, 80), o);
  ASSERT_TRUE(hit);
  o.highlight = hit->node;
  const Image img = render_tree(t, o);
  std::size_t red = 0, grey = 0;
  for (const Rgba8& p : img.pixels) {
    if (p.a == 0) continue;
    if (p.r > p.g + 60 && p.r > p.b + 60)
      ++red;
    else if (std::abs(p.r - p.g) < 10 && std::abs(p.g - p.b) < 10)
      ++grey;
  }
  EXPECT_GT(red, 20u);
  EXPECT_GT(grey, 20u);
  EXPECT_LT(red, grey + red - 20);
  o.highlight = static_cast<std::int32_t>(t.nodes.size());
  EXPECT_THROW(render_tree(t, o), OptionError);
}

TEST(RayTracer, SamePictureForAnyThreadCount) {
  RenderOptions o = front_view(96, 96);
  o.samples = 3;
  o.ambient_occlusion = true;
  Image one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = render_tree(sphere_tree(), o);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = render_tree(sphere_tree(), o);
  }
  EXPECT_TRUE(one.pixels == two.pixels);
}

TEST(RayTracer, CancelThrows) {
  RenderOptions o = front_view(64, 64);
  const auto progress = [](std::string_view, double f) { return f < 0.3; };
  EXPECT_THROW(render_tree(sphere_tree(), o, nullptr, progress), Cancelled);
}

TEST(RayTracer, RejectsBadOptions) {
  RenderOptions o = front_view(64, 64);
  o.samples = 0;
  EXPECT_THROW(render_tree(sphere_tree(), o), OptionError);
  o = front_view(64, 64);
  o.show = ShowMode::Error;  // without points
  EXPECT_THROW(render_tree(sphere_tree(), o), OptionError);
}

TEST(RayTracer, MeshAndCloudMatchTheTreeSilhouette) {
  const RenderOptions o = front_view(160, 160);
  const double expected = disc_area(o);
  const ImplicitSurface surface(sphere_tree());
  MeshOptions mo;
  mo.resolution = 64;
  const TriangleMesh mesh = extract_mesh(surface, mo);
  EXPECT_NEAR(static_cast<double>(covered(render_mesh(mesh, o))), expected, 0.02 * expected);
  const PointCloud cloud = test::sample_sphere(20000, 1.0);
  // Splats reach a little past the silhouette: allow their radius.
  EXPECT_NEAR(static_cast<double>(covered(render_points(cloud, o))), expected, 0.06 * expected);
  PointCloud bare = cloud;
  bare.normals.resize(0, 3);
  EXPECT_NEAR(static_cast<double>(covered(render_points(bare, o))), expected, 0.06 * expected);
}

// A tree, mesh or cloud of a z-up input is pictured z-up unless the camera says otherwise: the
// same picture as the y-up scene with the up vector given.
TEST(RayTracer, TheScenesUpAxisIsTheDefaultUp) {
  PointCloud cloud = test::sample_torus(6000);
  cloud.up = UpAxis::Z;
  const ClusterTree tree = build_cluster_tree(cloud);
  RenderOptions o;
  o.width = 96;
  o.height = 72;
  const Image z_default = render_tree(tree, o);
  ClusterTree y_tree = tree;
  y_tree.up = UpAxis::Y;
  RenderOptions explicit_up = o;
  explicit_up.camera.up = Eigen::Vector3d::UnitZ();
  EXPECT_EQ(z_default.pixels, render_tree(y_tree, explicit_up).pixels);
  EXPECT_NE(z_default.pixels, render_tree(y_tree, o).pixels);
  const Image cloud_z = render_points(cloud, o);
  PointCloud y_cloud = cloud;
  y_cloud.up = UpAxis::Y;
  EXPECT_EQ(cloud_z.pixels, render_points(y_cloud, explicit_up).pixels);
}

// A mesh or cloud in georeferenced coordinates (a UTM northing of 5,213 km, where float steps
// are half a metre) is drawn as the same shape next to zero is: a sphere 20 m wide keeps its
// outline.
TEST(RayTracer, GeometryFarFromZeroDrawsAsNearIt) {
  const double radius = 20;
  const Eigen::Vector3d site(636590.49, 5213216.55, 400.25);
  RenderOptions near_view = front_view(160, 160);
  *near_view.camera.eye *= radius;
  RenderOptions far_view = near_view;
  *far_view.camera.eye += site;
  *far_view.camera.target += site;
  const auto outlines_differ = [](const Image& a, const Image& b) {
    std::size_t differ = 0;
    for (std::size_t p = 0; p < a.pixels.size(); ++p) differ += (a.pixels[p].a > 0) != (b.pixels[p].a > 0);
    return static_cast<double>(differ);
  };
  const TriangleMesh near = test::icosphere(4, radius);
  TriangleMesh far = near;
  far.vertices.rowwise() += site.transpose();
  const Image a = render_mesh(near, near_view);
  EXPECT_NEAR(static_cast<double>(covered(a)), disc_area(near_view), 0.02 * disc_area(near_view));
  EXPECT_LE(outlines_differ(a, render_mesh(far, far_view)), 0.002 * disc_area(near_view));
  PointCloud cloud = test::sample_sphere(20000, radius), far_cloud = cloud;
  far_cloud.positions.rowwise() += site.transpose();
  EXPECT_LE(outlines_differ(render_points(cloud, near_view), render_points(far_cloud, far_view)),
            0.002 * disc_area(near_view));
}
