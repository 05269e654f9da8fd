// The k-d partition of a cloud into regions balanced by point count.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/regions/regions.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace clustersurf {

namespace {

/// Squared distance from x to the box (0 inside).
double distance_squared(const BoundingBox& box, const Eigen::Vector3d& x) {
  const Eigen::Vector3d below = (box.min - x).cwiseMax(0.0), above = (x - box.max).cwiseMax(0.0);
  return (below + above).squaredNorm();
}

struct Planner {
  const Points& sample;
  double points_per_sample;
  std::uint64_t max_points;
  RegionPlan& plan;

  /// Sample points within the halo of `box` but outside it.
  std::size_t halo_count(const BoundingBox& box) const {
    const double h2 = plan.halo * plan.halo;
    std::size_t n = 0;
    for (Eigen::Index i = 0; i < sample.rows(); ++i) {
      const double d = distance_squared(box, sample.row(i).transpose());
      n += d > 0 && d <= h2;
    }
    return n;
  }

  std::int32_t split(std::span<std::uint32_t> rows, const BoundingBox& box) {
    const auto index = static_cast<std::int32_t>(plan.cells.size());
    plan.cells.push_back({});
    plan.cells.back().box = box;
    // A region holds its points and its halo's; splitting stops once that fits, or once the
    // region's own points are a quarter of the limit (the halo of a smaller one would outweigh it).
    const double own = static_cast<double>(rows.size()) * points_per_sample;
    const double limit = static_cast<double>(max_points);
    const bool fits = own <= limit &&
                      (own <= 0.25 * limit || own + static_cast<double>(halo_count(box)) * points_per_sample <= limit);
    if (fits || rows.size() < 2) {
      plan.cells[static_cast<std::size_t>(index)].region = static_cast<std::int32_t>(plan.region_cell.size());
      plan.region_cell.push_back(index);
      return index;
    }
    Eigen::Index axis = 0;
    box.extent().maxCoeff(&axis);
    const auto half = static_cast<std::ptrdiff_t>(rows.size() / 2);
    std::nth_element(rows.begin(), rows.begin() + half, rows.end(), [&](std::uint32_t a, std::uint32_t b) {
      const double pa = sample(a, axis), pb = sample(b, axis);
      return pa < pb || (pa == pb && a < b);
    });
    const double at = sample(rows[static_cast<std::size_t>(half)], axis);
    // The left part holds the sample below the median coordinate; ties go right together.
    const auto mid = std::partition(rows.begin(), rows.end(), [&](std::uint32_t r) { return sample(r, axis) < at; });
    const auto k = static_cast<std::size_t>(mid - rows.begin());
    if (k == 0 || !(at > box.min(axis)) || !(at < box.max(axis))) {  // all on one coordinate: no split
      plan.cells[static_cast<std::size_t>(index)].region = static_cast<std::int32_t>(plan.region_cell.size());
      plan.region_cell.push_back(index);
      return index;
    }
    BoundingBox lower = box, upper = box;
    lower.max(axis) = at;
    upper.min(axis) = at;
    plan.cells[static_cast<std::size_t>(index)].axis = static_cast<std::int32_t>(axis);
    plan.cells[static_cast<std::size_t>(index)].split = at;
    const std::int32_t left = split(rows.subspan(0, k), lower);
    const std::int32_t right = split(rows.subspan(k), upper);
    plan.cells[static_cast<std::size_t>(index)].left = left;
    plan.cells[static_cast<std::size_t>(index)].right = right;
    return index;
  }
};

}  // namespace

std::int32_t RegionPlan::region_of(const Eigen::Vector3d& x) const {
  std::size_t c = 0;
  while (cells[c].left >= 0)
    c = static_cast<std::size_t>(x(cells[c].axis) < cells[c].split ? cells[c].left : cells[c].right);
  return cells[c].region;
}

void RegionPlan::halo_regions(const Eigen::Vector3d& x, std::vector<std::int32_t>& out) const {
  out.clear();
  const std::int32_t own = region_of(x);
  const double h2 = halo * halo;
  std::int32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Cell& cell = cells[static_cast<std::size_t>(stack[--top])];
    if (distance_squared(cell.box, x) > h2) continue;
    if (cell.left < 0) {
      if (cell.region != own) out.push_back(cell.region);
      continue;
    }
    if (top + 2 > 128) continue;  // depth beyond any plan of 2^64 regions
    stack[top++] = cell.right;
    stack[top++] = cell.left;
  }
  std::sort(out.begin(), out.end());
}

RegionPlan plan_regions(const Points& sample, std::uint64_t total_points, const BoundingBox& bbox, double point_spacing,
                        const RegionOptions& options) {
  if (options.max_points < 1) throw OptionError("a region must hold at least one point");
  if (!(options.halo_spacings >= 0) || !std::isfinite(options.halo_spacings))
    throw OptionError("the region halo must be a finite number of point spacings >= 0");
  if (!(point_spacing >= 0) || !std::isfinite(point_spacing))
    throw OptionError("the point spacing must be finite and >= 0");
  if (bbox.empty()) throw OptionError("cannot plan regions of an empty cloud");
  RegionPlan plan;
  plan.point_spacing = point_spacing;
  plan.halo = options.halo_spacings * point_spacing;
  plan.points = total_points;
  std::vector<std::uint32_t> rows(static_cast<std::size_t>(sample.rows()));
  std::iota(rows.begin(), rows.end(), 0u);
  const double per_sample = rows.empty() ? 0.0 : static_cast<double>(total_points) / static_cast<double>(rows.size());
  Planner{sample, per_sample, options.max_points, plan}.split(rows, bbox);
  return plan;
}

}  // namespace clustersurf
