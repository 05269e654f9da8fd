// The harmonic fill of ClosedSurface: f sampled on a coarse grid, Laplace's equation solved by
// conjugate gradients at the nodes where f is undefined.

#include <clustersurf/closed_surface.hpp>
#include <clustersurf/errors.hpp>

#include "core/progress_reporter.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace clustersurf {

namespace {

/// Sums of fixed blocks added in order: the same result whatever the thread count.
template <class Term>
double deterministic_sum(std::size_t n, const Term& term) {
  constexpr std::size_t kBlock = 4096;
  std::vector<double> partial((n + kBlock - 1) / kBlock, 0.0);
  tbb::parallel_for(std::size_t{0}, partial.size(), [&](std::size_t b) {
    double s = 0;
    for (std::size_t i = b * kBlock, end = std::min(n, i + kBlock); i < end; ++i) s += term(i);
    partial[b] = s;
  });
  double total = 0;
  for (double s : partial) total += s;
  return total;
}

/// Node values on a grid, x fastest, and which of them are fixed.
struct FillGrid {
  std::int64_t nx, ny, nz;
  std::vector<float> values;
  std::vector<std::uint8_t> known;
};

/// Solves Laplace's equation at the nodes that are not known, in place, and returns how many
/// there were. A = -Laplacian on the unknowns (7 points; at the grid's border the missing
/// neighbours drop out: no flux through it, so the fill is not pulled towards any value out
/// there), b = the sum of the known neighbours' values; every unknown region touches some
/// known node (the surface bounds it), so A is positive definite. Conjugate gradients to a
/// residual of 1e-6 of b, starting from the same problem solved on every other node
/// (recursively) and interpolated, which leaves only the fine detail to iterate on.
std::size_t solve_fill(FillGrid& g, detail::ProgressReporter* reporter) {
  const std::int64_t nx = g.nx, ny = g.ny, nz = g.nz;
  const auto count = static_cast<std::size_t>(nx * ny * nz);
  std::vector<std::size_t> unknown;
  for (std::size_t n = 0; n < count; ++n)
    if (!g.known[n]) unknown.push_back(n);
  const std::size_t m = unknown.size();
  if (m == 0) return 0;
  std::vector<double> u(m, 0.0);
  if (std::max({nx, ny, nz}) > 24) {
    FillGrid coarse{(nx + 1) / 2, (ny + 1) / 2, (nz + 1) / 2, {}, {}};
    const auto coarse_count = static_cast<std::size_t>(coarse.nx * coarse.ny * coarse.nz);
    coarse.values.resize(coarse_count);
    coarse.known.resize(coarse_count);
    for (std::int64_t k = 0; k < coarse.nz; ++k)
      for (std::int64_t j = 0; j < coarse.ny; ++j)
        for (std::int64_t i = 0; i < coarse.nx; ++i) {
          const auto c = static_cast<std::size_t>((k * coarse.ny + j) * coarse.nx + i);
          const auto f = static_cast<std::size_t>((std::min(2 * k, nz - 1) * ny + std::min(2 * j, ny - 1)) * nx + std::min(2 * i, nx - 1));
          coarse.values[c] = g.values[f];
          coarse.known[c] = g.known[f];
        }
    solve_fill(coarse, nullptr);
    tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
      const auto n = static_cast<std::int64_t>(unknown[e]);
      const double x = static_cast<double>(n % nx) / 2, y = static_cast<double>((n / nx) % ny) / 2, z = static_cast<double>(n / (nx * ny)) / 2;
      const std::int64_t i = std::min(static_cast<std::int64_t>(x), coarse.nx - 1), j = std::min(static_cast<std::int64_t>(y), coarse.ny - 1),
                         k = std::min(static_cast<std::int64_t>(z), coarse.nz - 1);
      const double tx = x - static_cast<double>(i), ty = y - static_cast<double>(j), tz = z - static_cast<double>(k);
      double v = 0;
      for (int d = 0; d < 8; ++d) {
        const std::int64_t a = std::min(i + (d & 1), coarse.nx - 1), b = std::min(j + (d >> 1 & 1), coarse.ny - 1),
                           c = std::min(k + (d >> 2 & 1), coarse.nz - 1);
        const double w = (d & 1 ? tx : 1 - tx) * (d >> 1 & 1 ? ty : 1 - ty) * (d >> 2 & 1 ? tz : 1 - tz);
        v += w * coarse.values[static_cast<std::size_t>((c * coarse.ny + b) * coarse.nx + a)];
      }
      u[e] = v;
    });
  }

  std::vector<std::int64_t> id(count, -1);
  for (std::size_t e = 0; e < m; ++e) id[unknown[e]] = static_cast<std::int64_t>(e);
  const std::int64_t step[6] = {1, -1, nx, -nx, nx * ny, -nx * ny};
  std::vector<double> b(m, 0.0), r(m), p(m), q(m);
  std::vector<std::uint8_t> degree(m, 0), mask(m);
  tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
    const auto n = static_cast<std::int64_t>(unknown[e]);
    const std::int64_t i = n % nx, j = (n / nx) % ny, k = n / (nx * ny);
    const int bits = (i + 1 < nx ? 1 : 0) | (i > 0 ? 2 : 0) | (j + 1 < ny ? 4 : 0) | (j > 0 ? 8 : 0) | (k + 1 < nz ? 16 : 0) |
                     (k > 0 ? 32 : 0);
    mask[e] = static_cast<std::uint8_t>(bits);
    for (int s = 0; s < 6; ++s) {
      if (!(bits >> s & 1)) continue;
      ++degree[e];
      const auto nb = static_cast<std::size_t>(n + step[s]);
      if (g.known[nb]) b[e] += g.values[nb];
    }
  });
  // Each unknown's unknown neighbours, in the order of `step` (-1: none), looked up once (at
  // most 1031³ nodes: indices fit in 32 bits).
  std::vector<std::array<std::int32_t, 6>> neighbours(m);
  tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
    for (int s = 0; s < 6; ++s)
      neighbours[e][static_cast<std::size_t>(s)] =
          mask[e] >> s & 1 ? static_cast<std::int32_t>(id[static_cast<std::size_t>(static_cast<std::int64_t>(unknown[e]) + step[s])]) : -1;
  });
  id = {};
  auto apply = [&](const std::vector<double>& in, std::vector<double>& out) {
    tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
      double sum = degree[e] * in[e];
      for (const std::int32_t nb : neighbours[e])
        if (nb >= 0) sum -= in[static_cast<std::size_t>(nb)];
      out[e] = sum;
    });
  };

  apply(u, q);
  tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) { r[e] = b[e] - q[e]; });
  p = r;
  double rr = deterministic_sum(m, [&](std::size_t e) { return r[e] * r[e]; });
  const double bb = deterministic_sum(m, [&](std::size_t e) { return b[e] * b[e]; });
  const double target = 1e-12 * std::max(bb, std::numeric_limits<double>::min());
  const std::size_t max_iterations = 20 * static_cast<std::size_t>(std::max({nx, ny, nz}));
  std::uint64_t reported = 0;
  const double start = std::log(std::max(rr, target));
  for (std::size_t it = 0; it < max_iterations && rr > target; ++it) {
    if (reporter != nullptr && it % 16 == 0) {
      reporter->check();
      // Progress: the share of the way from the first residual to the target, on a log scale.
      const double done = start > std::log(target) ? (start - std::log(rr)) / (start - std::log(target)) : 1.0;
      const auto now = static_cast<std::uint64_t>(std::clamp(done, 0.0, 1.0) * 100);
      if (now > reported) reporter->advance(now - reported), reported = now;
    }
    apply(p, q);
    const double alpha = rr / deterministic_sum(m, [&](std::size_t e) { return p[e] * q[e]; });
    tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
      u[e] += alpha * p[e];
      r[e] -= alpha * q[e];
    });
    const double rr_next = deterministic_sum(m, [&](std::size_t e) { return r[e] * r[e]; });
    const double beta = rr_next / rr;
    rr = rr_next;
    tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) { p[e] = r[e] + beta * p[e]; });
  }
  for (std::size_t e = 0; e < m; ++e) g.values[unknown[e]] = static_cast<float>(u[e]);
  return m;
}

}  // namespace

ClosedSurface::ClosedSurface(const ImplicitSurface& surface, const ClosingOptions& options, double min_weight,
                             const ProgressCallback& progress)
    : surface_(&surface), min_weight_(min_weight) {
  if (options.resolution < 8 || options.resolution > 1024)
    throw OptionError("the fill grid's resolution must be from 8 to 1024 cells");
  if (!(min_weight >= 0) || !std::isfinite(min_weight)) throw OptionError("the blend's confidence floor must be a finite weight >= 0");
  const BoundingBox box = surface.tree().bbox;
  const double longest = box.extent().maxCoeff();
  if (!(longest > 0) || !std::isfinite(longest))
    throw OptionError("the surface has no extent (all input points coincide): there is nothing to close");
  cell_ = longest / options.resolution;
  constexpr int kMarginCells = 3;
  corner_ = box.min - Eigen::Vector3d::Constant(kMarginCells * cell_);
  for (int a = 0; a < 3; ++a) dims_[a] = static_cast<std::int64_t>(std::ceil(box.extent()(a) / cell_)) + 2 * kMarginCells + 1;
  outside_ = kMarginCells * cell_;
  const auto nx = dims_[0], ny = dims_[1], nz = dims_[2];
  const auto count = static_cast<std::size_t>(nx * ny * nz);
  grid_.assign(count, 0.0f);

  // 1. f at the nodes some blended support reaches (elsewhere the total weight is 0: f is
  //    undefined without evaluating it).
  detail::ProgressReporter reporter(progress, "closing holes", static_cast<std::uint64_t>(nz) + 100);
  std::vector<std::uint8_t> reached(count, 0);
  for (const std::int32_t node : surface.cut()) {
    const Eigen::Vector3d c = (surface.tree().nodes[static_cast<std::size_t>(node)].support.center - corner_) / cell_;
    const double rad = surface.radius(node) / cell_;
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil(c(a) - rad)));
      hi[a] = std::min<std::int64_t>(dims_[a] - 1, static_cast<std::int64_t>(std::floor(c(a) + rad)));
    }
    for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
          if ((Eigen::Vector3d(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)) - c).squaredNorm() < rad * rad)
            reached[static_cast<std::size_t>((k * ny + j) * nx + i)] = 1;
  }
  std::vector<std::uint8_t> known(count, 0);
  for (std::int64_t k = 0; k < nz; ++k) {
    reporter.check();
    tbb::parallel_for(std::int64_t{0}, ny, [&](std::int64_t j) {
      for (std::int64_t i = 0; i < nx; ++i) {
        const auto n = static_cast<std::size_t>((k * ny + j) * nx + i);
        if (!reached[n]) continue;
        const Eigen::Vector3d x = corner_ + cell_ * Eigen::Vector3d(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
        if (const auto f = surface.value(x, min_weight)) {
          // The fill takes the side, not the size: f clamped to the border's value, so that
          // inside and outside pull on a hole alike (an unclamped blend is large only where
          // some proxy happens to extrapolate steeply, which would tilt the fill).
          grid_[n] = static_cast<float>(std::clamp(*f, -outside_, outside_));
          known[n] = 1;
        }
      }
    });
    reporter.advance(1);
  }

  // 2. Laplace's equation on the nodes where f is undefined.
  FillGrid fill{nx, ny, nz, std::move(grid_), std::move(known)};
  unknowns_ = solve_fill(fill, &reporter);
  grid_ = std::move(fill.values);
  reporter.finish();
}

double ClosedSurface::fill_value(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d g = (x - corner_) / cell_;
  const Eigen::Vector3d last(static_cast<double>(dims_[0] - 1), static_cast<double>(dims_[1] - 1), static_cast<double>(dims_[2] - 1));
  if (!g.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  if ((g.array() < 0).any() || (g.array() > last.array()).any())
    return outside_ + cell_ * (g.cwiseMax(Eigen::Vector3d::Zero()).cwiseMin(last) - g).norm();
  const Eigen::Vector3d c = g.cwiseMin(last - Eigen::Vector3d::Constant(1e-9)).array().floor();
  const Eigen::Vector3d t = g - c;
  const auto i = static_cast<std::int64_t>(c.x()), j = static_cast<std::int64_t>(c.y()), k = static_cast<std::int64_t>(c.z());
  double v = 0;
  for (int d = 0; d < 8; ++d) {
    const int di = d & 1, dj = (d >> 1) & 1, dk = (d >> 2) & 1;
    const double w = (di ? t.x() : 1 - t.x()) * (dj ? t.y() : 1 - t.y()) * (dk ? t.z() : 1 - t.z());
    if (w > 0) v += w * node(i + di, j + dj, k + dk);
  }
  return v;
}

bool ClosedSurface::in_grid(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d g = (x - corner_) / cell_;
  const Eigen::Vector3d last(static_cast<double>(dims_[0] - 1), static_cast<double>(dims_[1] - 1), static_cast<double>(dims_[2] - 1));
  return (g.array() >= 0).all() && (g.array() <= last.array()).all();
}

bool ClosedSurface::filled(const Eigen::Vector3d& x) const {
  return !in_grid(x) || !surface_->value(x, min_weight_).has_value();
}

double ClosedSurface::value(const Eigen::Vector3d& x) const {
  if (!in_grid(x)) return fill_value(x);  // beyond the grid's border everything is outside
  const auto [a, w] = surface_->weighted_sum(x);
  if (w > 0 && w > min_weight_) return a / w;
  const double fill = fill_value(x);
  if (!(w > 0) || !(min_weight_ > 0)) return fill;
  // Below the confidence floor the blend fades into the fill: F stays continuous, so its zero
  // set has no seam (and no spurious sheet) where the fill takes over. λ(w) f = λ a / w → 0
  // with w (λ ~ w²), so the fade needs no clamp of f.
  const double t = w / min_weight_, lambda = t * t * (3 - 2 * t);
  return lambda * (a / w) + (1 - lambda) * fill;
}

}  // namespace clustersurf
