#include "commands.hpp"
#include "input.hpp"

#include <clustersurf/spatial/cloud_stats.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <iostream>

namespace clustersurf::cli {

int run_stats(Console& console, const StatsArgs& args) {
  const PointCloud cloud = read_input(console, args.input);
  const CloudStats s = compute_stats(cloud);
  if (console.options().json) {
    nlohmann::json j{{"file", args.input.file},
                     {"points", s.points},
                     {"bbox_min", {s.bbox.min.x(), s.bbox.min.y(), s.bbox.min.z()}},
                     {"bbox_max", {s.bbox.max.x(), s.bbox.max.y(), s.bbox.max.z()}},
                     {"diagonal", s.diagonal},
                     {"mean_spacing", s.mean_spacing},
                     {"median_spacing", s.median_spacing},
                     {"origin", {s.origin.x(), s.origin.y(), s.origin.z()}},
                     {"has_normals", s.has_normals},
                     {"has_colors", s.has_colors},
                     {"attributes", s.attributes},
                     {"scanners", s.scanners},
                     {"scans", s.scans}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  console.print(fmt::format("file            {}", args.input.file));
  console.print(fmt::format("points          {}", s.points));
  console.print(fmt::format("bbox min        {:.10g} {:.10g} {:.10g}", s.bbox.min.x(), s.bbox.min.y(), s.bbox.min.z()));
  console.print(fmt::format("bbox max        {:.10g} {:.10g} {:.10g}", s.bbox.max.x(), s.bbox.max.y(), s.bbox.max.z()));
  console.print(fmt::format("diagonal        {:.6g}", s.diagonal));
  console.print(fmt::format("mean spacing    {:.6g} (median {:.6g}; nearest-neighbour distance)", s.mean_spacing,
                            s.median_spacing));
  console.print(fmt::format("normals         {}", s.has_normals ? "yes" : "no"));
  console.print(fmt::format("colors          {}", s.has_colors ? "yes" : "no"));
  console.print(fmt::format("attributes      {}",
                            s.attributes.empty() ? "none" : fmt::format("{}", fmt::join(s.attributes, ", "))));
  console.print(
      fmt::format("scanners        {}", s.scanners == 0 ? std::string("unknown") : std::to_string(s.scanners)));
  if (s.scans > 0) console.print(fmt::format("scans           {} (the scan of each point is known)", s.scans));
  if (!s.origin.isZero())
    console.print(fmt::format("origin          {:.17g} {:.17g} {:.17g} (the points are stored relative to it)",
                              s.origin.x(), s.origin.y(), s.origin.z()));
  return 0;
}

}  // namespace clustersurf::cli
