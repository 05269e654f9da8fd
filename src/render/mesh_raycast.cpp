// Pictures of triangle meshes and point clouds, so results of other tools can be shown with
// the same camera as a tree. Ray casting uses Embree (Debian's libembree-dev): its BVHs are
// the well-kept choice for triangles, and its oriented-disc and sphere points draw splats.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/render.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>

#include "core/embree_scene.hpp"
#include "render/pixel_loop.hpp"

#include <embree3/rtcore.h>

#include <limits>
#include <string>

namespace clustersurf {

namespace {

using detail::EmbreeScene;
using render::Color;
using render::SampleResult;

/// Shading shared by meshes and clouds: the hit's color, optional occlusion.
class Splatter {
 public:
  Splatter(const EmbreeScene& scene, const RenderOptions& options, const Camera& camera, double diagonal)
      : scene_(scene), options_(options), lights_(render::camera_lighting(camera)), diagonal_(diagonal) {}

  template <class ColorAt>
  SampleResult trace(const Ray& ray, std::uint64_t seed, ColorAt&& color_at) const {
    RTCRayHit rh;
    if (!scene_.intersect(ray, std::numeric_limits<float>::infinity(), rh)) return {};
    Eigen::Vector3d n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    Color base = render::kSurfaceColor;
    color_at(rh.hit.primID, rh.hit.u, rh.hit.v, base, n);
    n = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d(-ray.direction);
    double occlusion = 1;
    if (options_.ambient_occlusion) {
      const Eigen::Vector3d facing = n.dot(ray.direction) > 0 ? Eigen::Vector3d(-n) : n;
      const Eigen::Vector3d x =
          ray.origin + static_cast<double>(rh.ray.tfar) * ray.direction + render::kOcclusionOffset * diagonal_ * facing;
      occlusion = render::ambient_occlusion(facing, seed, [&](const Eigen::Vector3d& d) {
        return scene_.occluded({x, d}, static_cast<float>(render::kOcclusionReach * diagonal_));
      });
    }
    return {render::shade(lights_, n, ray.direction, base, occlusion), 1.0};
  }

 private:
  const EmbreeScene& scene_;
  const RenderOptions& options_;
  render::Lighting lights_;
  double diagonal_;
};

}  // namespace

Image render_mesh(const TriangleMesh& mesh, const RenderOptions& options, RenderStats* stats,
                  const ProgressCallback& progress) {
  render::check_common_options(options);
  if (mesh.triangles.rows() == 0) throw OptionError("cannot render a mesh without triangles");
  // Embree works in float: a mesh far from zero is drawn from next to it, as the readers move one.
  if (!origin_shift(bounding_box(mesh.vertices)).isZero()) {
    TriangleMesh near = mesh;
    shift_to_origin(near);
    return render_mesh(near, options, stats, progress);
  }
  const Camera camera = render::scene_camera(options, bounding_box(mesh.vertices), mesh.origin, mesh.up);
  EmbreeScene scene;
  scene.commit_triangles(mesh);
  const bool smooth = mesh.normals.rows() == mesh.vertices.rows();
  const bool colored = mesh.colors.rows() == mesh.vertices.rows();
  const Splatter splatter(scene, options, camera, bounding_box(mesh.vertices).diagonal());
  const auto color_at = [&](unsigned prim, float u, float w, Color& base, Eigen::Vector3d& normal) {
    const auto tri = mesh.triangles.row(prim);
    const double b0 = 1.0 - u - w, b1 = u, b2 = w;
    if (smooth) {
      const Eigen::Vector3d n = b0 * mesh.normals.row(tri(0)).transpose() + b1 * mesh.normals.row(tri(1)).transpose() +
                                b2 * mesh.normals.row(tri(2)).transpose();
      if (n.norm() > 0) normal = n;
    }
    if (colored)
      base = (b0 * mesh.colors.row(tri(0)).cast<double>() + b1 * mesh.colors.row(tri(1)).cast<double>() +
              b2 * mesh.colors.row(tri(2)).cast<double>())
                 .transpose() /
             255.0;
  };
  return render::trace_image(
      camera, options,
      [&](int, int, int, int) {
        return [&](const Ray& ray, std::uint64_t seed) { return splatter.trace(ray, seed, color_at); };
      },
      stats, progress);
}

Image render_points(const PointCloud& cloud, const RenderOptions& options, RenderStats* stats,
                    const ProgressCallback& progress) {
  render::check_common_options(options);
  if (cloud.empty()) throw OptionError("cannot render an empty point cloud");
  if (!origin_shift(bounding_box(cloud.positions)).isZero()) {
    PointCloud near = cloud;
    shift_to_origin(near);
    return render_points(near, options, stats, progress);
  }
  const Camera camera = render::scene_camera(options, bounding_box(cloud.positions), cloud.origin, cloud.up);
  double radius = options.point_radius;
  if (radius == 0) {
    const CloudStats st = compute_stats(cloud, 20000);
    radius = st.mean_spacing > 0 ? 0.75 * st.mean_spacing : 1e-3 * std::max(st.diagonal, 1e-9);
  }
  EmbreeScene scene;
  const bool oriented = cloud.has_normals();
  RTCGeometry geometry =
      rtcNewGeometry(scene.device(), oriented ? RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT : RTC_GEOMETRY_TYPE_SPHERE_POINT);
  const auto n = static_cast<std::size_t>(cloud.size());
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), n));
  if (v == nullptr) throw std::bad_alloc();
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k)
      v[4 * i + static_cast<std::size_t>(k)] = static_cast<float>(cloud.positions(static_cast<Eigen::Index>(i), k));
    v[4 * i + 3] = static_cast<float>(radius);
  }
  if (oriented) {
    auto* nb = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), n));
    if (nb == nullptr) throw std::bad_alloc();
    for (std::size_t i = 0; i < n; ++i) {
      Eigen::Vector3d nn = cloud.normals.row(static_cast<Eigen::Index>(i)).transpose();
      if (!(nn.norm() > 0)) nn = Eigen::Vector3d::UnitZ();
      nn.normalize();
      for (int k = 0; k < 3; ++k) nb[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(nn(k));
    }
  }
  scene.commit(geometry);
  const Splatter splatter(scene, options, camera, bounding_box(cloud.positions).diagonal());
  const auto color_at = [&](unsigned prim, float, float, Color& base, Eigen::Vector3d&) {
    if (cloud.has_colors()) base = cloud.colors.row(prim).cast<double>().transpose() / 255.0;
  };
  return render::trace_image(
      camera, options,
      [&](int, int, int, int) {
        return [&](const Ray& ray, std::uint64_t seed) { return splatter.trace(ray, seed, color_at); };
      },
      stats, progress);
}

}  // namespace clustersurf
