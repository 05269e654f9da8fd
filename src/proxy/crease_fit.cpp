// Two planes meeting along a crease, fitted to a cluster by k-planes.

#include "proxy/crease_fit.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace clustersurf::detail {

namespace {

constexpr int kMaxRounds = 12;
/// Each face holds at least this many points: a plane and two to spare, so that its residual
/// tells a face from any three points (a leaf of 8 points splits into two triples that two
/// planes fit exactly, however they lie).
constexpr std::size_t kMinFacePoints = 5;
/// k-planes runs on at most this many of the cluster's points (an even stride); the error is
/// measured on all of them. A crease is two planes: a sample this size fixes them as well as
/// all points do, and a large cluster costs one pass instead of a pass per round.
constexpr std::size_t kSample = 1024;
/// The widest angle between the two faces' normals a crease may have: 120 degrees, that is a
/// wedge of 60 degrees or more. Beyond it, two faces facing apart are as likely both sides of
/// a thin part (an ear, a blade: normals near 180 degrees apart) as a sharp wedge, and a crease
/// would end the part at its edge; the splits (and the sheet split, with input normals) deal
/// with them. Right angles and the slightly obtuse ones of machined and moulded parts (draft
/// angles, a model's facets) are creases, whichever side of 90 degrees the angle between
/// their fitted faces comes out.
constexpr double kMinFaceNormalCos = -0.5;

double plane_value(const PlaneProxy& p, const Eigen::Vector3d& x) { return p.normal.dot(x - p.point); }

/// The face a point belongs to: 0 when it is nearer to plane a (or as near), else 1.
std::uint8_t nearer_face(const PlaneProxy& a, const PlaneProxy& b, const Eigen::Vector3d& x) {
  return std::abs(plane_value(a, x)) <= std::abs(plane_value(b, x)) ? 0 : 1;
}

/// The points of `range` labelled 0 and 1, summed per label (in range order).
struct FaceSums {
  std::array<Eigen::Vector3d, 2> sum = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::array<std::size_t, 2> count = {0, 0};
};

/// A sum of points, or the lower triangle of a scatter matrix, kept in scalars. The k-planes
/// passes add each point to one of two of these by its label: indexing sums in memory by label
/// chained every point's update on the last one's store (and on a spilled vector's reload);
/// two named accumulators stay in registers. Each entry still sums its terms in range order,
/// so the sums are the same to the bit.
struct PointSum {
  double x = 0, y = 0, z = 0;
  std::size_t count = 0;
  void add(const double* p) { x += p[0], y += p[1], z += p[2], ++count; }
};

struct Scatter {
  double xx = 0, yx = 0, zx = 0, yy = 0, zy = 0, zz = 0;
  void add(double dx, double dy, double dz) {
    xx += dx * dx, yx += dx * dy, zx += dx * dz, yy += dy * dy, zy += dy * dz, zz += dz * dz;
  }
  /// The matrix with this lower triangle (the part the eigensolver reads), zeros above.
  Eigen::Matrix3d lower() const {
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    m(0, 0) = xx, m(1, 0) = yx, m(2, 0) = zx, m(1, 1) = yy, m(2, 1) = zy, m(2, 2) = zz;
    return m;
  }
};

FaceSums face_sums(const PointSum& a, const PointSum& b) {
  return {{Eigen::Vector3d(a.x, a.y, a.z), Eigen::Vector3d(b.x, b.y, b.z)}, {a.count, b.count}};
}

/// A face's points pin its plane down when they spread across it clearly more than off it: the
/// middle spread (its width) at least kMinFaceWidth times the smallest (its residual). A row of
/// points (one scan line, the last row at a part's rim) fits every plane through it.
constexpr double kMinFaceWidth = 3;

/// Two faces' planes, and whether each face's points pin its plane down (kMinFaceWidth).
struct Faces {
  std::array<PlaneProxy, 2> planes;
  bool pinned = true;
};

/// The least-squares planes of the points of `range` labelled 0 and 1, in one pass over them
/// (nullopt: a label with fewer than kMinFacePoints points).
std::optional<Faces> fit_faces(const Points& points, std::span<const std::uint32_t> range,
                               const std::vector<std::uint8_t>& label, const FaceSums& sums) {
  if (sums.count[0] < kMinFacePoints || sums.count[1] < kMinFacePoints) return std::nullopt;
  std::array<Eigen::Vector3d, 2> mean;
  for (int side : {0, 1}) mean[side] = sums.sum[side] / static_cast<double>(sums.count[side]);
  Scatter s0, s1;
  for (std::size_t k = 0; k < range.size(); ++k) {
    const double* x = points.row(range[k]).data();
    if (label[k] == 0)
      s0.add(x[0] - mean[0](0), x[1] - mean[0](1), x[2] - mean[0](2));
    else
      s1.add(x[0] - mean[1](0), x[1] - mean[1](1), x[2] - mean[1](2));
  }
  const std::array<Eigen::Matrix3d, 2> cov = {s0.lower(), s1.lower()};
  Faces faces;
  for (int side : {0, 1}) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov[side]);
    const Eigen::Vector3d spread = eig.eigenvalues().cwiseMax(0.0);
    // Relative to its length too: the spreads of points exactly on a line are rounding noise.
    faces.pinned = faces.pinned && spread(1) > kMinFaceWidth * kMinFaceWidth * spread(0) + 1e-12 * spread(2);
    faces.planes[side] = PlaneProxy{mean[side], eig.eigenvectors().col(0).normalized()};
  }
  return faces;
}

/// k-planes from the split of `range` by the sign of (x − origin) · axis. Two passes per round:
/// the faces' covariances, then the new labels with the next round's sums. Nullopt when a face
/// loses its points or, at the end, does not pin its plane down.
std::optional<std::array<PlaneProxy, 2>> k_planes(const Points& points, std::span<const std::uint32_t> range,
                                                  const Eigen::Vector3d& origin, const Eigen::Vector3d& axis) {
  std::vector<std::uint8_t> label(range.size());
  PointSum a, b;
  for (std::size_t k = 0; k < range.size(); ++k) {
    const Eigen::Vector3d x = points.row(range[k]).transpose();
    label[k] = (x - origin).dot(axis) < 0 ? 0 : 1;
    (label[k] == 0 ? a : b).add(x.data());
  }
  FaceSums sums = face_sums(a, b);
  Faces faces;
  std::array<PlaneProxy, 2>& planes = faces.planes;
  for (int round = 0; round < kMaxRounds; ++round) {
    const auto fitted = fit_faces(points, range, label, sums);
    if (!fitted) return std::nullopt;
    faces = *fitted;
    bool changed = false;
    a = PointSum{}, b = PointSum{};
    for (std::size_t k = 0; k < range.size(); ++k) {
      const Eigen::Vector3d x = points.row(range[k]).transpose();
      const std::uint8_t side = nearer_face(planes[0], planes[1], x);
      changed = changed || side != label[k];
      label[k] = side;
      (side == 0 ? a : b).add(x.data());
    }
    sums = face_sums(a, b);
    if (!changed) break;
  }
  if (!faces.pinned) return std::nullopt;
  return planes;
}

/// The line where planes a and b meet: its point nearest to `c` and its unit direction
/// (nullopt when the planes are parallel).
std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> edge_line(const PlaneProxy& a, const PlaneProxy& b,
                                                                     const Eigen::Vector3d& c) {
  const Eigen::Vector3d dir = a.normal.cross(b.normal);
  if (!(dir.squaredNorm() > 1e-18)) return std::nullopt;
  Eigen::Matrix3d m;
  m.row(0) = a.normal.transpose();
  m.row(1) = b.normal.transpose();
  m.row(2) = dir.transpose();
  const Eigen::Vector3d rhs(a.normal.dot(a.point), b.normal.dot(b.point), dir.dot(c));
  return std::pair{Eigen::Vector3d(m.colPivHouseholderQr().solve(rhs)), Eigen::Vector3d(dir.normalized())};
}

/// The directions from the edge into each face (the points nearer to its plane): towards their
/// centroid, perpendicular to the edge.
std::array<Eigen::Vector3d, 2> inward(const CreaseProxy& c, const Points& points, std::span<const std::uint32_t> range,
                                      const std::pair<Eigen::Vector3d, Eigen::Vector3d>& edge) {
  std::array<Eigen::Vector3d, 2> sum = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (auto i : range) {
    const Eigen::Vector3d x = points.row(i).transpose();
    const Eigen::Vector3d d = x - edge.first;
    sum[nearer_face(c.a, c.b, x)] += d - d.dot(edge.second) * edge.second;
  }
  return sum;
}

/// proxy_error of the convex and of the concave crease of c's planes, in one pass.
std::array<ProxyError, 2> convex_and_concave_errors(const CreaseProxy& c, const Points& points,
                                                    std::span<const std::uint32_t> range) {
  std::array<ProxyError, 2> e{};
  if (range.empty()) return e;
  std::array<double, 2> sum = {0, 0};
  for (auto i : range) {
    const Eigen::Vector3d x = points.row(i).transpose();
    const double qa = plane_value(c.a, x), qb = plane_value(c.b, x);
    const std::array<double, 2> q = {std::abs(std::max(qa, qb)), std::abs(std::min(qa, qb))};
    for (int kind : {0, 1}) {
      sum[kind] += q[kind] * q[kind];
      e[kind].max = std::max(e[kind].max, q[kind]);
    }
  }
  for (int kind : {0, 1}) e[kind].rms = std::sqrt(sum[kind] / static_cast<double>(range.size()));
  return e;
}

}  // namespace

std::optional<CreaseFit> fit_crease(const Points& points, std::span<const std::uint32_t> range, const Frame& frame,
                                    double extent) {
  if (range.size() < 2 * kMinFacePoints) return std::nullopt;
  std::vector<std::uint32_t> sample;
  std::span<const std::uint32_t> fitted = range;
  if (range.size() > kSample) {
    sample.reserve(kSample);
    for (std::size_t j = 0; j < kSample; ++j) sample.push_back(range[j * range.size() / kSample]);
    fitted = sample;
  }
  std::optional<CreaseFit> best;
  for (int axis = 0; axis < 2; ++axis) {
    const auto planes = k_planes(points, fitted, frame.origin, frame.axes.col(axis));
    if (!planes) continue;
    const auto edge = edge_line((*planes)[0], (*planes)[1], frame.origin);
    if (!edge || (edge->first - frame.origin).norm() > 0.5 * extent) continue;
    CreaseProxy c{(*planes)[0], (*planes)[1], true};
    // The planes agree on the outside: unfolding the crease (turning face b about the edge into
    // a's plane) takes b's normal to a's, that is sign(na · db) = sign(nb · da) with da, db the
    // directions from the edge into each face. A plane flipped against the other would make
    // max or min an unsigned distance: it fits the points as well, but is positive on both
    // sides of them.
    const auto [da, db] = inward(c, points, fitted, *edge);
    if (c.a.normal.dot(db) * c.b.normal.dot(da) < 0) c.b.normal = -c.b.normal;
    // Faces facing too far apart: left to the splits (kMinFaceNormalCos).
    if (c.a.normal.dot(c.b.normal) < kMinFaceNormalCos) continue;
    const std::array<ProxyError, 2> errors = convex_and_concave_errors(c, points, range);
    for (const bool convex : {true, false}) {
      c.convex = convex;
      const ProxyError& e = errors[convex ? 0 : 1];
      if (!best || e.rms < best->error.rms) best = CreaseFit{c, e};
    }
  }
  return best;
}

}  // namespace clustersurf::detail
