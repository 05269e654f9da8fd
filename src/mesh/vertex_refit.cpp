// Each vertex moved towards a local quadratic fit of the input points, by the share of the
// move that stands above the noise (a Wiener gain: the local power of the fits' moves above
// their noise, against the noise of the vertex's own move).

#include <clustersurf/cluster/noise.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/mesh/mesh_trim.hpp>
#include <clustersurf/mesh/vertex_refit.hpp>
#include <clustersurf/surface/box_walk.hpp>

#include "mesh/blend_noise.hpp"
#include "mesh/chord_sag.hpp"
#include "mesh/vertex_fit.hpp"
#include "mesh/vertex_move_guards.hpp"
#include "mesh/vertex_rings.hpp"
#include "spatial/spatial_order.hpp"

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

namespace clustersurf {

namespace {

/// Moves up to this share of the points' typical spread are not suspected of pushing the surface
/// through another part of it: they could only cross a part within twice that, closer than the
/// mesh's cells resolve.
constexpr double kSuspectMove = 0.1;

/// Consecutive vertices in spatial order whose supports are found by one walk of their box.
constexpr std::size_t kShareRun = 32;

/// What a vertex's Wiener share weighs, each averaged over the vertex's window (ring_mean());
/// an invalid fit counts zero in each.
struct WindowMeans {
  std::vector<double> squared;            ///< the moves' square
  std::vector<double> unit_variance;      ///< the moves' variance per unit variance of the noise
  std::vector<double> residual_variance;  ///< the noise the fits' residuals show without relief
  std::vector<double> dof;                ///< that noise's degrees of freedom
  std::vector<double> valid;              ///< 1 for a valid fit
  std::vector<double> coverage;           ///< the vertex's area over its fit's
};

WindowMeans window_means(const std::vector<detail::LocalFit>& fits, const std::vector<double>& area,
                         const detail::VertexRings& rings, std::uint32_t rounds) {
  const std::size_t n = fits.size();
  WindowMeans w;
  for (auto* values : {&w.squared, &w.unit_variance, &w.residual_variance, &w.dof, &w.valid, &w.coverage})
    values->assign(n, 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const detail::LocalFit& f = fits[v];
      if (!f.valid) continue;
      w.squared[v] = f.move * f.move;
      w.unit_variance[v] = f.unit_variance;
      w.residual_variance[v] = f.residual_variance;
      w.dof[v] = f.dof;
      w.valid[v] = 1;
      w.coverage[v] = area[v] / (std::numbers::pi * f.radius * f.radius);
    }
  });
  for (auto* values : {&w.squared, &w.unit_variance, &w.residual_variance, &w.dof, &w.valid, &w.coverage})
    *values = detail::ring_mean(rings, std::move(*values), rounds);
  return w;
}

/// The noise variance around vertex v: the smaller of the tree's and the relief-free one the
/// fits' residuals show over its window (relief_free_noise()), raised by the margin the tree's
/// noise tests allow an estimate of its degrees of freedom. The tree reads its noise from whole
/// clusters, whose quadratics leave relief it takes for noise.
double window_noise(const WindowMeans& w, std::size_t v, const ClusterTree& tree) {
  const double from_tree = tree.noise_sigma * tree.noise_sigma;
  if (!(w.valid[v] > 0)) return from_tree;
  return std::min(from_tree, w.residual_variance[v] / w.valid[v] * noise_variance_margin(w.dof[v] / w.valid[v]));
}

/// The supports of the crease leaves a surface blends: where one reaches, its two planes hold a
/// sharp edge that a quadratic would round.
class CreaseSupports {
 public:
  explicit CreaseSupports(const ImplicitSurface& surface) {
    for (const std::int32_t i : surface.cut()) {
      const ClusterNode& node = surface.tree().nodes[static_cast<std::size_t>(i)];
      if (!std::holds_alternative<CreaseProxy>(node.proxy.variant())) continue;
      supports_.push_back(Sphere{node.support.center, surface.radius(i)});
      reach_ = std::max(reach_, supports_.back().radius);
    }
    centers_.resize(static_cast<Eigen::Index>(supports_.size()), 3);
    for (std::size_t k = 0; k < supports_.size(); ++k)
      centers_.row(static_cast<Eigen::Index>(k)) = supports_[k].center.transpose();
    if (!supports_.empty()) index_ = std::make_unique<KdTree>(centers_);
  }

  /// Whether a crease leaf's support contains x.
  bool contain(const Eigen::Vector3d& x, std::vector<Neighbor>& near) const {
    if (!index_) return false;
    index_->radius_unsorted(x, reach_, near);
    return std::any_of(near.begin(), near.end(), [&](const Neighbor& nb) { return supports_[nb.index].contains(x); });
  }

 private:
  std::vector<Sphere> supports_;
  Points centers_;
  std::unique_ptr<KdTree> index_;
  double reach_ = 0;
};

/// Each vertex's widest consistent fit (widest_consistent_fit()) to the data's points nearest
/// to it, the blend's share of its variance taken away; none for the `held` vertices (positive),
/// those inside a crease leaf's support (then marked held) and those whose fit asks for more
/// than `max_move`.
std::vector<detail::LocalFit> local_fits(const TriangleMesh& mesh, const Points& normals, const KdTree& data,
                                         const ImplicitSurface& surface, const VertexRefitOptions& options,
                                         std::vector<float>& held, double max_move) {
  const CreaseSupports creases(surface);
  const auto n = static_cast<std::size_t>(mesh.vertices.rows());
  std::vector<detail::LocalFit> fits(n);
  // Queried in spatial order: consecutive queries visit the same part of the k-d tree and, in
  // runs of kShareRun, share one walk of the surface's supports.
  const std::vector<std::uint32_t> order = detail::spatial_order(mesh.vertices);
  const std::size_t wanted = options.points << (detail::kFitWidths - 1);
  const auto fit = [&](std::size_t v, const ImplicitSurface::BoxWalk& supports, std::vector<Neighbor>& near) {
    if (held[v] > 0) return;
    const Eigen::Vector3d x = mesh.vertices.row(static_cast<Eigen::Index>(v)).transpose();
    if (creases.contain(x, near)) {
      held[v] = 1;
      return;
    }
    data.knn(x, wanted, near);
    // Equally distant points in the order of their positions: the same sums whatever the data's
    // row order (a tile's points are numbered otherwise than the whole cloud's).
    std::sort(near.begin(), near.end(), [&](const Neighbor& p, const Neighbor& q) {
      if (p.distance_squared != q.distance_squared) return p.distance_squared < q.distance_squared;
      const auto a = data.points().row(p.index), b = data.points().row(q.index);
      return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end());
    });
    detail::LocalFit& f = fits[v];
    f = detail::widest_consistent_fit(x, normals.row(static_cast<Eigen::Index>(v)).transpose(), data.points(), near,
                                      options.points, surface.tree());
    // The blend lies within a spread of the data; a fit asking for more is not its sag (a vertex
    // at a rim left by the trim, fitted to points of another part).
    if (!(std::abs(f.move) <= max_move)) f = detail::LocalFit{};
    // The blend averages the same noise over the leaves' supports: of the fit's noise, the move
    // keeps what the blend does not (the variance of the difference of two nested averages is
    // the difference of their variances; none where the blend is the noisier).
    if (f.valid) f.unit_variance *= 1 - detail::blend_variance_share(supports, x, f.radius);
  };
  const std::size_t runs = (n + kShareRun - 1) / kShareRun;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, runs, 32), [&](const auto& range) {
    std::vector<Neighbor> near;
    for (std::size_t run = range.begin(); run != range.end(); ++run) {
      const std::size_t begin = run * kShareRun, end = std::min(n, begin + kShareRun);
      BoundingBox box;
      for (std::size_t o = begin; o != end; ++o) box.extend(mesh.vertices.row(order[o]).transpose());
      const ImplicitSurface::BoxWalk supports(surface, box);
      for (std::size_t o = begin; o != end; ++o) fit(order[o], supports, near);
    }
  });
  return fits;
}

}  // namespace

void check_refit_options(const VertexRefitOptions& options) {
  if (options.points > 0 && options.points < kMinRefitPoints)
    throw OptionError("refit_points must be 0 or at least " + std::to_string(kMinRefitPoints) +
                      " (a quadratic's coefficients), not " + std::to_string(options.points));
}

VertexRefitReport refit_vertices(TriangleMesh& mesh, const KdTree& data, const ImplicitSurface& surface,
                                 const VertexRefitOptions& options, std::span<const float> fixed) {
  const ClusterTree& tree = surface.tree();
  check_refit_options(options);
  VertexRefitReport report;
  const auto n = static_cast<std::size_t>(mesh.vertices.rows());
  if (options.points == 0 || n == 0 || data.size() < 6) return report;
  const bool has_normals = mesh.normals.rows() == mesh.vertices.rows();
  const Points computed = has_normals ? Points() : vertex_normals(mesh);
  const Points& normals = has_normals ? mesh.normals : computed;
  const double max_move = typical_spread(tree);
  // The vertices a crease leaf holds, and the fixed ones: neither is refitted nor offset.
  std::vector<float> held(fixed.begin(), fixed.end());
  held.resize(n, 0.0f);
  const std::vector<detail::LocalFit> fits = local_fits(mesh, normals, data, surface, options, held, max_move);
  const detail::VertexRings rings = detail::edge_neighbors(mesh);
  const WindowMeans means = window_means(fits, detail::vertex_areas(mesh, rings), rings, options.rings);
  // How many independent fits the window holds: its area over a fit's (neighbouring vertices'
  // fits share most of their points, so their moves are one sample of the noise, not several).
  const double window = detail::kernel_vertices(options.rings);
  const Points before = mesh.vertices;
  std::vector<double> moves(n, 0.0), shares(n, 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      if (!fits[v].valid) continue;
      const double noise = window_noise(means, v, tree);
      // The moves' power above the noise around the vertex, against the noise of its own move.
      const double samples = std::max(1.0, window * means.coverage[v]);
      // The upper quantile, as far out as the tree's noise tests reach, of a mean square of that
      // many samples of the noise (a long tail when they are few).
      const double signal =
          std::max(0.0, means.squared[v] - noise_variance_quantile(samples) * noise * means.unit_variance[v]);
      const double variance = noise * fits[v].unit_variance;
      const double share = signal + variance > 0 ? signal / (signal + variance) : 1.0;
      const auto row = static_cast<Eigen::Index>(v);
      moves[v] = share * fits[v].move;
      shares[v] = share;
      mesh.vertices.row(row) += moves[v] * normals.row(row).normalized();
    }
  });
  report.refitted = static_cast<std::size_t>(
      std::count_if(fits.begin(), fits.end(), [](const detail::LocalFit& f) { return f.valid; }));
  detail::undo_folds(mesh, before, moves);
  detail::undo_crossings(mesh, before, moves, kSuspectMove * max_move);
  if (options.chord_offset) report.mean_chord_offset = detail::offset_chord_sag(mesh, held);
  double moved = 0, shared = 0;
  for (std::size_t v = 0; v < n; ++v) moved += std::abs(moves[v]), shared += moves[v] != 0 ? shares[v] : 0.0;
  report.mean_move = moved / static_cast<double>(n);
  report.mean_share = report.refitted > 0 ? shared / static_cast<double>(report.refitted) : 0.0;
  return report;
}

}  // namespace clustersurf
