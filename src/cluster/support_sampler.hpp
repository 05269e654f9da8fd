#pragma once
// Sampling the input points inside a support sphere at a bounded cost, for the support check.

#include <clustersurf/spatial/kd_tree.hpp>

#include <vector>

namespace clustersurf::detail {

/// Nested random subsets of the input — level l keeps the points whose index hashes to a
/// multiple of 4^l, so each level holds about a quarter of the previous one and contains all
/// the coarser ones — each with its own k-d tree. Querying the coarsest level that still puts
/// enough points in a sphere costs in proportion to the sample, not to every point inside.
class SupportSampler {
 public:
  /// Level 0 is `full`, a k-d tree of `points`; both must outlive the sampler.
  SupportSampler(const Points& points, const KdTree& full);

  /// Points (input indices, squared distances) inside the sphere (center, radius), from the
  /// coarsest level expected to hold at least `wanted` of them when the sphere holds about
  /// `expected` input points. Deterministic; thread-safe.
  void inside(const Eigen::Vector3d& center, double radius, std::size_t expected, std::size_t wanted,
              std::vector<Neighbor>& out) const;
  /// The k-d tree of every point (level 0).
  const KdTree& full() const noexcept { return full_; }

 private:
  struct Level {
    Points points;
    std::vector<std::uint32_t> ids;  // input index of each row
    std::unique_ptr<KdTree> index;
  };
  const KdTree& full_;
  std::vector<Level> levels_;  // levels 1, 2, ...
};

}  // namespace clustersurf::detail
