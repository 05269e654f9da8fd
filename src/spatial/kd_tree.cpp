#include <clustersurf/spatial/kd_tree.hpp>

#include "spatial/spatial_order.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace clustersurf {

namespace {

/// nanoflann dataset adaptor over the rows of a Points matrix.
struct PointsAdaptor {
  const Points* points;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(points->rows()); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return (*points)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(dim));
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>, PointsAdaptor, 3,
                                                  std::uint32_t>;

bool closer(const Neighbor& a, const Neighbor& b) {
  return a.distance_squared < b.distance_squared || (a.distance_squared == b.distance_squared && a.index < b.index);
}

/// The rows of `points` in Morton order, or as they are when a coordinate is not finite.
std::vector<std::uint32_t> layout_order(const Points& points) {
  if (points.allFinite()) return detail::spatial_order(points);
  std::vector<std::uint32_t> rows(static_cast<std::size_t>(points.rows()));
  std::iota(rows.begin(), rows.end(), 0u);
  return rows;
}

/// The rows `rows` of `points`, in that order.
Points gathered(const Points& points, const std::vector<std::uint32_t>& rows) {
  Points out(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = points.row(rows[i]);
  return out;
}

}  // namespace

struct KdTree::Impl {
  const Points* caller;
  std::vector<std::uint32_t> rows;  ///< rows[i]: the caller's row of local point i
  Points local;                     ///< the caller's points in Morton order: a query reads nearby memory
  PointsAdaptor adaptor;
  Index index;
  Impl(const Points& points, int leaf_size)
      : caller(&points),
        rows(layout_order(points)),
        local(gathered(points, rows)),
        adaptor{&local},
        index(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(static_cast<std::size_t>(std::max(1, leaf_size)))) {
  }

  /// The neighbour found at local point `i`, by the caller's row.
  Neighbor found(std::uint32_t i, double d2) const { return Neighbor{rows[i], d2}; }

  /// Every point with squared distance <= r2 (inclusive), sorted by distance then index.
  void within(const Eigen::Vector3d& query, double r2, std::vector<Neighbor>& out) const {
    // nanoflann's L2 adaptors compare squared distances; its test is "< radius", so widen by
    // one ulp to make the query inclusive, then filter exactly.
    thread_local std::vector<std::pair<std::uint32_t, double>> found;
    found.clear();
    index.radiusSearch(query.data(), std::nextafter(r2, std::numeric_limits<double>::infinity()), found,
                       nanoflann::SearchParams(32, 0, false));
    out.clear();
    out.reserve(found.size());
    for (const auto& [i, d2] : found)
      if (d2 <= r2) out.push_back(this->found(i, d2));
    std::sort(out.begin(), out.end(), closer);
  }
};

KdTree::KdTree(const Points& points, int leaf_size) : impl_(std::make_unique<Impl>(points, leaf_size)) {}
KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

std::size_t KdTree::size() const noexcept { return impl_->rows.size(); }
const Points& KdTree::points() const noexcept { return *impl_->caller; }

void KdTree::knn(const Eigen::Vector3d& query, std::size_t k, std::vector<Neighbor>& out) const {
  k = std::min(k, size());
  out.clear();
  if (k == 0) return;
  // Ask for one extra candidate so ties at the k-th distance resolve by index deterministically.
  const std::size_t want = std::min(k + 1, size());
  thread_local std::vector<std::uint32_t> idx;
  thread_local std::vector<double> d2;
  idx.resize(want);
  d2.resize(want);
  nanoflann::KNNResultSet<double, std::uint32_t> result(want);
  result.init(idx.data(), d2.data());
  impl_->index.findNeighbors(result, query.data(), nanoflann::SearchParams());
  const std::size_t found = result.size();
  out.reserve(found);
  for (std::size_t i = 0; i < found; ++i) out.push_back(impl_->found(idx[i], d2[i]));
  std::sort(out.begin(), out.end(), closer);
  // nanoflann keeps the first points it meets at the worst distance, so when the (k+1)-th
  // candidate ties with the k-th, other points at that distance may have been left out and the
  // lowest indices among them may be missing: gather all of them.
  if (out.size() > k && out[k].distance_squared == out[k - 1].distance_squared)
    impl_->within(query, out[k - 1].distance_squared, out);
  out.resize(std::min(k, out.size()));
}

void KdTree::neighbors_of(Eigen::Index row, std::size_t k, std::vector<Neighbor>& out) const {
  knn(points().row(row).transpose(), k + 1, out);
  const auto self = std::find_if(out.begin(), out.end(),
                                 [&](const Neighbor& n) { return n.index == static_cast<std::uint32_t>(row); });
  if (self != out.end())
    out.erase(self);
  else if (out.size() > k)
    out.pop_back();  // the point is among more than k duplicates of itself
}

std::vector<Neighbor> KdTree::knn(const Eigen::Vector3d& query, std::size_t k) const {
  std::vector<Neighbor> out;
  knn(query, k, out);
  return out;
}

void KdTree::radius_unsorted(const Eigen::Vector3d& query, double radius, std::vector<Neighbor>& out) const {
  out.clear();
  if (!(radius >= 0)) return;
  thread_local std::vector<std::pair<std::uint32_t, double>> found;
  found.clear();
  const double r2 = radius * radius;
  impl_->index.radiusSearch(query.data(), std::nextafter(r2, std::numeric_limits<double>::infinity()), found,
                            nanoflann::SearchParams(32, 0, false));
  for (const auto& [i, d2] : found)
    if (d2 <= r2) out.push_back(impl_->found(i, d2));
}

std::vector<Neighbor> KdTree::radius(const Eigen::Vector3d& query, double radius) const {
  std::vector<Neighbor> out;
  if (radius >= 0 && size() > 0) impl_->within(query, radius * radius, out);
  return out;
}

}  // namespace clustersurf
