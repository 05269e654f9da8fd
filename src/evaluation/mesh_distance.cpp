#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/mesh_distance.hpp>

#include <Eigen/Geometry>
#include <embree3/rtcore.h>

#include <limits>
#include <string>

namespace clustersurf {

struct MeshDistance::Impl {
  Points vertices;
  Triangles triangles;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }

  struct Query {
    const Impl* impl;
    Eigen::Vector3d p;
    ClosestPoint best;
  };

  /// Embree calls this for each triangle whose box the query sphere reaches; shrinking the
  /// radius prunes the rest of the traversal.
  static bool visit(RTCPointQueryFunctionArguments* args) {
    auto* q = static_cast<Query*>(args->userPtr);
    const auto t = static_cast<Eigen::Index>(args->primID);
    const auto tri = q->impl->triangles.row(t);
    const auto& v = q->impl->vertices;
    const Eigen::Vector3d x = closest_point_on_triangle(q->p, v.row(tri(0)).transpose(), v.row(tri(1)).transpose(),
                                                        v.row(tri(2)).transpose());
    const double d2 = (x - q->p).squaredNorm();
    if (d2 < q->best.distance_squared ||
        (d2 == q->best.distance_squared && static_cast<std::int32_t>(t) < q->best.triangle)) {
      q->best = {x, d2, static_cast<std::int32_t>(t)};
      // Float boxes: keep a hair of slack so a triangle at the same distance is still visited.
      args->query->radius = static_cast<float>(std::sqrt(d2)) * (1 + 1e-6f) + std::numeric_limits<float>::min();
      return true;
    }
    return false;
  }
};

MeshDistance::MeshDistance(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->vertices = mesh.vertices;
  impl_->triangles = mesh.triangles;
  check_triangle_indices(mesh);
  const auto nv = mesh.vertices.rows(), nt = mesh.triangles.rows();
  impl_->device = rtcNewDevice("threads=1");
  if (impl_->device == nullptr) throw Error("cannot create the Embree device");
  impl_->scene = rtcNewScene(impl_->device);
  if (nt > 0) {
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), static_cast<std::size_t>(nv)));
    for (Eigen::Index i = 0; i < nv; ++i)
      for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(mesh.vertices(i, k));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), static_cast<std::size_t>(nt)));
    for (Eigen::Index t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) ib[3 * t + k] = static_cast<unsigned>(mesh.triangles(t, k));
    rtcSetGeometryPointQueryFunction(geometry, &Impl::visit);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl_->scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(impl_->scene);
}

MeshDistance::~MeshDistance() = default;
MeshDistance::MeshDistance(MeshDistance&&) noexcept = default;
MeshDistance& MeshDistance::operator=(MeshDistance&&) noexcept = default;

ClosestPoint MeshDistance::closest(const Eigen::Vector3d& query) const {
  Impl::Query q{impl_.get(), query, {}};
  q.best.distance_squared = std::numeric_limits<double>::infinity();
  if (impl_->triangles.rows() == 0) return q.best;
  RTCPointQuery pq;
  pq.x = static_cast<float>(query.x());
  pq.y = static_cast<float>(query.y());
  pq.z = static_cast<float>(query.z());
  pq.time = 0;
  pq.radius = std::numeric_limits<float>::infinity();
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(impl_->scene, &pq, &context, nullptr, &q);
  return q.best;
}

Eigen::Vector3d MeshDistance::triangle_normal(std::int32_t t) const {
  const auto tri = impl_->triangles.row(t);
  const auto& v = impl_->vertices;
  const Eigen::Vector3d n =
      (v.row(tri(1)) - v.row(tri(0))).transpose().cross((v.row(tri(2)) - v.row(tri(0))).transpose());
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

}  // namespace clustersurf
