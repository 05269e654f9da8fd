#pragma once
// Surface proxies: the small analytic surfaces fitted to each cluster (thesis ch. 4).
// Every proxy gives an approximate signed distance Q(x) (positive on the side its normal points
// to), its gradient, a ray intersection and its error over a set of points.

#include <clustersurf/core/point_cloud.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>

namespace clustersurf {

/// The proxy types. Values are stored in tree files: never renumber.
enum class ProxyKind : std::uint8_t { Point = 0, Plane = 1, Poly = 2, Quadric = 3, Crease = 4 };
/// How many proxy kinds there are.
inline constexpr std::size_t kProxyKinds = 5;

/// Name used on the command line and in reports: "point", "plane", "poly", "quadric", "crease".
const char* to_string(ProxyKind kind);
/// The kind a tree may be built with, by its to_string() name: "plane", "poly" or "quadric".
/// Throws OptionError otherwise.
ProxyKind parse_proxy_kind(std::string_view text);

/// Orthonormal local frame: `origin` and axes e1, e2 (tangents) and e3 (normal) as the
/// columns of `axes`.
struct Frame {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();

  Eigen::Vector3d to_local(const Eigen::Vector3d& x) const { return axes.transpose() * (x - origin); }
  Eigen::Vector3d to_world(const Eigen::Vector3d& l) const { return origin + axes * l; }
};

/// The cluster's mean. Defines no surface: value() is the distance to the center.
struct PointProxy {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
};

/// Plane through `point` with unit `normal`; Q(x) = normal · (x − point).
struct PlaneProxy {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

/// Bivariate quadratic height field over a local frame (thesis 4.2):
/// w = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v², with (u, v, w) the local coordinates, and
/// Q(x) = (w − f(u, v)) / sqrt(1 + |∇f|²).
struct PolyProxy {
  Frame frame;
  std::array<double, 6> coeffs{};

  /// The height f(u, v) at local coordinates (u, v).
  double height(double u, double v) const {
    const auto& c = coeffs;
    return c[0] + c[1] * u + c[2] * v + c[3] * u * u + c[4] * u * v + c[5] * v * v;
  }
};

/// General quadric q(y) = cᵀ [y1², y2², y3², y1y2, y1y3, y2y3, y1, y2, y3, 1] in normalized
/// coordinates y = (x − center) / scale (Taubin fit); Q(x) = scale · q / |∇_y q|.
struct QuadricProxy {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double scale = 1.0;
  std::array<double, 10> coeffs{};
};

/// Two planes meeting along a crease, for a leaf whose points lie on two faces of a sharp edge
/// (MPU's edge function): Q(x) = max(Qa, Qb) when the inside is where both planes say inside
/// (a convex edge), min(Qa, Qb) when it is where either does (a concave one). The zero set is
/// the two half-planes and the edge between them is sharp, where one smooth proxy would round
/// it. Built by the tree builder (BuildOptions::creases), never chosen as BuildOptions::proxy.
struct CreaseProxy {
  PlaneProxy a;
  PlaneProxy b;
  bool convex = true;
};

/// RMS and maximum of |Q| over a set of points.
struct ProxyError {
  double rms = 0;
  double max = 0;
};

/// One proxy of any kind, held by value.
class Proxy {
 public:
  using Variant = std::variant<PointProxy, PlaneProxy, PolyProxy, QuadricProxy, CreaseProxy>;

  Proxy() = default;
  /// Implicit from any of the proxy types (and from Variant).
  template <class T>
  requires std::is_constructible_v<Variant, T> Proxy(T p) : v_(std::move(p)) {}  // NOLINT(google-explicit-constructor)

  ProxyKind kind() const noexcept { return static_cast<ProxyKind>(v_.index()); }
  const Variant& variant() const noexcept { return v_; }
  Variant& variant() noexcept { return v_; }

  /// Approximate signed distance Q(x); finite everywhere.
  double value(const Eigen::Vector3d& x) const;
  /// Exact gradient of value() at x (a crease: of its plane that decides there).
  Eigen::Vector3d gradient(const Eigen::Vector3d& x) const;
  /// value() and gradient() at x computed together: the same numbers for less work.
  std::pair<double, Eigen::Vector3d> value_and_gradient(const Eigen::Vector3d& x) const;
  /// Smallest t in [t_min, t_max] with Q(origin + t·direction) = 0, if any (Point: none).
  std::optional<double> intersect(const Ray& ray, double t_min, double t_max) const;
  /// Negates Q (swaps inside and outside) without changing the zero set.
  void flip();
  /// Unit normal direction of the proxy near its center (plane and poly: e3; quadric: the
  /// normalized gradient at the center; crease: the mean of its planes' normals; point: +z).
  Eigen::Vector3d normal() const;

 private:
  Variant v_;
};

/// Principal-component frame of points[indices]: origin at the mean, e1/e2/e3 the axes of
/// decreasing variance, right-handed, each axis's sign fixed so results are reproducible.
Frame pca_frame(const Points& points, std::span<const std::uint32_t> indices);

/// Least-squares fit of a proxy of `kind` to points[indices] (nonempty). Rank-deficient systems
/// (collinear points, fewer points than coefficients) get the minimum-norm pseudo-inverse
/// solution; the result is always finite. A crease: two planes by k-planes, or the plane of
/// all the points when they do not lie on two faces meeting among them.
Proxy fit_proxy(ProxyKind kind, const Points& points, std::span<const std::uint32_t> indices);

/// Fits a bivariate polynomial over a given frame (the frame is kept; only coefficients fit).
PolyProxy fit_poly_in_frame(const Frame& frame, const Points& points, std::span<const std::uint32_t> indices);

/// Weighted least squares: minimizes Σ weights[k] · (w_k − f(u_k, v_k))² over points[indices[k]]
/// (weights ≥ 0, one per index).
PolyProxy fit_poly_in_frame(const Frame& frame, const Points& points, std::span<const std::uint32_t> indices,
                            std::span<const double> weights);

/// The weighted fit with normals (Hermite data): also minimizes normal_weight · Σ weights[k] ·
/// |m_w ∇f + (m_u, m_v)|² over the local normals m = normals[indices[k]] (either sign; rows of
/// `normals` as of `points`); normal_weight is a squared length (0 or no normals: the fit above).
PolyProxy fit_poly_in_frame(const Frame& frame, const Points& points, std::span<const std::uint32_t> indices,
                            std::span<const double> weights, const Points* normals, double normal_weight);

/// RMS and max of |Q| over points[indices] (zero for no points).
ProxyError proxy_error(const Proxy& proxy, const Points& points, std::span<const std::uint32_t> indices);

}  // namespace clustersurf
