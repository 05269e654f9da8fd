// One index of a cloud for every stage of the pipeline.

#include <clustersurf/spatial/cloud_index.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>

#include <algorithm>
#include <mutex>
#include <optional>
#include <vector>

namespace clustersurf {

struct CloudIndex::Impl {
  const PointCloud& cloud;
  std::once_flag points_once, spacing_once;
  std::optional<KdTree> points;
  double spacing = 0;
  std::mutex subset_mutex;  // guards the last subset
  std::vector<std::uint32_t> subset_rows;
  std::unique_ptr<Points> subset_positions;
  std::unique_ptr<KdTree> subset_index;
};

CloudIndex::CloudIndex(const PointCloud& cloud) : impl_(new Impl{cloud, {}, {}, {}, 0, {}, {}, {}, {}}) {}
CloudIndex::~CloudIndex() = default;

const PointCloud& CloudIndex::cloud() const noexcept { return impl_->cloud; }

const KdTree& CloudIndex::points() const {
  std::call_once(impl_->points_once, [this] { impl_->points.emplace(impl_->cloud.positions); });
  return *impl_->points;
}

double CloudIndex::median_spacing() const {
  std::call_once(impl_->spacing_once, [this] { impl_->spacing = point_spacing(points()).median; });
  return impl_->spacing;
}

OutlierReport CloudIndex::outliers(const OutlierOptions& options) const {
  OutlierReport report = find_outliers(impl_->cloud.positions, points(), options);
  if (!report.nearest.empty())
    std::call_once(impl_->spacing_once, [&] { impl_->spacing = point_spacing(report.nearest).median; });
  return report;
}

CloudIndex::Subset CloudIndex::rows(std::span<const std::uint32_t> kept) const {
  if (kept.size() == static_cast<std::size_t>(impl_->cloud.size())) return {impl_->cloud.positions, points()};
  const std::lock_guard lock(impl_->subset_mutex);
  if (!impl_->subset_index ||
      !std::equal(kept.begin(), kept.end(), impl_->subset_rows.begin(), impl_->subset_rows.end())) {
    impl_->subset_index.reset();  // it references the positions it replaces
    impl_->subset_rows.assign(kept.begin(), kept.end());
    impl_->subset_positions = std::make_unique<Points>(impl_->cloud.positions(impl_->subset_rows, Eigen::all));
    impl_->subset_index = std::make_unique<KdTree>(*impl_->subset_positions);
  }
  return {*impl_->subset_positions, *impl_->subset_index};
}

}  // namespace clustersurf
