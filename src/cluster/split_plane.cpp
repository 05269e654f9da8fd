// Split-plane clustering (thesis 3.2.3): direction from 2-means, sort along it,
// sweep the split index with O(1) moment fits.

#include "cluster/splitters.hpp"

#include <clustersurf/proxy/moments.hpp>

#include "cluster/key_sort.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace clustersurf::detail {

namespace {

Eigen::Vector3d farthest_from(const Points& points, std::span<const std::uint32_t> range, const Eigen::Vector3d& x) {
  double best = -1;
  Eigen::Vector3d far = x;
  for (auto i : range) {
    const double d = (points.row(i).transpose() - x).squaredNorm();
    if (d > best) best = d, far = points.row(i).transpose();
  }
  return far;
}

/// Clusters larger than this estimate the split direction from an evenly strided subset.
constexpr std::size_t kDirectionSample = 4096;
/// Lloyd rounds for the direction: it converges to a few degrees within a handful.
constexpr int kDirectionRounds = 12;
/// Clusters of more than kSampledSplitMin points choose the split position on an evenly
/// strided sample of kSweepSample points.
constexpr std::size_t kSweepSample = 16384;
constexpr std::size_t kSampledSplitMin = 4 * kSweepSample;

/// Direction of eq. 3.7 from a 2-means split; the principal axis when that degenerates.
Eigen::Vector3d split_direction(const Points& points, std::span<const std::uint32_t> cluster, const Frame& frame) {
  std::vector<std::uint32_t> sample;
  std::span<const std::uint32_t> range = cluster;
  if (cluster.size() > kDirectionSample) {
    sample.resize(kDirectionSample);
    for (std::size_t k = 0; k < kDirectionSample; ++k) sample[k] = cluster[k * cluster.size() / kDirectionSample];
    range = sample;
  }
  const Eigen::Vector3d mean = frame.origin;
  const Eigen::Vector3d a = farthest_from(points, range, mean);
  const Eigen::Vector3d b = farthest_from(points, range, a);
  const TwoMeans tm = two_means(points, range, a, b, kDirectionRounds);
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  if (tm.sizes[0] > 0 && tm.sizes[1] > 0)
    n = static_cast<double>(tm.sizes[0]) * (tm.centers[0] - mean) -
        static_cast<double>(tm.sizes[1]) * (tm.centers[1] - mean);
  const double scale = (b - a).norm() * static_cast<double>(range.size());
  if (!(n.norm() > 1e-12 * scale)) return frame.axes.col(0);
  return n.normalized();
}

/// Moments of one side of a split. Its error is the tighter of two O(1) upper bounds of the
/// side's own fit error: the PCA plane (exact for the side, frame-free) and, for polynomial
/// proxies, the polynomial in the parent's fixed frame (tight while the parent is a height field
/// over that frame, loose for large curved clusters).
struct SideMoments {
  PlaneMoments plane;
  std::optional<PolyMoments> poly;
  void add(const Eigen::Vector3d& p) {
    plane.add(p);
    if (poly) poly->add(p);
  }
  SideMoments& operator+=(const SideMoments& o) {
    plane += o.plane;
    if (poly) *poly += *o.poly;
    return *this;
  }
};

/// What the sweep needs of one side: its fit error and its elongation, the ratio of its two
/// largest principal spreads (1 for a round patch), from one eigen-decomposition.
struct SideFit {
  double error = 0;
  double elongation = 0;
};

SideFit side_fit(const SideMoments& m) {
  const Eigen::Vector3d s = m.plane.spreads();
  const double plane_error = std::sqrt(s(0));
  return {m.poly ? std::min(plane_error, m.poly->rms_error()) : plane_error,
          s(1) > 0 ? std::sqrt(s(2) / s(1)) : std::numeric_limits<double>::infinity()};
}

/// Children may be this elongated (or as elongated as their parent): thinner slivers make
/// leaves whose support spheres reach far sideways of the strip their proxy was fitted to.
constexpr double kMaxElongation = 3.0;

/// Among the candidate split positions, the one minimizing max(e+, e−) among those that cut no
/// sliver (among all candidates when each one does). `blocks[k]` holds the moments of the
/// sorted points between candidates k − 1 and k (the last block: after the last candidate), so
/// each point is added once and each side is fitted once per candidate.
std::size_t sweep(const std::vector<SideMoments>& blocks, const SideMoments& empty,
                  const std::vector<std::size_t>& candidates, std::size_t m, double noise) {
  const std::size_t c = candidates.size();
  std::vector<SideFit> left(c), right(c);
  SideMoments acc = empty;
  for (std::size_t k = 0; k < c; ++k) left[k] = side_fit(acc += blocks[k]);
  const double shape_limit = std::max(kMaxElongation, side_fit(acc += blocks[c]).elongation);
  acc = empty;
  for (std::size_t k = c; k-- > 0;) right[k] = side_fit(acc += blocks[k + 1]);
  std::vector<std::uint8_t> allowed(c);
  bool any_allowed = false;
  for (std::size_t k = 0; k < c; ++k) {
    allowed[k] = left[k].elongation <= shape_limit && right[k].elongation <= shape_limit;
    any_allowed = any_allowed || allowed[k];
  }
  if (!any_allowed) std::fill(allowed.begin(), allowed.end(), 1);

  // Scores within 2 % of the best (or within the noise, whose part of the error no split can
  // remove) count as ties: among them take the most balanced split, so noise-dominated
  // clusters are halved instead of cut at an arbitrary position.
  std::vector<double> score(c);
  double best_score = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < c; ++k) {
    const double e = std::max(left[k].error, right[k].error);
    score[k] = std::sqrt(std::max(0.0, e * e - noise * noise));
    if (allowed[k]) best_score = std::min(best_score, score[k]);
  }
  std::size_t best = 0;
  double best_balance = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < c; ++k) {
    if (!allowed[k] || score[k] > best_score * 1.02) continue;
    const double balance = std::abs(2.0 * static_cast<double>(candidates[k]) - static_cast<double>(m));
    if (balance < best_balance) best_balance = balance, best = candidates[k];
  }
  return best;
}

/// Sorts `range` along `n` and returns the best split position by the sweep.
std::size_t sorted_split(const Points& points, std::span<std::uint32_t> range, const Eigen::Vector3d& n,
                         const Frame& parent_frame, const BuildOptions& options, std::size_t kmin, double noise) {
  const std::size_t m = range.size();
  std::vector<KeyedIndex> keyed(m);
  for (std::size_t k = 0; k < m; ++k) keyed[k] = {n.dot(points.row(range[k]).transpose()), range[k]};
  sort_by_key(keyed);  // ties by point index: reproducible
  for (std::size_t k = 0; k < m; ++k) range[k] = keyed[k].second;

  const std::size_t span_len = m - 2 * kmin;
  const std::size_t step = options.kstep > 0 ? options.kstep : std::max<std::size_t>(1, span_len / 64);
  std::vector<std::size_t> candidates;
  for (std::size_t k = kmin; k <= m - kmin; k += step) candidates.push_back(k);

  SideMoments empty{PlaneMoments(parent_frame.origin), std::nullopt};
  if (options.proxy != ProxyKind::Plane) {
    // Polynomial moments in the parent's fixed frame (also a bound for point and quadric
    // proxies, whose fits have no O(1) update).
    double scale = 0;
    for (auto i : range) scale = std::max(scale, parent_frame.to_local(points.row(i).transpose()).head<2>().norm());
    empty.poly.emplace(parent_frame, scale > 0 ? scale : 1.0);
  }
  std::vector<SideMoments> blocks(candidates.size() + 1, empty);
  std::size_t block = 0;
  for (std::size_t i = 0; i < m; ++i) {
    while (block < candidates.size() && candidates[block] == i) ++block;
    blocks[block].add(points.row(range[i]).transpose());
  }
  return sweep(blocks, empty, candidates, m, noise);
}

}  // namespace

std::size_t split_plane(const Points& points, std::span<std::uint32_t> range, const Frame& parent_frame,
                        const BuildOptions& options, double noise) {
  const std::size_t m = range.size();
  const std::size_t kmin = std::max<std::size_t>(1, options.min_points);
  if (m < 2 * kmin) return 0;
  const Eigen::Vector3d n = split_direction(points, range, parent_frame);

  // Large clusters choose the split position on an evenly strided sample and then partition
  // every point by the chosen plane: O(m) instead of a full sort and two full sweeps. Their
  // splits are far above the leaves, where the sample's errors rank positions as the full set's do.
  if (m > kSampledSplitMin && options.kstep == 0) {
    std::vector<std::uint32_t> sample(kSweepSample);
    for (std::size_t k = 0; k < kSweepSample; ++k) sample[k] = range[k * m / kSweepSample];
    // Neither side may be a sliver: a few points cut off a large cluster make a thin strip whose
    // support sphere spans far beyond where its proxy is constrained.
    const std::size_t kmin_sample = std::max<std::size_t>(kSweepSample / 64, (kmin * kSweepSample + m - 1) / m);
    const std::size_t b = sorted_split(points, sample, n, parent_frame, options, kmin_sample, noise);
    const auto key = [&](std::uint32_t i) { return n.dot(points.row(i).transpose()); };
    const double cut = 0.5 * (key(sample[b - 1]) + key(sample[b]));
    const auto mid = std::stable_partition(range.begin(), range.end(), [&](std::uint32_t i) { return key(i) < cut; });
    const auto k = static_cast<std::size_t>(mid - range.begin());
    if (k >= kmin && m - k >= kmin) return k;
  }
  return sorted_split(points, range, n, parent_frame, options, kmin, noise);
}

}  // namespace clustersurf::detail
