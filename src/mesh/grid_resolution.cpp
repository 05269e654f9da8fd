// The mesh grid matched to the sampling density of the input points.

#include <clustersurf/cloud_stats.hpp>
#include <clustersurf/errors.hpp>
#include <clustersurf/mesh_extraction.hpp>

#include <charconv>
#include <cmath>
#include <string>

namespace clustersurf {

double cell_size_for_spacing(double median_spacing, double spacing_factor) {
  if (!(spacing_factor > 0) || !std::isfinite(spacing_factor)) throw OptionError("the grid's spacing factor must be positive");
  if (!(median_spacing > 0) || !std::isfinite(median_spacing))
    throw OptionError("cannot match the mesh grid to the points: most of them coincide (median spacing 0)");
  return spacing_factor * median_spacing;
}

double cell_size_for_points(const PointCloud& cloud, double spacing_factor) {
  return cell_size_for_spacing(compute_stats(cloud).median_spacing, spacing_factor);
}

std::optional<std::uint32_t> parse_resolution(std::string_view text) {
  if (text == "auto") return std::nullopt;
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size() || value < 2 || value > 100000)
    throw OptionError("resolution must be a whole number from 2 to 100000 or \"auto\", not \"" + std::string(text) + "\"");
  return static_cast<std::uint32_t>(value);
}

}  // namespace clustersurf
