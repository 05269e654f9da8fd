#include "cluster/support_sampler.hpp"
#include "core/splitmix.hpp"

#include <tbb/parallel_for.h>

namespace clustersurf::detail {

namespace {

/// Levels stop when they would hold fewer points than this.
constexpr std::size_t kMinLevelSize = 4096;

}  // namespace

SupportSampler::SupportSampler(const Points& points, const KdTree& full) : full_(full) {
  const auto n = static_cast<std::size_t>(points.rows());
  for (std::size_t level = 1, kept = n / 4; kept >= kMinLevelSize && level < 31; ++level, kept /= 4) {
    Level l;
    for (std::size_t i = 0; i < n; ++i)
      if (in_subsample(i, static_cast<unsigned>(level))) l.ids.push_back(static_cast<std::uint32_t>(i));
    l.points.resize(static_cast<Eigen::Index>(l.ids.size()), 3);
    for (std::size_t k = 0; k < l.ids.size(); ++k) l.points.row(static_cast<Eigen::Index>(k)) = points.row(l.ids[k]);
    levels_.push_back(std::move(l));
  }
  tbb::parallel_for(std::size_t{0}, levels_.size(),
                    [&](std::size_t k) { levels_[k].index = std::make_unique<KdTree>(levels_[k].points); });
}

void SupportSampler::inside(const Eigen::Vector3d& center, double radius, std::size_t expected, std::size_t wanted,
                            std::vector<Neighbor>& out) const {
  std::size_t level = 0;
  while (level < levels_.size() && (expected >> (2 * (level + 1))) >= wanted) ++level;
  if (level == 0) {
    full_.radius_unsorted(center, radius, out);
    return;
  }
  const Level& l = levels_[level - 1];
  l.index->radius_unsorted(center, radius, out);
  for (auto& nb : out) nb.index = l.ids[nb.index];
}

}  // namespace clustersurf::detail
