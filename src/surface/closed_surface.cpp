// The harmonic fill of ClosedSurface: f sampled on a coarse grid, Laplace's equation solved at
// the nodes where f is undefined (fill_solver.cpp), and F, f faded into the fill.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/surface/closed_surface.hpp>

#include "core/progress_reporter.hpp"
#include "surface/fill_solver.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace clustersurf {

ClosedSurface::ClosedSurface(const ImplicitSurface& surface, const ClosingOptions& options, double min_weight,
                             const ProgressCallback& progress)
    : surface_(&surface), min_weight_(min_weight) {
  if (options.resolution < 8 || options.resolution > 1024)
    throw OptionError("the fill grid's resolution must be from 8 to 1024 cells");
  if (!(min_weight >= 0) || !std::isfinite(min_weight))
    throw OptionError("the blend's confidence floor must be a finite weight >= 0");
  const BoundingBox box = surface.tree().bbox;
  const double longest = box.extent().maxCoeff();
  if (!(longest > 0) || !std::isfinite(longest))
    throw OptionError("the surface has no extent (all input points coincide): there is nothing to close");
  cell_ = longest / options.resolution;
  constexpr int kMarginCells = 3;
  corner_ = box.min - Eigen::Vector3d::Constant(kMarginCells * cell_);
  for (int a = 0; a < 3; ++a)
    dims_[a] = static_cast<std::int64_t>(std::ceil(box.extent()(a) / cell_)) + 2 * kMarginCells + 1;
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
          if ((Eigen::Vector3d(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)) - c)
                  .squaredNorm() < rad * rad)
            reached[static_cast<std::size_t>((k * ny + j) * nx + i)] = 1;
  }
  std::vector<std::uint8_t> known(count, 0);
  for (std::int64_t k = 0; k < nz; ++k) {
    reporter.check();
    tbb::parallel_for(std::int64_t{0}, ny, [&](std::int64_t j) {
      for (std::int64_t i = 0; i < nx; ++i) {
        const auto n = static_cast<std::size_t>((k * ny + j) * nx + i);
        if (!reached[n]) continue;
        const Eigen::Vector3d x =
            corner_ + cell_ * Eigen::Vector3d(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
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
  detail::FillGrid fill{nx, ny, nz, std::move(grid_), std::move(known)};
  unknowns_ = detail::solve_fill(fill, &reporter);
  grid_ = std::move(fill.values);
  reporter.finish();
}

double ClosedSurface::fill_value(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d g = (x - corner_) / cell_;
  const Eigen::Vector3d last(static_cast<double>(dims_[0] - 1), static_cast<double>(dims_[1] - 1),
                             static_cast<double>(dims_[2] - 1));
  if (!g.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  if ((g.array() < 0).any() || (g.array() > last.array()).any())
    return outside_ + cell_ * (g.cwiseMax(Eigen::Vector3d::Zero()).cwiseMin(last) - g).norm();
  const Eigen::Vector3d c = g.cwiseMin(last - Eigen::Vector3d::Constant(1e-9)).array().floor();
  const Eigen::Vector3d t = g - c;
  const auto i = static_cast<std::int64_t>(c.x()), j = static_cast<std::int64_t>(c.y()),
             k = static_cast<std::int64_t>(c.z());
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
  const Eigen::Vector3d last(static_cast<double>(dims_[0] - 1), static_cast<double>(dims_[1] - 1),
                             static_cast<double>(dims_[2] - 1));
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
