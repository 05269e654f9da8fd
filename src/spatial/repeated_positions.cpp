// One point kept per position where points repeat each other exactly.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/spatial/repeated_positions.hpp>

#include "spatial/position_ids.hpp"

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
  Points at(static_cast<Eigen::Index>(candidates.size()), 3);
  for (std::size_t c = 0; c < candidates.size(); ++c)
    at.row(static_cast<Eigen::Index>(c)) = positions.row(rows[candidates[c]]);
  // A candidate repeats a position when an earlier one holds it: its id is not its own.
  const std::vector<std::int32_t> first = detail::position_ids(at);
  std::vector<std::uint8_t> repeat(rows.size(), 0);
  bool any = false;
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (first[c] != static_cast<std::int32_t>(c)) repeat[candidates[c]] = 1, any = true;
  if (!any) return rows;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (!repeat[k]) rows[kept++] = rows[k];
  rows.resize(kept);
  return rows;
}

}  // namespace clustersurf
