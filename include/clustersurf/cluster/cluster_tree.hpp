#pragma once
// The cluster tree: a binary tree of point clusters, each with a fitted proxy and support
// sphere (thesis ch. 3).

#include <clustersurf/cluster/noise.hpp>
#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/core/progress.hpp>
#include <clustersurf/proxy/proxy.hpp>
#include <clustersurf/spatial/cloud_index.hpp>
#include <clustersurf/spatial/outliers.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace clustersurf {

/// How a cluster is split in two. Values are stored in tree files: never renumber.
enum class SplitterKind : std::uint8_t { SplitPlane = 0, Lloyd = 1 };
/// Which error of a cluster's proxy is compared with the threshold. Stored in tree files.
enum class ErrorMetric : std::uint8_t { Rms = 0, Max = 1 };
/// How the error threshold is given. Stored in tree files.
enum class ThresholdMode : std::uint8_t {
  Relative = 0,  ///< value × bounding-box diagonal of the input
  Absolute = 1,  ///< value, in the input's units
  Auto = 2,      ///< hypot(value × diagonal, noise_factor × estimated noise): the noise plus a tolerance
};

const char* to_string(SplitterKind kind);
const char* to_string(ErrorMetric metric);
const char* to_string(ThresholdMode mode);
/// The splitter named by to_string(): "split-plane" or "lloyd". Throws OptionError otherwise.
SplitterKind parse_splitter(std::string_view text);
/// The metric named by to_string(): "rms" or "max". Throws OptionError otherwise.
ErrorMetric parse_error_metric(std::string_view text);

/// Options of build_cluster_tree(); the defaults are the recommended settings. Plain values:
/// progress and cancellation are build_cluster_tree()'s own argument.
struct BuildOptions {
  ProxyKind proxy = ProxyKind::Poly;  ///< proxy fitted to every node
  SplitterKind splitter = SplitterKind::SplitPlane;
  ErrorMetric metric = ErrorMetric::Rms;  ///< RMS: max never drops below scanner noise
  ThresholdMode threshold_mode = ThresholdMode::Auto;
  /// The error a leaf may keep on top of the noise; relative (fraction of the diagonal) or
  /// absolute. A cluster is a leaf when its error is ≤ hypot(tolerance, noise) (the noise with
  /// a margin for small clusters: cluster_error_threshold()).
  double tolerance = 0.00005;
  /// Auto: the noise counted is this × the estimate; 0 counts none (the tree is then built and
  /// stored as Relative, with no estimate).
  double noise_factor = 1.0;
  /// No child below this many points (but strays cut off across a gap, and the sheets of a
  /// would-be leaf on two sheets); 0: leaf_min_points() of the noise and the point spacing, and a
  /// leaf of that size whose quadratic misses the threshold is split into halves of two thirds
  /// of it when they resolve the misfit (relief finer than the clusters).
  std::uint32_t min_points = 0;
  std::uint32_t max_depth = 200;  ///< nodes at this depth are leaves (root: 0)
  /// Support radius = alpha × cluster bbox diagonal; 0: support_alpha() of the noise and the
  /// point spacing.
  double alpha = 0;
  std::uint32_t kstep = 0;                   ///< split-plane sweep step; 0: ≤ 64 candidates
  std::uint32_t lloyd_restarts = 4;          ///< Lloyd splitter: 2-means restarts
  std::uint32_t proxy_lloyd_iterations = 0;  ///< Lloyd splitter: proxy refinement rounds
  std::uint64_t seed = 1;                    ///< seeds every random choice (Lloyd seeding)
  /// A leaf must also fit the input points inside its support sphere: the RMS of |Q| over
  /// them, weighted by the blending weight, must be at most hypot(noise, support_factor ×
  /// tolerance) (MPU's rule; by default the bound its own points meet). Polynomial proxies are refitted to those
  /// weighted points (MPU's local fit), so they hold wherever the blend uses them and average the noise over the whole
  /// support. Keeps the blend accurate where supports overlap and stops large clusters from
  /// extrapolating across the model. 0 turns the check and the refit off.
  double support_factor = 1.0;
  /// A leaf's support grows beyond alpha × its extent until it holds this many input points
  /// (MPU's N_min; at most 4 times that radius): small leaves overlap their neighbours instead
  /// of leaving gaps. The default is the fewest points its refit takes; a larger count makes
  /// supports reach past where the leaves' quadratics hold. 0: no growth.
  std::uint32_t support_points = 12;
  /// Leave isolated points (find_outliers(): scanner strays, points in the air) out of every
  /// cluster, the noise estimate and the support checks; their point_leaf is -1.
  bool remove_outliers = true;
  /// Where the input has normals: a would-be leaf whose normals fall into two groups facing
  /// apart (both sides of a thin part, the faces of a deep fold) is split into its two sheets,
  /// each of at least 3 points. Off, or without normals, the tree depends on the positions alone.
  bool use_normals = true;
  /// With use_normals: a cluster's tangent plane comes from the mean of its input normals
  /// instead of its principal components where the normals pin it down better (noisy positions,
  /// consistent normals: a noisy thin part has no principal plane). Without input normals, a
  /// cluster as thick as it is wide (its principal frame the noise's) takes the mean axis of
  /// normals estimated over its points' 30 nearest neighbours where they pin it down better.
  /// Clean data keep the principal plane either way.
  bool frames_from_normals = true;
  /// With use_normals and support_factor > 0: a leaf's support fit also follows the slopes of
  /// the input normals (either sign), weighted by how much surer they are than the positions
  /// (exact normals on noisy positions: noise averages out faster), and only where they add at
  /// least about a tenth of the positions' information. Clean data and a scanner's normals,
  /// computed from the same positions, are mostly left to the positions. The normals also mark
  /// where another sheet begins: the support stops short of it (the far side of a thin part, a
  /// fold's other wall).
  bool fit_normals = true;
  /// A cluster on the two faces of a sharp edge, which no smooth proxy fits within the
  /// threshold, becomes a leaf whose proxy is the crease of two planes (CreaseProxy) when that
  /// fits: edges and corners of machined parts stay sharp instead of rounded and lumpy.
  bool creases = true;
  OutlierOptions outliers;        ///< the outlier test
  NoiseOptions noise;             ///< the noise estimate of the Auto threshold
  bool keep_point_leaves = true;  ///< store the leaf of every input point
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<BuildOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("proxy", o.proxy);
  f("splitter", o.splitter);
  f("metric", o.metric);
  f("threshold_mode", o.threshold_mode);
  f("tolerance", o.tolerance);
  f("noise_factor", o.noise_factor);
  f("min_points", o.min_points);
  f("max_depth", o.max_depth);
  f("alpha", o.alpha);
  f("kstep", o.kstep);
  f("lloyd_restarts", o.lloyd_restarts);
  f("proxy_lloyd_iterations", o.proxy_lloyd_iterations);
  f("seed", o.seed);
  f("support_factor", o.support_factor);
  f("support_points", o.support_points);
  f("remove_outliers", o.remove_outliers);
  f("use_normals", o.use_normals);
  f("frames_from_normals", o.frames_from_normals);
  f("fit_normals", o.fit_normals);
  f("creases", o.creases);
  f("outliers", o.outliers);
  f("noise", o.noise);
  f("keep_point_leaves", o.keep_point_leaves);
}

/// A sphere by center and radius.
struct Sphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0;
  bool contains(const Eigen::Vector3d& x) const { return (x - center).squaredNorm() < radius * radius; }
};

/// The blending weight of a node's support sphere at s = ‖x − c‖² / r² (< 1): (1 − s)³.
/// Smooth, 1 at the center, 0 with zero slope at the rim. The implicit surface blends with it;
/// the builder's support fit weighs points with it.
inline double blend_weight(double s) noexcept {
  const double t = 1 - s;
  return t * t * t;
}

/// One node of the tree. Nodes are stored in depth-first pre-order, root first; a node's
/// children come after it. `left`/`right` are -1 for leaves (both or neither are set).
struct ClusterNode {
  std::int32_t parent = -1;
  std::int32_t left = -1;
  std::int32_t right = -1;
  std::uint32_t depth = 0;
  std::uint32_t point_count = 0;
  Proxy proxy;
  /// RMS and max of |Q| over the cluster (a leaf's: but the few stray points its support fit
  /// trimmed as outliers of the local surface)
  double rms_error = 0;
  double max_error = 0;
  double extent = 0;  ///< diagonal of the cluster's bounding box
  Sphere support;     ///< center = cluster mean, radius ≥ alpha × extent (grown to cover
                      ///< enough input points, shrunk where the proxy fails over it)
  Sphere bound;       ///< encloses `support` and every support in the subtree

  bool is_leaf() const noexcept { return left < 0; }
};

/// The options a tree was built with, as stored in its file (BuildOptions' stored part).
struct TreeParameters {
  ProxyKind proxy = ProxyKind::Poly;
  SplitterKind splitter = SplitterKind::SplitPlane;
  ErrorMetric metric = ErrorMetric::Rms;
  ThresholdMode threshold_mode = ThresholdMode::Auto;
  double tolerance = 0.00005;
  double noise_factor = 1.0;
  std::uint32_t min_points = 20;  ///< the value used (leaf_min_points() where the options said 0)
  std::uint32_t max_depth = 200;
  double alpha = 0.75;  ///< the value used (support_alpha() where the options said 0)
  std::uint32_t kstep = 0;
  std::uint32_t lloyd_restarts = 4;
  std::uint32_t proxy_lloyd_iterations = 0;
  double support_factor = 1.0;
  std::uint64_t seed = 1;
  bool creases = false;  ///< built with BuildOptions::creases (off in version-1 files)

  bool operator==(const TreeParameters&) const = default;
};

/// A built (or loaded) cluster tree.
struct ClusterTree {
  TreeParameters parameters;
  double noise_sigma = 0;      ///< estimated noise of the input (Auto mode; 0 otherwise)
  double error_threshold = 0;  ///< a leaf's error threshold, hypot(tolerance, counted noise), in input units
  /// Median distance from an input point to its nearest other point (compute_stats()'s); 0 when
  /// unknown (trees from version-1 files).
  double point_spacing = 0;
  BoundingBox bbox;  ///< of the clustered points (the input without outliers)
  /// The input's origin (PointCloud::origin): nodes, bbox and meshes are relative to it, and
  /// meshes of the tree are written back at it.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  /// The input's up axis (PointCloud::up): what pictures and the viewer of the tree take as up,
  /// and what its meshes carry.
  UpAxis up = UpAxis::Y;
  std::uint64_t input_points = 0;  ///< all input points; the root holds those not outliers
  std::vector<ClusterNode> nodes;  ///< pre-order, nodes[0] is the root
  /// Node index of each input point's leaf (-1 for an outlier), or empty.
  std::vector<std::int32_t> point_leaf;

  /// Indices of the leaves, in pre-order.
  std::vector<std::int32_t> leaves() const;
  /// Largest node depth (root: 0).
  std::uint32_t depth() const;
  /// Input points left out of every cluster: outliers, and points at the very position of an
  /// earlier point (build_cluster_tree() clusters one point per position).
  std::uint64_t outliers() const { return nodes.empty() ? 0 : input_points - nodes[0].point_count; }
};

/// The error a cluster of `points` points may keep in `tree`: hypot(tolerance, noise), the
/// noise allowed a margin for the spread of an RMS over that many points (σ² (1 + 2 √(2/n))), so
/// that noise alone does not split a cluster. Equals tree.error_threshold without noise. The
/// noise is the cloud's estimate times `noise_scale`: a cluster where the noise field reads more
/// (NoiseOptions::local) keeps up to kMaxLocalNoise times it.
double cluster_error_threshold(const ClusterTree& tree, double points, double noise_scale = 1);

/// The smallest cluster a leaf may have when BuildOptions::min_points is 0, from the noise σ
/// against the point spacing h (both in the input's units): enough points that the noise a
/// bivariate quadratic's six coefficients pick up from them, σ √(6/n), stays within a quarter
/// of the spacing (n ≥ 6 (4σ/h)²), between 12 and 20. Where the noise is well under the
/// spacing (clean or sparse data), leaves of 12 points follow thin parts and fine relief that
/// leaves of 15–20 wrap around, their supports' 30 points still average the noise, and a stray
/// point just off the surface still leaves most of a leaf's points to fit; noise of half a
/// spacing or more takes 20 (its support fit averages over more). Noise 0 gives 12, a spacing
/// of 0 gives 20.
std::uint32_t leaf_min_points(double noise, double spacing);

/// The support radius over the cluster extent when BuildOptions::alpha is 0, from the noise σ
/// against the point spacing h: 0.75 (the thesis's) up to σ = 0.15 h, rising linearly to 1 at
/// σ = h / 2 and staying there. Where the noise is a sizable share of the spacing (noisy scans,
/// layers of misregistered scans), the blend averages it over wider overlaps; clean and sparse
/// data (σ about h / 10) keep the narrower supports that hold fine relief. A spacing of 0 gives
/// 0.75.
double support_alpha(double noise, double spacing);

/// Builds the tree of the cloud's points but its outliers (BuildOptions::remove_outliers) and
/// but the points at the very position of an earlier one (first_of_each_position(): a cloud
/// whose points each repeat gives the tree of its distinct points). Deterministic: the same
/// cloud and options give the same tree for any thread count. Throws OptionError for invalid
/// options, Cancelled when `progress` says stop.
ClusterTree build_cluster_tree(const PointCloud& cloud, const BuildOptions& options = {},
                               const ProgressCallback& progress = {});
/// The same with the cloud's index shared with the later stages (CloudIndex: its k-d tree,
/// spacing and clustered rows are computed here once).
ClusterTree build_cluster_tree(const CloudIndex& cloud, const BuildOptions& options = {},
                               const ProgressCallback& progress = {});

/// Throws OptionError unless `input` can be the tree's input: as many rows as the tree's input
/// points. `what` names the points in the message.
void require_tree_input(const ClusterTree& tree, const Points& input, std::string_view what = "the points");

/// The indices of the input rows the tree clusters, increasing: all but its outliers (every
/// row when it left none out or holds no point-leaf table).
std::vector<std::uint32_t> clustered_rows(const ClusterTree& tree);

/// The rows of `input` (the tree's input points) that the tree clusters (clustered_rows()).
/// Throws OptionError when `input` is not the tree's input (require_tree_input()).
Points clustered_points(const ClusterTree& tree, const Points& input);

/// The rows of `cloud` that `tree` clusters (clustered_rows()) and their k-d tree, through the
/// index's one subset (CloudIndex::rows()). Throws OptionError unless the indexed cloud is the
/// tree's input (require_tree_input()).
CloudIndex::Subset clustered_subset(const CloudIndex& cloud, const ClusterTree& tree);

/// Figures of a tree for reports (`clustersurf info`).
struct TreeSummary {
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  std::uint32_t depth = 0;
  std::array<std::size_t, kProxyKinds> proxy_histogram{};  ///< leaves per ProxyKind
  std::array<double, 5> leaf_size_percentiles{};           ///< 0, 25, 50, 75, 100 %
  std::array<double, 5> leaf_rms_percentiles{};            ///< 0, 25, 50, 75, 100 %
  std::size_t leaves_over_threshold = 0;  ///< leaves whose error exceeds cluster_error_threshold() at the estimate
};

TreeSummary summarize(const ClusterTree& tree);

/// The report of a tree as a JSON object, the one both front ends give (`clustersurf --json
/// info`, Python's Tree.info()): nodes, leaves, depth, input_points, outliers, has_point_leaves,
/// bbox_min, bbox_max, diagonal, leaf_proxies (leaves per proxy kind), leaf_size and
/// leaf_rms_error (min, p25, median, p75, max), leaves_over_threshold, noise_sigma,
/// error_threshold, point_spacing and the build's parameters; numbers that read back exactly.
std::string tree_info_json(const ClusterTree& tree);

}  // namespace clustersurf
