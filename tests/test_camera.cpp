// Camera: rays through the image, automatic framing keeps the whole box in view, explicit eye.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/camera.hpp>
#include <clustersurf/render/image.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace clustersurf;

namespace {

/// Pixel coordinates of x seen by the camera (y down).
Eigen::Vector2d project(const Camera& c, const Eigen::Vector3d& x) {
  const Eigen::Vector3d p = x - c.eye;
  const double z = p.dot(c.forward);
  return {0.5 * c.width + c.focal_pixels() * p.dot(c.right) / z, 0.5 * c.height - c.focal_pixels() * p.dot(c.up) / z};
}

}  // namespace

TEST(Camera, CenterRayLooksAtTarget) {
  CameraOptions o;
  o.eye = Eigen::Vector3d(0, 0, 5);
  o.target = Eigen::Vector3d::Zero();
  const Camera c = make_camera({}, o, 200, 100);
  const Ray r = c.ray(100, 50);
  EXPECT_NEAR((r.direction - Eigen::Vector3d(0, 0, -1)).norm(), 0, 1e-12);
  EXPECT_NEAR(r.direction.norm(), 1, 1e-12);
  // The top edge of the picture is fov/2 above the axis.
  const Ray top = c.ray(100, 0);
  EXPECT_NEAR(std::acos(top.direction.dot(c.forward)) * 180 / std::numbers::pi, 0.5 * o.fov, 1e-9);
  EXPECT_GT(top.direction.y(), 0);
  EXPECT_GT(c.ray(200, 50).direction.x(), 0);  // right is +x looking down -z with +y up
}

TEST(Camera, AutomaticFramingShowsTheWholeBox) {
  BoundingBox box;
  box.extend({-1, 0, -0.5});
  box.extend({2, 0.7, 0.5});
  for (double az : {0.0, 30.0, 135.0, 270.0})
    for (double el : {-30.0, 0.0, 20.0, 80.0}) {
      CameraOptions o;
      o.azimuth = az, o.elevation = el;
      const Camera c = make_camera(box, o, 320, 200);
      double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d corner(k & 1 ? box.max.x() : box.min.x(), k & 2 ? box.max.y() : box.min.y(),
                                     k & 4 ? box.max.z() : box.min.z());
        const Eigen::Vector2d p = project(c, corner);
        min_x = std::min(min_x, p.x()), max_x = std::max(max_x, p.x());
        min_y = std::min(min_y, p.y()), max_y = std::max(max_y, p.y());
      }
      EXPECT_GE(min_x, 0) << az << " " << el;
      EXPECT_LE(max_x, 320) << az << " " << el;
      EXPECT_GE(min_y, 0) << az << " " << el;
      EXPECT_LE(max_y, 200) << az << " " << el;
      // ... and fills much of it along one axis (the target is the box center, so perspective
      // leaves one side a little wider).
      EXPECT_TRUE(max_x - min_x > 0.6 * 320 || max_y - min_y > 0.6 * 200) << az << " " << el;
    }
}

// A z-up scene (a survey) is looked at from above by default: the eye above the target, the
// picture's up toward +z; the azimuth turns from the front axis +x toward +y.
TEST(Camera, ZUpSceneIsSeenFromAbove) {
  BoundingBox terrain;
  terrain.extend({0, 0, 0});
  terrain.extend({100, 60, 4});  // flat in z
  CameraOptions o;
  o.up = Eigen::Vector3d::UnitZ();
  o.azimuth = 0;
  const Camera c = make_camera(terrain, o, 320, 240);
  const Eigen::Vector3d center(50, 30, 2);
  EXPECT_GT(c.eye.z(), center.z() + 0.3 * (c.eye - center).norm());  // 20 degrees up: sin 20 > 0.3
  EXPECT_GT(c.up.z(), 0.9);
  EXPECT_NEAR(c.eye.y(), center.y(), 1e-9);  // azimuth 0: in the x-z plane
  EXPECT_GT(c.eye.x(), center.x());
}

TEST(Camera, RejectsBadOptions) {
  BoundingBox box;
  box.extend({0, 0, 0});
  box.extend({1, 1, 1});
  CameraOptions o;
  EXPECT_THROW(make_camera(box, o, 0, 10), OptionError);
  o.fov = 0;
  EXPECT_THROW(make_camera(box, o, 10, 10), OptionError);
  o = {};
  o.eye = Eigen::Vector3d(0.5, 5, 0.5);  // looking straight down the up axis
  EXPECT_THROW(make_camera(box, o, 10, 10), OptionError);
  o.up = Eigen::Vector3d::UnitZ();
  EXPECT_NO_THROW(make_camera(box, o, 10, 10));
}

TEST(Image, PngHasMagicAndTextDraws) {
  Image img(64, 32, {255, 255, 255, 255});
  draw_text(img, 2, 2, "0.123 ab", {0, 0, 0, 255}, 2);
  int dark = 0;
  for (const Rgba8& p : img.pixels) dark += p.r < 128;
  EXPECT_GT(dark, 20);
  EXPECT_GT(text_width("0.123", 1), 10);
  const std::string png = encode_png(img);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const Image cells[2] = {img, img};
  const std::string labels[2] = {"a", "b"};
  const Image grid = compose_grid(cells, labels, {255, 255, 255, 255});
  EXPECT_EQ(grid.width, 128);
  EXPECT_GT(grid.height, 32);
}
