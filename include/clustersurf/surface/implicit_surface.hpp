#pragma once
// The partition-of-unity implicit function of a cluster tree:
// f(x) = Σ wᵢ(x) Qᵢ(x) / Σ wᵢ(x) over the nodes of a cut of the tree (the leaves by default),
// with wᵢ = (1 − ‖x − cᵢ‖² / rᵢ²)³ inside node i's support sphere and 0 outside. A blend may
// grow every radius by a margin (rᵢ = support radius + margin): the mesher does, only where f
// is otherwise undefined, to close gaps narrower than its grid cells.

#include <clustersurf/cluster/cluster_tree.hpp>

#include <optional>
#include <utility>
#include <vector>

namespace clustersurf {

/// Where the blend counts as defined: its total weight Σwᵢ must exceed this. Near the outer
/// rim of the supports a lone proxy extrapolates away from its data (w = 0.02 is 85 % of a
/// radius from a lone center). The mesher, the renderer and the Python module default to it,
/// so a picture shows the surface the mesh has.
inline constexpr double kMinWeight = 0.02;

/// Which nodes are blended: the leaves (default), or a coarser cut of the tree.
struct LevelOfDetail {
  /// Cut at this depth: nodes of that depth, plus shallower leaves.
  std::optional<std::uint32_t> max_depth;
  /// Cut where the node error first drops to this value (the tree's error metric, in the
  /// input's units): the shallowest nodes with error ≤ error_limit, or leaves.
  std::optional<double> error_limit;
};

/// The nodes of `tree` forming the cut `lod` (pre-order; every input point is covered once).
std::vector<std::int32_t> lod_cut(const ClusterTree& tree, const LevelOfDetail& lod);

/// The cut as the front ends give it: a depth, and/or an error limit as a fraction of the
/// tree's bounding-box diagonal (≥ 0). Throws OptionError for a negative or non-finite fraction.
LevelOfDetail level_of_detail(const ClusterTree& tree, std::optional<std::uint32_t> depth,
                              std::optional<double> error_fraction);

/// f, its gradient and the total weight at a point. `defined` is false where no support sphere
/// of the cut reaches (total weight 0): f is undefined there, not invented.
struct SurfaceSample {
  double value = 0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  double weight = 0;
  bool defined = false;
};

/// The implicit surface of a tree. Holds a reference to the tree, which must outlive it and
/// stay unchanged. Evaluation descends the tree's bounding spheres: cost ~ depth + number of
/// supports containing the point. All methods are const and thread-safe.
class ImplicitSurface {
 public:
  explicit ImplicitSurface(const ClusterTree& tree, const LevelOfDetail& lod = {});

  /// The same cut blended with every support radius grown by `margin` (≥ 0): f is then
  /// defined up to `margin` beyond every support, and the proxies extrapolate that far.
  ImplicitSurface with_margin(double margin) const;
  /// The radius margin (0 unless set by with_margin()).
  double margin() const noexcept { return margin_; }
  /// The blending radius of node i: its support radius + margin().
  double radius(std::int32_t i) const noexcept { return supports_[static_cast<std::size_t>(i)].radius; }

  /// The walk of a whole box done once (box_walk.hpp).
  class BoxWalk;

  /// f and ∇f at x (exact analytic gradient of the blend).
  SurfaceSample sample(const Eigen::Vector3d& x) const;
  /// sample() with the supports found through `near`: the same sample (OptionError when `near`
  /// was built for another surface).
  SurfaceSample sample(const Eigen::Vector3d& x, const BoxWalk& near) const;
  /// f at x, or nullopt where undefined: where the total weight is 0, or not above
  /// `min_weight` (a confidence floor, kMinWeight for the mesher and the renderer).
  std::optional<double> value(const Eigen::Vector3d& x, double min_weight = 0) const;
  /// value() with the supports found through `near`: the same value (OptionError when `near`
  /// was built for another surface).
  std::optional<double> value(const Eigen::Vector3d& x, double min_weight, const BoxWalk& near) const;
  /// Σ wᵢ Qᵢ(x) and Σ wᵢ over the supports containing x: value() is their ratio.
  std::pair<double, double> weighted_sum(const Eigen::Vector3d& x) const;
  /// Samples every row of `points` in parallel; results in row order.
  std::vector<SurfaceSample> sample_all(const Points& points) const;
  /// Calls visit(node index, s = ‖x − c‖² / radius²) for every cut node whose support (grown
  /// by the margin) contains x.
  template <class Visit>
  void for_each_support(const Eigen::Vector3d& x, Visit&& visit) const;
  /// The one walk down the bounding spheres, for any query (a point, a ray, a cone): descends
  /// only into nodes whose bounding sphere grown by the margin, passed as a Sphere, satisfies
  /// `meets`, and calls visit(node index) for each cut node reached, in pre-order (the test of
  /// its own support is the caller's).
  template <class Meets, class Visit>
  void walk(Meets&& meets, Visit&& visit) const;

  /// Node i's bounding sphere (enclosing its support and every support below it) grown by the
  /// margin: the sphere the walk tests.
  const Sphere& bound(std::int32_t i) const noexcept { return walk_nodes_[static_cast<std::size_t>(i)].bound; }

  const ClusterTree& tree() const noexcept { return *tree_; }
  /// The nodes blended (pre-order).
  const std::vector<std::int32_t>& cut() const noexcept { return cut_; }
  /// Whether node i is blended.
  bool in_cut(std::int32_t i) const noexcept { return walk_nodes_[static_cast<std::size_t>(i)].in_cut != 0; }

 private:
  /// What walk() reads of a node, packed in 48 bytes: a ClusterNode spans 264, and the walk
  /// touched two of its cache lines per node.
  struct WalkNode {
    Sphere bound;  ///< the node's bounding sphere grown by the margin
    std::int32_t left = -1, right = -1;
    std::uint8_t in_cut = 0;
  };
  /// Sets the radii of walk_nodes_ and supports_ for margin_.
  void grow_by_margin();
  /// Calls visit(i, s) when x lies inside node i's support (grown by the margin).
  template <class Visit>
  void visit_support(std::int32_t i, const Eigen::Vector3d& x, Visit&& visit) const {
    const Sphere& support = supports_[static_cast<std::size_t>(i)];
    const double s = (x - support.center).squaredNorm() / (support.radius * support.radius);
    if (s < 1) visit(i, s);
  }

  const ClusterTree* tree_;
  std::vector<std::int32_t> cut_;
  std::vector<WalkNode> walk_nodes_;  // per node
  std::vector<Sphere> supports_;      // per node: its support grown by the margin
  double margin_ = 0;
};

template <class Meets, class Visit>
void ImplicitSurface::walk(Meets&& meets, Visit&& visit) const {
  if (walk_nodes_.empty()) return;
  std::int32_t stack[256];
  int top = 0;
  stack[top++] = 0;
  std::vector<std::int32_t> overflow;
  while (top > 0 || !overflow.empty()) {
    std::int32_t i;
    if (!overflow.empty()) {
      i = overflow.back();
      overflow.pop_back();
    } else {
      i = stack[--top];
    }
    const WalkNode& n = walk_nodes_[static_cast<std::size_t>(i)];
    if (!meets(n.bound)) continue;
    if (n.in_cut) {
      visit(i);
      continue;
    }
    if (n.left < 0) continue;
    for (std::int32_t c : {n.right, n.left}) {
      if (top < 256)
        stack[top++] = c;
      else
        overflow.push_back(c);
    }
  }
}

template <class Visit>
void ImplicitSurface::for_each_support(const Eigen::Vector3d& x, Visit&& visit) const {
  walk([&x](const Sphere& bound) { return bound.contains(x); }, [&](std::int32_t i) { visit_support(i, x, visit); });
}

}  // namespace clustersurf
