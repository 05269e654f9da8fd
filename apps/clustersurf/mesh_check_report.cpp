#include "mesh_check_report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>

namespace clustersurf::cli {

namespace {

std::string plural(std::size_t n, const char* one, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

}  // namespace

nlohmann::json check_report_json(const MeshCheck& c) { return nlohmann::json::parse(mesh_check_json(c)); }

std::vector<std::string> mesh_check_lines(const MeshCheck& c) {
  const MeshTopology& t = c.topology;
  std::vector<std::string> out;
  out.push_back(fmt::format("vertices        {}", t.vertices));
  out.push_back(fmt::format("triangles       {}", t.triangles));
  out.push_back(fmt::format("edges           {}: {} boundary, {} non-manifold, {} inconsistently oriented", t.edges,
                            t.boundary_edges, t.non_manifold_edges, t.inconsistent_edges));
  out.push_back(fmt::format("components      {}", t.components));
  out.push_back(c.genus >= 0 ? fmt::format("euler           {} (genus {})", t.euler_characteristic, c.genus)
                             : fmt::format("euler           {} (genus not defined: {})", t.euler_characteristic,
                                           !c.watertight              ? "not closed"
                                           : !c.consistently_oriented ? "not consistently oriented"
                                                                      : "components pinched at vertices"));
  out.push_back(std::isnan(c.volume) ? std::string("volume          n/a (not closed)")
                                     : fmt::format("volume          {:.6g}{}", c.volume,
                                                   c.volume < 0 ? " (negative: the triangles face inward)" : ""));
  std::string pairs;
  if (!c.intersecting_pairs.empty()) {
    std::vector<std::string> shown;
    for (std::size_t k = 0; k < c.intersecting_pairs.size() && k < 5; ++k)
      shown.push_back(fmt::format("{}&{}", c.intersecting_pairs[k][0], c.intersecting_pairs[k][1]));
    pairs =
        fmt::format(" (triangles {}{})", fmt::join(shown, ", "), c.self_intersections > shown.size() ? ", ..." : "");
  }
  out.push_back(
      fmt::format("self-intersect  {}{}", plural(c.self_intersections, "triangle pair", "triangle pairs"), pairs));
  out.push_back(fmt::format("watertight      {}", c.watertight ? "yes" : "no"));
  out.push_back(fmt::format("oriented        {}", c.consistently_oriented ? "yes" : "no"));
  const std::vector<std::string> problems = printing_problems(c);
  out.push_back(c.printable ? std::string("printable       yes")
                            : fmt::format("printable       no: {}", fmt::join(problems, ", ")));
  return out;
}

}  // namespace clustersurf::cli
