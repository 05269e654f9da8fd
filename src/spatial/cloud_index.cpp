// One index of a cloud for every stage of the pipeline.

#include <clustersurf/spatial/cloud_index.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>

#include <algorithm>
#include <mutex>
#include <optional>
#include <span>
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
  // The last outliers() call's kept rows and their spreads among themselves.
  std::vector<std::uint32_t> spread_rows;
  std::vector<double> spread;
  std::size_t spread_neighbors = 0;

  /// The spreads of `rows` when they are the last outlier test's kept rows, else empty.
  std::span<const double> spread_of(std::span<const std::uint32_t> rows) const {
    if (spread.empty() || !std::equal(rows.begin(), rows.end(), spread_rows.begin(), spread_rows.end())) return {};
    return spread;
  }
};

CloudIndex::CloudIndex(const PointCloud& cloud) : impl_(new Impl{cloud, {}, {}, {}, 0, {}, {}, {}, {}, {}, {}, 0}) {}
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
  const std::lock_guard lock(impl_->subset_mutex);
  impl_->spread_rows.assign(report.kept.begin(), report.kept.end());
  impl_->spread = report.kept_spread;
  impl_->spread_neighbors = options.neighbors;
  if (impl_->spread.size() != impl_->spread_rows.size()) impl_->spread.clear();
  return report;
}

CloudIndex::Subset CloudIndex::rows(std::span<const std::uint32_t> kept) const {
  const KdTree& all = points();
  const std::lock_guard lock(impl_->subset_mutex);
  const std::span<const double> spread = impl_->spread_of(kept);
  if (kept.size() == static_cast<std::size_t>(impl_->cloud.size()))
    return {impl_->cloud.positions, all, spread, impl_->spread_neighbors};
  if (!impl_->subset_index ||
      !std::equal(kept.begin(), kept.end(), impl_->subset_rows.begin(), impl_->subset_rows.end())) {
    impl_->subset_index.reset();  // it references the positions it replaces
    impl_->subset_rows.assign(kept.begin(), kept.end());
    impl_->subset_positions = std::make_unique<Points>(impl_->cloud.positions(impl_->subset_rows, Eigen::all));
    impl_->subset_index = std::make_unique<KdTree>(*impl_->subset_positions);
  }
  return {*impl_->subset_positions, *impl_->subset_index, spread, impl_->spread_neighbors};
}

}  // namespace clustersurf
