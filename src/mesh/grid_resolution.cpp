// The mesh grid matched to the sampling density of the input points.

#include <clustersurf/cloud_stats.hpp>
#include <clustersurf/errors.hpp>
#include <clustersurf/mesh_extraction.hpp>

#include <cmath>

namespace clustersurf {

double cell_size_for_points(const PointCloud& cloud, double spacing_factor) {
  if (!(spacing_factor > 0) || !std::isfinite(spacing_factor)) throw OptionError("the grid's spacing factor must be positive");
  const CloudStats stats = compute_stats(cloud);
  if (!(stats.median_spacing > 0) || !std::isfinite(stats.median_spacing))
    throw OptionError("cannot match the mesh grid to the points: most of them coincide (median spacing 0)");
  return spacing_factor * stats.median_spacing;
}

}  // namespace clustersurf
