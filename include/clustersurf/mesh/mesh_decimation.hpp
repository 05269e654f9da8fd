#pragma once
// Reducing a mesh to fewer triangles (meshoptimizer's edge collapses, which keep a subset of
// the vertices in place): a triangle budget, a distance bound, or both.

#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/point_cloud.hpp>

#include <cstddef>

namespace clustersurf {

/// What decimate() aims for; with both set, it stops at whichever it reaches first.
struct DecimationOptions {
  /// Keep at most this many triangles (0: no budget; the distance bound alone decides).
  std::size_t target_triangles = 0;
  /// Move the surface by at most about this distance, in input units (the simplifier's
  /// estimate: distances to the planes of the triangles merged, not a strict Hausdorff bound;
  /// 0: no bound, the budget alone decides).
  double max_deviation = 0;
  /// Keep the mesh's boundary edges (the rims of an open scan) in place.
  bool lock_boundary = true;

  /// Whether any reduction was asked for.
  bool enabled() const noexcept { return target_triangles > 0 || max_deviation > 0; }
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<DecimationOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("target_triangles", o.target_triangles);
  f("max_deviation", o.max_deviation);
  f("lock_boundary", o.lock_boundary);
}

/// What decimate() did.
struct DecimationReport {
  std::size_t triangles_before = 0;
  std::size_t triangles_after = 0;
  /// The largest distance the surface moved, as the simplifier estimates it (input units).
  double deviation = 0;
};

/// The mesh with fewer triangles: surviving vertices keep their positions, normals, colors and attributes,
/// unused vertices are dropped (order kept), the origin is kept. The same mesh and options give
/// the same result. Throws OptionError for a negative or non-finite bound.
TriangleMesh decimate(const TriangleMesh& mesh, const DecimationOptions& options, DecimationReport* report = nullptr);

}  // namespace clustersurf
