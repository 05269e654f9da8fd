// Self-intersections of a triangle mesh: candidate pairs from Embree's BVH collision of the mesh
// with itself, then a triangle–triangle test in double precision that knows which corners the
// two triangles share.
//
// The test. A triangle's plane is its unit normal through a corner; a point closer to it than
// τ = tolerance × (the longer of the two triangles' longest edges) lies in it. Two closed
// triangles meet exactly when an edge of one meets the other (their intersection, when not
// empty, is a segment or a convex polygon whose corners lie on edges), and a segment meets a
// triangle where it crosses the plane (a crossing point computed from distances at least τ
// apart, so well conditioned), or, lying in the plane, where it meets the triangle in the plane
// (2D tests on the plane's projection along its dominant axis). Shared corners change the
// question: sharing one corner v, the triangles' intersection is a segment from v (or a polygon
// in their common plane) and reaches beyond v exactly when the edge opposite v of one meets
// the other; sharing an edge, two triangles in different planes meet only on that edge, in
// the same plane they overlap exactly when both lie on the same side of it (folded flat).

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_check.hpp>

#include "mesh/triangle_boxes.hpp"
#include "spatial/position_ids.hpp"

#include <Eigen/Geometry>
#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <numeric>
#include <string>

namespace clustersurf {

namespace {

using Vec = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
using Corners = std::array<Vec, 3>;
using CornerIds = std::array<std::int64_t, 3>;

/// A triangle's plane (unit normal; zero when the triangle is too thin to define one) and size.
struct Plane {
  Vec normal = Vec::Zero();
  double size = 0;  ///< longest edge
};

Plane plane_of(const Corners& t, double tolerance) {
  Plane p;
  p.size = std::sqrt(std::max({(t[1] - t[0]).squaredNorm(), (t[2] - t[1]).squaredNorm(), (t[0] - t[2]).squaredNorm()}));
  const Vec n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double twice_area = n.norm();
  // Height over the longest edge = twice_area / size; thinner than tolerance × size: no plane.
  if (std::isfinite(twice_area) && std::isfinite(p.size) && twice_area > 0 && twice_area > tolerance * p.size * p.size)
    p.normal = n / twice_area;
  return p;
}

int side(double h, double tau) { return h > tau ? 1 : (h < -tau ? -1 : 0); }

/// Projection onto a plane along the normal's dominant axis (distances shrink by at most √3).
struct Projection {
  int i = 0, j = 1;
  explicit Projection(const Vec& normal) {
    int k = 0;
    normal.cwiseAbs().maxCoeff(&k);
    i = (k + 1) % 3;
    j = (k + 2) % 3;
  }
  Vec2 operator()(const Vec& p) const { return {p[i], p[j]}; }
};

double cross2(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

/// Side of c of the line through a and b, 0 within distance tau of it.
int side2(const Vec2& a, const Vec2& b, const Vec2& c, double tau) {
  const Vec2 ab = b - a;
  return side(cross2(ab, c - a), tau * ab.norm());
}

bool in_box2(const Vec2& p, const Vec2& a, const Vec2& b, double tau) {
  return p.x() >= std::min(a.x(), b.x()) - tau && p.x() <= std::max(a.x(), b.x()) + tau &&
         p.y() >= std::min(a.y(), b.y()) - tau && p.y() <= std::max(a.y(), b.y()) + tau;
}

/// Closed segments pq and ab meet (within tau).
bool segments_meet2(const Vec2& p, const Vec2& q, const Vec2& a, const Vec2& b, double tau) {
  const int d1 = side2(p, q, a, tau), d2 = side2(p, q, b, tau);
  const int d3 = side2(a, b, p, tau), d4 = side2(a, b, q, tau);
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && in_box2(a, p, q, tau)) || (d2 == 0 && in_box2(b, p, q, tau)) ||
         (d3 == 0 && in_box2(p, a, b, tau)) || (d4 == 0 && in_box2(q, a, b, tau));
}

/// p lies in the closed triangle t (within tau of it counts).
bool point_in_triangle2(const Vec2& p, const std::array<Vec2, 3>& t, double tau) {
  const int orientation = cross2(t[1] - t[0], t[2] - t[0]) > 0 ? 1 : -1;
  for (int e = 0; e < 3; ++e)
    if (orientation * side2(t[e], t[(e + 1) % 3], p, tau) < 0) return false;
  return true;
}

/// The closed segment pq meets the triangle t (whose plane has unit normal n).
bool segment_meets_triangle(const Vec& p, const Vec& q, const Corners& t, const Vec& n, double tau) {
  const double hp = n.dot(p - t[0]), hq = n.dot(q - t[0]);
  const int sp = side(hp, tau), sq = side(hq, tau);
  if (sp * sq > 0) return false;  // both clearly on one side
  const Projection proj(n);
  const std::array<Vec2, 3> t2{proj(t[0]), proj(t[1]), proj(t[2])};
  if (sp == 0 && sq == 0) {  // in the plane
    const Vec2 p2 = proj(p), q2 = proj(q);
    if (point_in_triangle2(p2, t2, tau) || point_in_triangle2(q2, t2, tau)) return true;
    for (int e = 0; e < 3; ++e)
      if (segments_meet2(p2, q2, t2[e], t2[(e + 1) % 3], tau)) return true;
    return false;
  }
  // At least one end clearly off the plane. Crossing it: where (|hp − hq| > tau, well
  // conditioned); else the end in the plane is the segment's closest point to it.
  if ((hp < 0 && hq > 0) || (hp > 0 && hq < 0))
    return point_in_triangle2(proj(p + (q - p) * (hp / (hp - hq))), t2, tau);
  return point_in_triangle2(proj(sp == 0 ? p : q), t2, tau);
}

/// All corners of t clearly on one side of the plane through o with normal n.
bool one_side(const Corners& t, const Vec& n, const Vec& o, double tau) {
  const int s0 = side(n.dot(t[0] - o), tau), s1 = side(n.dot(t[1] - o), tau), s2 = side(n.dot(t[2] - o), tau);
  return (s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0);
}

/// The test of two triangles whose corners have the ids ia and ib (equal ids: a shared corner).
bool pair_intersects(const Corners& a, const CornerIds& ia, const Plane& pa, const Corners& b, const CornerIds& ib,
                     const Plane& pb, double tolerance) {
  if (pa.normal.isZero() || pb.normal.isZero()) return false;
  std::array<int, 3> match{-1, -1, -1};  // match[i]: b's corner at a's corner i
  int shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (ia[i] == ib[j]) {
        match[i] = j;
        ++shared;
      }
  const double tau = tolerance * std::max(pa.size, pb.size);
  if (shared >= 3) return true;  // the same face twice
  if (shared == 2) {
    int i0 = 0;
    while (match[i0] >= 0) ++i0;
    const int j0 = 3 - match[(i0 + 1) % 3] - match[(i0 + 2) % 3];
    const Vec& u = a[(i0 + 1) % 3];
    const Vec e = a[(i0 + 2) % 3] - u;
    // Different planes meet on the shared edge only; in one plane the two overlap when on the same side.
    if (std::abs(pb.normal.dot(a[i0] - u)) > tau && std::abs(pa.normal.dot(b[j0] - u)) > tau) return false;
    return e.cross(a[i0] - u).dot(e.cross(b[j0] - u)) > 0;
  }
  if (shared == 1) {
    int i0 = 0;
    while (match[i0] < 0) ++i0;
    const int j0 = match[i0];
    return segment_meets_triangle(a[(i0 + 1) % 3], a[(i0 + 2) % 3], b, pb.normal, tau) ||
           segment_meets_triangle(b[(j0 + 1) % 3], b[(j0 + 2) % 3], a, pa.normal, tau);
  }
  if (one_side(b, pa.normal, a[0], tau) || one_side(a, pb.normal, b[0], tau)) return false;
  for (int e = 0; e < 3; ++e)
    if (segment_meets_triangle(a[e], a[(e + 1) % 3], b, pb.normal, tau)) return true;
  for (int e = 0; e < 3; ++e)
    if (segment_meets_triangle(b[e], b[(e + 1) % 3], a, pa.normal, tau)) return true;
  return false;
}

void check_tolerance(double tolerance) {
  if (!(tolerance >= 0 && tolerance < 1))
    throw OptionError("self-intersection tolerance must be in [0, 1), got " + std::to_string(tolerance));
}

/// Everything the collision callback reads, and what it collects.
struct Search {
  const TriangleMesh* mesh = nullptr;
  const std::vector<std::int32_t>* vertex_id = nullptr;  // one id per position
  const std::vector<Plane>* planes = nullptr;
  const std::vector<std::int32_t>* tested = nullptr;        // Embree primitive → triangle (ascending)
  const std::vector<detail::TriangleBox>* boxes = nullptr;  // per Embree primitive
  const std::vector<std::uint8_t>* suspect = nullptr;       // per triangle; null: every pair is tested
  double tolerance = 0;
  tbb::enumerable_thread_specific<std::vector<std::array<std::int32_t, 2>>> found;
  std::mutex failure_mutex;
  std::exception_ptr failure;

  /// Primitives i and j, triangles f and g.
  bool test(unsigned int i, unsigned int j, std::int32_t f, std::int32_t g) const {
    const auto& v = mesh->vertices;
    const auto tf = mesh->triangles.row(f), tg = mesh->triangles.row(g);
    const Corners a{v.row(tf(0)).transpose(), v.row(tf(1)).transpose(), v.row(tf(2)).transpose()};
    const Corners b{v.row(tg(0)).transpose(), v.row(tg(1)).transpose(), v.row(tg(2)).transpose()};
    const auto& id = *vertex_id;
    const CornerIds ia{id[tf(0)], id[tf(1)], id[tf(2)]}, ib{id[tg(0)], id[tg(1)], id[tg(2)]};
    return pair_intersects(a, ia, (*planes)[i], b, ib, (*planes)[j], tolerance);
  }

  static void bounds(const RTCBoundsFunctionArguments* args) {
    const auto* s = static_cast<const Search*>(args->geometryUserPtr);
    const detail::TriangleBox& box = (*s->boxes)[args->primID];
    args->bounds_o->lower_x = box.lower[0], args->bounds_o->lower_y = box.lower[1],
    args->bounds_o->lower_z = box.lower[2];
    args->bounds_o->upper_x = box.upper[0], args->bounds_o->upper_y = box.upper[1],
    args->bounds_o->upper_z = box.upper[2];
  }

  // Embree reports each overlapping pair of boxes of one scene in both orders (never a box with
  // itself); the pair is tested once, as (lower, higher), may be called from several threads.
  static void collide(void* user, RTCCollision* collisions, unsigned int count) {
    auto* s = static_cast<Search*>(user);
    try {
      auto& out = s->found.local();
      for (unsigned int k = 0; k < count; ++k) {
        const unsigned int i = collisions[k].primID0, j = collisions[k].primID1;
        if (i >= j) continue;
        const std::int32_t f = (*s->tested)[i], g = (*s->tested)[j];
        if (s->suspect != nullptr && (*s->suspect)[f] == 0 && (*s->suspect)[g] == 0) continue;
        if (s->test(i, j, f, g)) out.push_back({f, g});
      }
    } catch (...) {
      const std::lock_guard lock(s->failure_mutex);
      if (!s->failure) s->failure = std::current_exception();
    }
  }
};

/// An Embree device and scene, released on destruction.
struct EmbreeCollider {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  EmbreeCollider() {
    device = rtcNewDevice(nullptr);
    if (device == nullptr) throw Error("Embree: cannot create a device");
    scene = rtcNewScene(device);
  }
  ~EmbreeCollider() {
    if (scene != nullptr) rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
  EmbreeCollider(const EmbreeCollider&) = delete;
  EmbreeCollider& operator=(const EmbreeCollider&) = delete;
};

}  // namespace

bool triangles_intersect(const std::array<Eigen::Vector3d, 3>& a, const std::array<Eigen::Vector3d, 3>& b,
                         double tolerance) {
  check_tolerance(tolerance);
  // Corner ids: equal positions, equal ids.
  CornerIds ia{0, 1, 2}, ib{3, 4, 5};
  for (int i = 1; i < 3; ++i)
    for (int k = 0; k < i; ++k)
      if (a[i] == a[k]) ia[i] = ia[k];
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i)
      if (b[j] == a[i]) ib[j] = ia[i];
    for (int k = 0; k < j; ++k)
      if (ib[j] == 3 + j && b[j] == b[k]) ib[j] = ib[k];
  }
  return pair_intersects(a, ia, plane_of(a, tolerance), b, ib, plane_of(b, tolerance), tolerance);
}

namespace {

SelfIntersections search(const TriangleMesh& mesh, const MeshCheckOptions& options,
                         const std::vector<std::uint8_t>* suspect) {
  check_tolerance(options.tolerance);
  SelfIntersections result;
  const Eigen::Index nt = mesh.triangles.rows();
  const Eigen::Index nv = mesh.vertices.rows();
  if (nt < 2) return result;
  if ((mesh.triangles.array() < 0).any() || (mesh.triangles.array() >= nv).any())
    throw OptionError("mesh check: a triangle refers to a vertex that does not exist");

  // The triangles searched: all, or the suspects and those whose boxes meet theirs.
  std::vector<std::int32_t> candidates;
  if (suspect != nullptr) {
    candidates = detail::near_suspects(mesh, *suspect, options.tolerance);
  } else {
    candidates.resize(static_cast<std::size_t>(nt));
    std::iota(candidates.begin(), candidates.end(), 0);
  }
  std::vector<Plane> candidate_planes(candidates.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size()), [&](const auto& r) {
    for (std::size_t k = r.begin(); k < r.end(); ++k) {
      const auto t = mesh.triangles.row(candidates[k]);
      const Corners c{mesh.vertices.row(t(0)).transpose(), mesh.vertices.row(t(1)).transpose(),
                      mesh.vertices.row(t(2)).transpose()};
      candidate_planes[k] = plane_of(c, options.tolerance);
    }
  });
  // Those with a plane (thin ones and those with a non-finite corner have none) go into the BVH,
  // their boxes grown by the tolerance and rounded outwards to float.
  std::vector<std::int32_t> tested;
  std::vector<Plane> planes;
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (!candidate_planes[k].normal.isZero()) tested.push_back(candidates[k]), planes.push_back(candidate_planes[k]);
  candidates = {};
  candidate_planes = {};
  if (tested.size() < 2) return result;
  std::vector<detail::TriangleBox> boxes(tested.size());
  tbb::parallel_for(std::size_t{0}, tested.size(), [&](std::size_t k) {
    boxes[k] = detail::triangle_box(mesh, tested[k], options.tolerance * planes[k].size);
  });
  const std::vector<std::int32_t> vertex_id = detail::position_ids(mesh.vertices);

  Search search;
  search.suspect = suspect;
  search.mesh = &mesh;
  search.vertex_id = &vertex_id;
  search.planes = &planes;
  search.tested = &tested;
  search.boxes = &boxes;
  search.tolerance = options.tolerance;
  {
    EmbreeCollider embree;
    RTCGeometry geometry = rtcNewGeometry(embree.device, RTC_GEOMETRY_TYPE_USER);
    if (geometry == nullptr) throw Error("Embree: cannot create a user geometry");
    rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned int>(tested.size()));
    rtcSetGeometryUserData(geometry, &search);
    rtcSetGeometryBoundsFunction(geometry, &Search::bounds, nullptr);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(embree.scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(embree.scene);
    if (rtcGetDeviceError(embree.device) != RTC_ERROR_NONE) throw Error("Embree: building the scene failed");
    rtcCollide(embree.scene, embree.scene, &Search::collide, &search);
    if (rtcGetDeviceError(embree.device) != RTC_ERROR_NONE) throw Error("Embree: the collision query failed");
  }
  if (search.failure) std::rethrow_exception(search.failure);

  std::vector<std::array<std::int32_t, 2>> pairs;
  for (const auto& part : search.found) pairs.insert(pairs.end(), part.begin(), part.end());
  tbb::parallel_sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  result.count = pairs.size();
  if (pairs.size() > options.max_pairs) pairs.resize(options.max_pairs);
  result.pairs = std::move(pairs);
  return result;
}

}  // namespace

SelfIntersections find_self_intersections(const TriangleMesh& mesh, const MeshCheckOptions& options) {
  return search(mesh, options, nullptr);
}

SelfIntersections find_self_intersections(const TriangleMesh& mesh, const std::vector<std::uint8_t>& suspect,
                                          const MeshCheckOptions& options) {
  if (suspect.size() != static_cast<std::size_t>(mesh.triangles.rows()))
    throw OptionError("mesh check: the suspect marks do not match the triangles");
  return search(mesh, options, &suspect);
}

}  // namespace clustersurf
