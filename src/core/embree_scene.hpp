#pragma once
// One Embree device and scene for ray casting (rendering meshes and clouds, scanning meshes).

#include <clustersurf/core/errors.hpp>
#include <clustersurf/core/point_cloud.hpp>

#include <embree3/rtcore.h>

#include <new>

namespace clustersurf::detail {

/// An Embree device and scene holding one geometry; released on destruction.
class EmbreeScene {
 public:
  /// `watertight`: rays never slip between triangles that share an edge (Embree's robust
  /// mode, a little slower): a scanner must not see through a closed mesh.
  explicit EmbreeScene(bool watertight = false) : device_(rtcNewDevice(nullptr)) {
    if (device_ == nullptr) throw Error("Embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    if (watertight) rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  }
  ~EmbreeScene() {
    if (scene_ != nullptr) rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCDevice device() const { return device_; }
  /// Attaches the triangles of `mesh` as the scene's geometry and commits the scene.
  void commit_triangles(const TriangleMesh& mesh) {
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v =
        static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                    3 * sizeof(float), static_cast<std::size_t>(mesh.vertices.rows())));
    auto* f = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned),
                                                             static_cast<std::size_t>(mesh.triangles.rows())));
    if (v == nullptr || f == nullptr) {
      rtcReleaseGeometry(geometry);
      throw std::bad_alloc();
    }
    for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
      for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(mesh.vertices(i, k));
    for (Eigen::Index i = 0; i < mesh.triangles.rows(); ++i)
      for (int k = 0; k < 3; ++k) f[3 * i + k] = static_cast<unsigned>(mesh.triangles(i, k));
    commit(geometry);
  }
  /// Attaches and commits `geometry` (taking it over), then commits the scene.
  void commit(RTCGeometry geometry) {
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw Error("Embree: building the scene failed");
  }

  /// The nearest hit along the ray, if any: (t, unnormalized normal, primitive, u, v).
  bool intersect(const Ray& ray, float t_max, RTCRayHit& rh) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    set_ray(ray, t_max, rh.ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
  /// True when something lies along the ray before t_max.
  bool occluded(const Ray& ray, float t_max) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    set_ray(ray, t_max, r);
    rtcOccluded1(scene_, &context, &r);
    return r.tfar < 0;
  }

 private:
  static void set_ray(const Ray& ray, float t_max, RTCRay& r) {
    r.org_x = static_cast<float>(ray.origin.x()), r.org_y = static_cast<float>(ray.origin.y());
    r.org_z = static_cast<float>(ray.origin.z());
    r.dir_x = static_cast<float>(ray.direction.x()), r.dir_y = static_cast<float>(ray.direction.y());
    r.dir_z = static_cast<float>(ray.direction.z());
    r.tnear = 0, r.tfar = t_max, r.time = 0, r.mask = ~0u, r.id = 0, r.flags = 0;
  }
  RTCDevice device_;
  RTCScene scene_ = nullptr;
};

}  // namespace clustersurf::detail
