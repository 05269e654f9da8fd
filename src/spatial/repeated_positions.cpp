// One point kept per position where points repeat each other exactly.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/repeated_positions.hpp>

#include <tbb/parallel_sort.h>

#include <string>

namespace clustersurf {

std::vector<std::uint32_t> first_of_each_position(const Points& positions, std::vector<std::uint32_t> rows,
                                                  std::span<const std::uint8_t> coincident) {
  if (!coincident.empty() && coincident.size() != static_cast<std::size_t>(positions.rows()))
    throw OptionError("repeated positions: " + std::to_string(coincident.size()) + " flags for " +
                      std::to_string(positions.rows()) + " points");
  // The places in `rows` of the rows that may repeat a position.
  std::vector<std::uint32_t> candidates;
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (coincident.empty() || coincident[rows[k]] != 0) candidates.push_back(static_cast<std::uint32_t>(k));
  if (candidates.size() < 2) return rows;
  const auto at = [&](std::uint32_t k) { return positions.row(rows[k]); };
  // By position, then by place in `rows`: a repeat follows the first row at its position.
  tbb::parallel_sort(candidates.begin(), candidates.end(), [&](std::uint32_t a, std::uint32_t b) {
    const auto p = at(a), q = at(b);
    for (int c = 0; c < 3; ++c)
      if (p(c) != q(c)) return p(c) < q(c);
    return a < b;
  });
  std::vector<std::uint8_t> repeat(rows.size(), 0);
  bool any = false;
  for (std::size_t i = 1; i < candidates.size(); ++i)
    if (at(candidates[i]) == at(candidates[i - 1])) repeat[candidates[i]] = 1, any = true;
  if (!any) return rows;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (!repeat[k]) rows[kept++] = rows[k];
  rows.resize(kept);
  return rows;
}

}  // namespace clustersurf
