// The virtual range scanner (see range_scan.hpp): Embree casts each scan's grid of rays.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/range_scan.hpp>

#include "core/embree_scene.hpp"
#include "core/portable_random.hpp"
#include "core/splitmix.hpp"

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

namespace clustersurf {

namespace {

/// Rays of a probe grid, per side, that estimate how much of a scan's view the mesh fills.
constexpr int kProbeSide = 64;
/// Grid neighbours farther apart than this many grid spacings (at their depth) lie across a
/// depth discontinuity and do not make a normal.
constexpr double kMaxNeighbourGap = 4;
/// The largest noise correlation, in grid steps: the smoothing kernel spans 6 times as many.
constexpr double kMaxNoiseCorrelation = 100;

/// One scanner: position, viewing axes, and the half-width of its grid at unit depth.
struct Scanner {
  Eigen::Vector3d eye;
  Eigen::Matrix3d axes;  // columns: right, up, forward
  double half_width = 0;

  Ray ray(int i, int j, int side) const {
    const double u = ((j + 0.5) / side * 2 - 1) * half_width, v = ((i + 0.5) / side * 2 - 1) * half_width;
    return {eye, (axes.col(2) + u * axes.col(0) + v * axes.col(1)).normalized()};
  }
};

/// The k-th of n directions on a Fibonacci sphere.
Eigen::Vector3d fibonacci_direction(std::size_t k, std::size_t n) {
  const double z = 1 - 2 * (static_cast<double>(k) + 0.5) / static_cast<double>(n);
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  const double phi = std::numbers::pi * (3 - std::sqrt(5.0)) * static_cast<double>(k);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Scanner make_scanner(const Eigen::Vector3d& center, double radius, double distance, const Eigen::Vector3d& direction) {
  Scanner s;
  s.eye = center + distance * direction;
  const Eigen::Vector3d forward = -direction;
  const Eigen::Vector3d helper = std::abs(forward.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d right = forward.cross(helper).normalized();
  s.axes.col(0) = right;
  s.axes.col(1) = right.cross(forward);
  s.axes.col(2) = forward;
  s.half_width = std::tan(std::asin(std::min(1.0, radius / distance)));
  return s;
}

/// A return of one grid ray: the point hit (with range noise), the unit normal of the facet
/// hit, and whether there is a return.
struct Return {
  Eigen::Vector3d point;
  Eigen::Vector3d facet_normal;
  bool valid = false;
};

/// One pass of a Gaussian of unit sum over the lines of a side × side grid (row-major): along
/// its rows, or along its columns; the grid's edges repeat.
std::vector<double> smooth_lines(const std::vector<double>& values, int side, const std::vector<double>& kernel,
                                 bool along_rows) {
  const int reach = static_cast<int>(kernel.size() / 2);
  const auto at = [side](int i, int j) {
    return static_cast<std::size_t>(i) * static_cast<std::size_t>(side) + static_cast<std::size_t>(j);
  };
  std::vector<double> out(values.size());
  tbb::parallel_for(0, side, [&](int i) {
    for (int j = 0; j < side; ++j) {
      double sum = 0;
      for (int t = -reach; t <= reach; ++t) {
        const int k = std::clamp((along_rows ? j : i) + t, 0, side - 1);
        sum += kernel[static_cast<std::size_t>(t + reach)] * values[along_rows ? at(i, k) : at(k, j)];
      }
      out[at(i, j)] = sum;
    }
  });
  return out;
}

/// Unit-variance range noise for a side × side grid (row-major), independent from cell to cell,
/// or correlated over `correlation` grid steps: smoothed by a Gaussian of that standard
/// deviation (cut at 3), then scaled back to unit variance.
std::vector<double> range_noise(int side, double correlation, std::uint64_t seed) {
  const auto n = static_cast<std::size_t>(side);
  std::vector<double> noise(n * n);
  tbb::parallel_for(0, side, [&](int i) {
    detail::PortableRandom random(detail::splitmix64(seed ^ (static_cast<std::uint64_t>(i) << 32)));
    for (std::size_t j = 0; j < n; ++j) noise[static_cast<std::size_t>(i) * n + j] = random.normal();
  });
  if (!(correlation > 0)) return noise;
  const int reach = static_cast<int>(std::ceil(3 * correlation));
  std::vector<double> kernel(static_cast<std::size_t>(2 * reach + 1));
  double sum = 0, squares = 0;
  for (int t = -reach; t <= reach; ++t)
    sum += kernel[static_cast<std::size_t>(t + reach)] = std::exp(-0.5 * t * t / (correlation * correlation));
  for (double& k : kernel) k /= sum, squares += k * k;
  noise = smooth_lines(smooth_lines(noise, side, kernel, true), side, kernel, false);
  for (double& v : noise) v /= squares;  // the variance of a 2-D pass is squares²
  return noise;
}

/// The returns of one scan's side × side grid (row-major), with range noise of standard
/// deviation `sigma` correlated over `correlation` grid steps.
std::vector<Return> scan_grid(const detail::EmbreeScene& scene, const Scanner& scanner, int side, double sigma,
                              double correlation, double min_cos, std::uint64_t seed) {
  std::vector<Return> grid(static_cast<std::size_t>(side) * static_cast<std::size_t>(side));
  const std::vector<double> noise = sigma > 0 ? range_noise(side, correlation, seed) : std::vector<double>();
  tbb::parallel_for(0, side, [&](int i) {
    RTCRayHit hit;
    for (int j = 0; j < side; ++j) {
      const Ray ray = scanner.ray(i, j, side);
      const std::size_t cell =
          static_cast<std::size_t>(i) * static_cast<std::size_t>(side) + static_cast<std::size_t>(j);
      const double range_noise = sigma > 0 ? sigma * noise[cell] : 0.0;
      if (!scene.intersect(ray, std::numeric_limits<float>::infinity(), hit)) continue;
      const Eigen::Vector3d n = Eigen::Vector3d(hit.hit.Ng_x, hit.hit.Ng_y, hit.hit.Ng_z).normalized();
      if (!(std::abs(n.dot(ray.direction)) >= min_cos)) continue;  // grazing (or degenerate) return
      Return& r = grid[cell];
      r.point = ray.origin + (static_cast<double>(hit.ray.tfar) + range_noise) * ray.direction;
      r.facet_normal = n;
      r.valid = true;
    }
  });
  return grid;
}

/// The normal at grid cell (i, j) from its neighbours' returns (central differences where both
/// sides exist, one-sided otherwise), oriented towards `eye`. A return without neighbours in
/// both grid directions (at a silhouette, next to a hole) takes the facet's normal, as a
/// scanner's software would estimate it from a wider neighbourhood.
Eigen::Vector3d grid_normal(const std::vector<Return>& grid, int side, int i, int j, const Eigen::Vector3d& eye,
                            double pixel_angle) {
  const auto at = [&](int a, int b) -> const Return* {
    if (a < 0 || b < 0 || a >= side || b >= side) return nullptr;
    const Return& r = grid[static_cast<std::size_t>(a) * static_cast<std::size_t>(side) + static_cast<std::size_t>(b)];
    return r.valid ? &r : nullptr;
  };
  const Return& c = *at(i, j);
  const double reach = kMaxNeighbourGap * pixel_angle * (c.point - eye).norm();
  const auto near = [&](const Return* r, int steps) {
    return r != nullptr && (r->point - c.point).norm() <= steps * reach;
  };
  const auto difference = [&](const Return* lo, const Return* hi) -> std::optional<Eigen::Vector3d> {
    if (near(lo, 1) && near(hi, 1)) return hi->point - lo->point;
    if (near(hi, 1)) return hi->point - c.point;
    if (near(lo, 1)) return c.point - lo->point;
    return std::nullopt;
  };
  const auto du = difference(at(i, j - 1), at(i, j + 1));
  const auto dv = difference(at(i - 1, j), at(i + 1, j));
  const Eigen::Vector3d view = (eye - c.point).normalized();
  Eigen::Vector3d n = du && dv ? du->cross(*dv) : c.facet_normal;
  if (!(n.norm() > 0)) n = c.facet_normal;
  n.normalize();
  return n.dot(view) < 0 ? Eigen::Vector3d(-n) : n;
}

/// A random rigid motion about `center` displacing points at distance `radius` by about
/// `sigma` (half by rotation, half by translation).
Eigen::Isometry3d misregistration(const Eigen::Vector3d& center, double radius, double sigma, std::uint64_t seed) {
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  if (!(sigma > 0)) return motion;
  detail::PortableRandom random(seed);
  const double share = sigma / std::sqrt(2.0);
  const Eigen::Vector3d axis = random.unit_vector();
  const double angle = share / radius * random.normal();
  const Eigen::Vector3d shift =
      share / std::sqrt(3.0) * Eigen::Vector3d(random.normal(), random.normal(), random.normal());
  motion.translate(center + shift);
  motion.rotate(Eigen::AngleAxisd(angle, axis));
  motion.translate(-center);
  return motion;
}

void validate(const TriangleMesh& mesh, const RangeScanOptions& o) {
  if (mesh.triangles.rows() == 0) throw OptionError("cannot scan a mesh without triangles");
  if (o.scans < 1) throw OptionError("the scanner needs at least 1 scan");
  if (o.count < 1) throw OptionError("the scanner needs a point count of at least 1");
  if (!(o.distance > 0.5) || !std::isfinite(o.distance))
    throw OptionError(
        fmt::format("the scanner distance must exceed 0.5 diagonals (outside the model), got {}", o.distance));
  if (!(o.noise >= 0) || !std::isfinite(o.noise))
    throw OptionError(fmt::format("noise must be a finite fraction >= 0, got {}", o.noise));
  if (!(o.noise_correlation >= 0) || !(o.noise_correlation <= kMaxNoiseCorrelation))
    throw OptionError(fmt::format("the noise correlation must be in [0, {}] grid steps, got {}", kMaxNoiseCorrelation,
                                  o.noise_correlation));
  if (!(o.registration >= 0) || !std::isfinite(o.registration))
    throw OptionError(fmt::format("registration error must be a finite fraction >= 0, got {}", o.registration));
  if (!(o.flipped_normals >= 0 && o.flipped_normals <= 1))
    throw OptionError(fmt::format("the share of flipped normals must be in [0, 1], got {}", o.flipped_normals));
  if (!(o.max_incidence_degrees > 0 && o.max_incidence_degrees <= 90))
    throw OptionError(
        fmt::format("the largest incidence angle must be in (0, 90] degrees, got {}", o.max_incidence_degrees));
  check_triangle_indices(mesh);
}

}  // namespace

PointCloud scan_surface(const TriangleMesh& mesh, const RangeScanOptions& options) {
  validate(mesh, options);
  BoundingBox box;
  for (const auto& row : mesh.triangles.rowwise())
    for (int k = 0; k < 3; ++k) box.extend(mesh.vertices.row(row(k)).transpose());
  const double diagonal = box.diagonal();
  if (!(diagonal > 0) || !std::isfinite(diagonal)) throw OptionError("the mesh has no extent to scan");
  const Eigen::Vector3d center = 0.5 * (box.min + box.max);
  const double radius = 0.5 * diagonal;
  const double min_cos = std::cos(options.max_incidence_degrees * std::numbers::pi / 180);

  detail::EmbreeScene scene(/*watertight=*/true);
  scene.commit_triangles(mesh);

  std::vector<Scanner> scanners;
  for (std::size_t s = 0; s < options.scans; ++s)
    scanners.push_back(
        make_scanner(center, radius, options.distance * diagonal, fibonacci_direction(s, options.scans)));

  // How many of a grid's rays return, on a coarse probe of every scan; the grids are sized so
  // that all scans together return about options.count points.
  std::size_t probe_returns = 0;
  for (const auto& scanner : scanners)
    for (const auto& r : scan_grid(scene, scanner, kProbeSide, 0, 0, min_cos, 0)) probe_returns += r.valid;
  if (probe_returns == 0) throw OptionError("no scanner sees the mesh (every return is grazing)");
  const double per_ray = static_cast<double>(probe_returns) /
                         (static_cast<double>(kProbeSide * kProbeSide) * static_cast<double>(options.scans));
  const int side =
      std::max(2, static_cast<int>(std::lround(
                      std::sqrt(static_cast<double>(options.count) / (per_ray * static_cast<double>(options.scans))))));

  PointCloud cloud;
  std::vector<Eigen::Vector3d> points, normals;
  const double sigma = options.noise * diagonal;
  for (std::size_t s = 0; s < scanners.size(); ++s) {
    const Scanner& scanner = scanners[s];
    const std::uint64_t scan_seed = detail::splitmix64(options.seed * 0x100000001b3ULL + s);
    const std::vector<Return> grid =
        scan_grid(scene, scanner, side, sigma, options.noise_correlation, min_cos, scan_seed);
    const Eigen::Isometry3d motion =
        misregistration(center, radius, options.registration * diagonal, detail::splitmix64(scan_seed));
    const double pixel_angle = 2 * scanner.half_width / side;
    for (int i = 0; i < side; ++i)
      for (int j = 0; j < side; ++j) {
        const Return& r =
            grid[static_cast<std::size_t>(i) * static_cast<std::size_t>(side) + static_cast<std::size_t>(j)];
        if (!r.valid) continue;
        points.push_back(motion * r.point);
        normals.push_back(motion.linear() * grid_normal(grid, side, i, j, scanner.eye, pixel_angle));
        cloud.scanner_of_point.push_back(static_cast<std::uint32_t>(s));
      }
  }
  cloud.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  cloud.normals.resize(static_cast<Eigen::Index>(points.size()), 3);
  detail::PortableRandom flips(detail::splitmix64(options.seed ^ 0x666c6970ULL));
  for (std::size_t k = 0; k < points.size(); ++k) {
    cloud.positions.row(static_cast<Eigen::Index>(k)) = points[k];
    const bool flip = options.flipped_normals > 0 && flips.uniform() < options.flipped_normals;
    cloud.normals.row(static_cast<Eigen::Index>(k)) = flip ? Eigen::Vector3d(-normals[k]) : normals[k];
  }
  return cloud;
}

}  // namespace clustersurf
