// Laplace's equation on a grid's unknown nodes: multigrid-preconditioned conjugate gradients;
// see fill_solver.hpp.

#include "surface/fill_solver.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace clustersurf::detail {

namespace {

/// Grids with no more unknowns than this (or no side longer than kCoarsestSide) end the
/// hierarchy; the V-cycle smooths there kCoarsestSweeps times instead of recursing.
constexpr std::size_t kCoarsestUnknowns = 4096;
constexpr std::int64_t kCoarsestSide = 8;
constexpr int kCoarsestSweeps = 40;
/// Damped Jacobi sweeps before and after the coarse correction, and their damping (below 1:
/// the smoother converges for the 7-point Laplacian, whose Jacobi eigenvalues lie in [0, 2)).
constexpr int kSmoothingSweeps = 2;
constexpr double kDamping = 6.0 / 7.0;

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

using Vector = std::vector<double>;

/// Calls visit(s, neighbour) for the six neighbours of node n of an nx × ny × nz grid, in the
/// order +x, −x, +y, −y, +z, −z; `neighbour` is −1 beyond the grid's border.
template <class Visit>
void for_each_neighbour(std::int64_t nx, std::int64_t ny, std::int64_t nz, std::int64_t n, Visit&& visit) {
  const std::int64_t i = n % nx, j = (n / nx) % ny, k = n / (nx * ny);
  const bool inside[6] = {i + 1 < nx, i > 0, j + 1 < ny, j > 0, k + 1 < nz, k > 0};
  const std::int64_t step[6] = {1, -1, nx, -nx, nx * ny, -nx * ny};
  for (int s = 0; s < 6; ++s) visit(s, inside[s] ? n + step[s] : std::int64_t{-1});
}

/// The unknowns of one grid and their operator: A u = degree · u − Σ unknown neighbours.
struct Level {
  std::int64_t nx = 0, ny = 0, nz = 0;
  std::vector<std::size_t> unknown;                     // node of each unknown
  std::vector<std::int32_t> id;                         // node → unknown, −1 when known
  std::vector<std::array<std::int32_t, 6>> neighbours;  // unknown neighbours, −1: none
  std::vector<std::uint8_t> degree;                     // neighbours inside the grid

  std::size_t size() const { return unknown.size(); }
  std::size_t node(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::size_t>((k * ny + j) * nx + i);
  }

  void apply(const Vector& in, Vector& out) const {
    tbb::parallel_for(std::size_t{0}, size(), [&](std::size_t e) {
      double sum = degree[e] * in[e];
      for (const std::int32_t nb : neighbours[e])
        if (nb >= 0) sum -= in[static_cast<std::size_t>(nb)];
      out[e] = sum;
    });
  }
};

Level make_level(std::int64_t nx, std::int64_t ny, std::int64_t nz, const std::vector<std::uint8_t>& known) {
  Level l;
  l.nx = nx, l.ny = ny, l.nz = nz;
  const auto count = static_cast<std::size_t>(nx * ny * nz);
  l.id.assign(count, -1);
  l.unknown.reserve(static_cast<std::size_t>(std::count(known.begin(), known.end(), std::uint8_t{0})));
  for (std::size_t n = 0; n < count; ++n)
    if (!known[n]) l.id[n] = static_cast<std::int32_t>(l.unknown.size()), l.unknown.push_back(n);
  const std::size_t m = l.size();
  l.neighbours.resize(m);
  l.degree.assign(m, 0);
  tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
    for_each_neighbour(nx, ny, nz, static_cast<std::int64_t>(l.unknown[e]), [&](int s, std::int64_t nb) {
      l.neighbours[e][static_cast<std::size_t>(s)] = nb >= 0 ? l.id[static_cast<std::size_t>(nb)] : -1;
      l.degree[e] = static_cast<std::uint8_t>(l.degree[e] + (nb >= 0 ? 1 : 0));
    });
  });
  return l;
}

/// The coarse grid's nodes: every other node of `fine` (the last one kept), known where that
/// node is.
Level coarsen(const Level& fine) {
  const std::int64_t cx = (fine.nx + 1) / 2, cy = (fine.ny + 1) / 2, cz = (fine.nz + 1) / 2;
  std::vector<std::uint8_t> known(static_cast<std::size_t>(cx * cy * cz));
  for (std::int64_t k = 0; k < cz; ++k)
    for (std::int64_t j = 0; j < cy; ++j)
      for (std::int64_t i = 0; i < cx; ++i)
        known[static_cast<std::size_t>((k * cy + j) * cx + i)] =
            fine.id[fine.node(std::min(2 * i, fine.nx - 1), std::min(2 * j, fine.ny - 1),
                              std::min(2 * k, fine.nz - 1))] < 0;
  return make_level(cx, cy, cz, known);
}

/// The weight of coarse index c in the trilinear interpolation to fine index f along an axis
/// of `coarse` coarse nodes (fine node 2c sits on coarse node c).
double axis_weight(std::int64_t f, std::int64_t c, std::int64_t coarse) {
  const std::int64_t lo = f / 2;
  if (f % 2 == 0 || lo + 1 >= coarse) return c == lo ? 1.0 : 0.0;
  return c == lo || c == lo + 1 ? 0.5 : 0.0;
}

/// The multigrid hierarchy below a grid and its V-cycle, a symmetric positive definite
/// approximation of A⁻¹.
class Multigrid {
 public:
  explicit Multigrid(Level finest) {
    levels_.push_back(std::move(finest));
    while (levels_.back().size() > kCoarsestUnknowns &&
           std::max({levels_.back().nx, levels_.back().ny, levels_.back().nz}) > kCoarsestSide)
      levels_.push_back(coarsen(levels_.back()));
    work_.resize(levels_.size());
  }
  const Level& finest() const { return levels_.front(); }

  /// z = M r on the finest level.
  void precondition(const Vector& r, Vector& z) const { cycle(0, r, z); }

 private:
  /// Damped Jacobi sweeps on A z = r, from z.
  static void smooth(const Level& l, const Vector& r, Vector& z, int sweeps, Vector& scratch) {
    for (int s = 0; s < sweeps; ++s) {
      l.apply(z, scratch);
      tbb::parallel_for(std::size_t{0}, l.size(),
                        [&](std::size_t e) { z[e] += kDamping * (r[e] - scratch[e]) / l.degree[e]; });
    }
  }

  void cycle(std::size_t at, const Vector& r, Vector& z) const {
    const Level& l = levels_[at];
    z.assign(l.size(), 0.0);
    Vector& scratch = work_[at].scratch;
    scratch.resize(l.size());
    if (at + 1 == levels_.size()) {
      smooth(l, r, z, kCoarsestSweeps, scratch);
      return;
    }
    smooth(l, r, z, kSmoothingSweeps, scratch);
    // The residual, restricted (the transpose of the interpolation, over 8) and scaled by 4
    // (the coarse operator's cells are twice as wide), solved for on the coarse level.
    l.apply(z, scratch);
    tbb::parallel_for(std::size_t{0}, l.size(), [&](std::size_t e) { scratch[e] = r[e] - scratch[e]; });
    const Level& c = levels_[at + 1];
    Vector& coarse_r = work_[at].coarse_r;
    Vector& coarse_z = work_[at].coarse_z;
    coarse_r.resize(c.size());
    tbb::parallel_for(std::size_t{0}, c.size(), [&](std::size_t e) {
      const auto n = static_cast<std::int64_t>(c.unknown[e]);
      const std::int64_t ci = n % c.nx, cj = (n / c.nx) % c.ny, ck = n / (c.nx * c.ny);
      double sum = 0;
      for (std::int64_t k = std::max<std::int64_t>(0, 2 * ck - 1); k <= std::min(l.nz - 1, 2 * ck + 1); ++k)
        for (std::int64_t j = std::max<std::int64_t>(0, 2 * cj - 1); j <= std::min(l.ny - 1, 2 * cj + 1); ++j)
          for (std::int64_t i = std::max<std::int64_t>(0, 2 * ci - 1); i <= std::min(l.nx - 1, 2 * ci + 1); ++i) {
            const std::int32_t f = l.id[l.node(i, j, k)];
            if (f < 0) continue;
            const double w = axis_weight(i, ci, c.nx) * axis_weight(j, cj, c.ny) * axis_weight(k, ck, c.nz);
            sum += w * scratch[static_cast<std::size_t>(f)];
          }
      coarse_r[e] = 0.5 * sum;  // 4 / 8
    });
    cycle(at + 1, coarse_r, coarse_z);
    // The correction, interpolated back.
    tbb::parallel_for(std::size_t{0}, l.size(), [&](std::size_t e) {
      const auto n = static_cast<std::int64_t>(l.unknown[e]);
      const std::int64_t i = n % l.nx, j = (n / l.nx) % l.ny, k = n / (l.nx * l.ny);
      double sum = 0;
      for (std::int64_t ck = k / 2; ck <= std::min(c.nz - 1, k / 2 + 1); ++ck)
        for (std::int64_t cj = j / 2; cj <= std::min(c.ny - 1, j / 2 + 1); ++cj)
          for (std::int64_t ci = i / 2; ci <= std::min(c.nx - 1, i / 2 + 1); ++ci) {
            const std::int32_t g = c.id[c.node(ci, cj, ck)];
            if (g < 0) continue;
            const double w = axis_weight(i, ci, c.nx) * axis_weight(j, cj, c.ny) * axis_weight(k, ck, c.nz);
            sum += w * coarse_z[static_cast<std::size_t>(g)];
          }
      z[e] += sum;
    });
    smooth(l, r, z, kSmoothingSweeps, scratch);
  }

  std::vector<Level> levels_;
  /// Each level's vectors, kept from one cycle to the next (precondition() is not reentrant).
  struct Work {
    Vector scratch, coarse_r, coarse_z;
  };
  mutable std::vector<Work> work_;
};

/// solve_fill(); `advance`: whether this level reports progress to `reporter` (the coarser
/// levels only check for cancellation).
std::size_t solve(FillGrid& g, ProgressReporter* reporter, bool advance);

/// The start of the solve of `g`'s m unknowns (in node order): zero, or on a grid wider than 24
/// nodes, the same problem solved on every other node and interpolated (a start that leaves the
/// fine detail to the finer solve).
Vector coarse_start(const FillGrid& g, std::size_t m, ProgressReporter* reporter) {
  const std::int64_t nx = g.nx, ny = g.ny, nz = g.nz;
  Vector u(m, 0.0);
  if (std::max({nx, ny, nz}) <= 24) return u;
  std::vector<std::size_t> unknown;
  unknown.reserve(m);
  for (std::size_t n = 0; n < g.known.size(); ++n)
    if (!g.known[n]) unknown.push_back(n);
  FillGrid coarse{(nx + 1) / 2, (ny + 1) / 2, (nz + 1) / 2, {}, {}};
  const auto coarse_count = static_cast<std::size_t>(coarse.nx * coarse.ny * coarse.nz);
  coarse.values.resize(coarse_count);
  coarse.known.resize(coarse_count);
  for (std::int64_t k = 0; k < coarse.nz; ++k)
    for (std::int64_t j = 0; j < coarse.ny; ++j)
      for (std::int64_t i = 0; i < coarse.nx; ++i) {
        const auto c = static_cast<std::size_t>((k * coarse.ny + j) * coarse.nx + i);
        const auto f = static_cast<std::size_t>((std::min(2 * k, nz - 1) * ny + std::min(2 * j, ny - 1)) * nx +
                                                std::min(2 * i, nx - 1));
        coarse.values[c] = g.values[f];
        coarse.known[c] = g.known[f];
      }
  solve(coarse, reporter, false);
  tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
    const auto n = static_cast<std::int64_t>(unknown[e]);
    const double x = static_cast<double>(n % nx) / 2, y = static_cast<double>((n / nx) % ny) / 2,
                 z = static_cast<double>(n / (nx * ny)) / 2;
    const std::int64_t i = std::min(static_cast<std::int64_t>(x), coarse.nx - 1),
                       j = std::min(static_cast<std::int64_t>(y), coarse.ny - 1),
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
  return u;
}

/// Multigrid-preconditioned conjugate gradients on the finest level's system A u = b from `u`,
/// to a residual of 1e-12 |b|² or `max_iterations`; progress on a log scale of the residual
/// when `advance`.
void conjugate_gradients(const Multigrid& multigrid, Vector b, Vector& u, std::size_t max_iterations,
                         ProgressReporter* reporter, bool advance) {
  const Level& l = multigrid.finest();
  const std::size_t m = u.size();
  Vector r(m), z(m), p(m), q(m);
  l.apply(u, q);
  tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) { r[e] = b[e] - q[e]; });
  double rr = deterministic_sum(m, [&](std::size_t e) { return r[e] * r[e]; });
  const double bb = deterministic_sum(m, [&](std::size_t e) { return b[e] * b[e]; });
  b = {};
  const double target = 1e-12 * std::max(bb, std::numeric_limits<double>::min());
  multigrid.precondition(r, z);
  p = z;
  double rz = deterministic_sum(m, [&](std::size_t e) { return r[e] * z[e]; });
  std::uint64_t reported = 0;
  const double start = std::log(std::max(rr, target));
  for (std::size_t it = 0; it < max_iterations && rr > target; ++it) {
    if (reporter != nullptr) reporter->check();
    if (reporter != nullptr && advance) {
      // Progress: the share of the way from the first residual to the target, on a log scale.
      const double done = start > std::log(target) ? (start - std::log(rr)) / (start - std::log(target)) : 1.0;
      const auto now = static_cast<std::uint64_t>(std::clamp(done, 0.0, 1.0) * 100);
      if (now > reported) reporter->advance(now - reported), reported = now;
    }
    l.apply(p, q);
    const double alpha = rz / deterministic_sum(m, [&](std::size_t e) { return p[e] * q[e]; });
    tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
      u[e] += alpha * p[e];
      r[e] -= alpha * q[e];
    });
    rr = deterministic_sum(m, [&](std::size_t e) { return r[e] * r[e]; });
    if (!(rr > target)) break;
    multigrid.precondition(r, z);
    const double rz_next = deterministic_sum(m, [&](std::size_t e) { return r[e] * z[e]; });
    const double beta = rz_next / rz;
    rz = rz_next;
    tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) { p[e] = z[e] + beta * p[e]; });
  }
}

std::size_t solve(FillGrid& g, ProgressReporter* reporter, bool advance) {
  const std::int64_t nx = g.nx, ny = g.ny, nz = g.nz;
  const auto m = static_cast<std::size_t>(std::count(g.known.begin(), g.known.end(), std::uint8_t{0}));
  if (m == 0) return 0;
  // The start first, so that the coarser problems' hierarchies are gone before this one's is
  // built; the unknowns in node order, as make_level() numbers them.
  Vector u = coarse_start(g, m, reporter);
  const Multigrid multigrid(make_level(nx, ny, nz, g.known));
  const Level& l = multigrid.finest();
  // b: the known neighbours' values.
  Vector b(m, 0.0);
  tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
    for_each_neighbour(nx, ny, nz, static_cast<std::int64_t>(l.unknown[e]), [&](int, std::int64_t nb) {
      if (nb >= 0 && g.known[static_cast<std::size_t>(nb)]) b[e] += g.values[static_cast<std::size_t>(nb)];
    });
  });
  conjugate_gradients(multigrid, std::move(b), u, 20 * static_cast<std::size_t>(std::max({nx, ny, nz})), reporter,
                      advance);
  for (std::size_t e = 0; e < m; ++e) g.values[l.unknown[e]] = static_cast<float>(u[e]);
  return m;
}

}  // namespace

std::size_t solve_fill(FillGrid& g, ProgressReporter* reporter) { return solve(g, reporter, true); }

}  // namespace clustersurf::detail
