// decimate(): meshoptimizer's simplifier on float positions, then the surviving vertices
// gathered in their original order with their attributes.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_decimation.hpp>

#include "mesh/mesh_subset.hpp"

#include <meshoptimizer.h>

#include <cmath>
#include <limits>
#include <vector>

namespace clustersurf {

TriangleMesh decimate(const TriangleMesh& mesh, const DecimationOptions& options, DecimationReport* report) {
  if (!(options.max_deviation >= 0) || !std::isfinite(options.max_deviation))
    throw OptionError("the decimation's distance bound must be a finite number >= 0");
  const auto nv = static_cast<std::size_t>(mesh.vertices.rows());
  const auto nf = static_cast<std::size_t>(mesh.triangles.rows());
  DecimationReport done;
  done.triangles_before = done.triangles_after = nf;
  if (!options.enabled() || nf == 0 ||
      (options.target_triangles > 0 && options.target_triangles >= nf && options.max_deviation == 0)) {
    if (report) *report = done;
    return mesh;
  }
  std::vector<float> positions(3 * nv);  // row-major xyz
  for (std::size_t i = 0; i < 3 * nv; ++i) positions[i] = static_cast<float>(mesh.vertices.data()[i]);
  std::vector<unsigned> indices(3 * nf);
  for (std::size_t i = 0; i < 3 * nf; ++i) indices[i] = static_cast<unsigned>(mesh.triangles.data()[i]);
  const float scale = meshopt_simplifyScale(positions.data(), nv, 3 * sizeof(float));
  // The simplifier's error is relative to the mesh's extent; no bound means any error (1).
  const float relative =
      options.max_deviation > 0 && scale > 0 ? static_cast<float>(options.max_deviation / scale) : 1.0f;
  const std::size_t target = options.target_triangles > 0 ? 3 * options.target_triangles : 0;
  std::vector<unsigned> kept(indices.size());
  float error = 0;
  kept.resize(meshopt_simplify(kept.data(), indices.data(), indices.size(), positions.data(), nv, 3 * sizeof(float),
                               target, relative,
                               options.lock_boundary ? static_cast<unsigned>(meshopt_SimplifyLockBorder) : 0u, &error));

  TriangleMesh out = mesh;
  out.triangles.resize(static_cast<Eigen::Index>(kept.size() / 3), 3);
  for (std::size_t i = 0; i < kept.size(); ++i)
    out.triangles(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) =
        static_cast<std::int32_t>(kept[i]);
  out = detail::without_unused_vertices(out);
  done.triangles_after = kept.size() / 3;
  done.deviation = static_cast<double>(error) * static_cast<double>(scale);
  if (report) *report = done;
  return out;
}

}  // namespace clustersurf
