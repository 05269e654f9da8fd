// Vertices at the same position, as one.
// Points at the same position, as one (a mesh's vertices, a cloud's repeated points).
#include "spatial/position_ids.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <cmath>
#include <numeric>

namespace clustersurf::detail {

std::vector<std::int32_t> position_ids(const Points& v) {
  const auto n = static_cast<std::int32_t>(v.rows());
  std::vector<std::int32_t> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  const auto before = [](double x, double y) {  // a strict weak order even with NaN (last)
    return std::isnan(y) ? !std::isnan(x) : x < y;
  };
  const auto less = [&v, &before](std::int32_t a, std::int32_t b) {
    for (int k = 0; k < 3; ++k) {
      if (before(v(a, k), v(b, k))) return true;
      if (before(v(b, k), v(a, k))) return false;
    }
    return a < b;
  };
  tbb::parallel_sort(order.begin(), order.end(), less);
  // Each vertex takes the id of the first of its run of equal positions in that order.
  std::vector<std::int32_t> id(order.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 4096), [&](const auto& r) {
    for (std::size_t k = r.begin(); k != r.end(); ++k) {
      std::size_t first = k;
      while (first > 0 && v.row(order[first]) == v.row(order[first - 1])) --first;
      id[static_cast<std::size_t>(order[k])] = order[first];
    }
  });
  return id;
}

}  // namespace clustersurf::detail
