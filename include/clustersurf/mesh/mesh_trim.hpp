#pragma once
// Trimming a mesh to the reach of its input points: where the data stops (a scan's open border,
// an unscanned hole), the blended proxies extrapolate; the mesh stops with the data instead. And
// a loose fragment that hardly any input point lies nearest to (a sliver of extrapolated surface,
// a small inner shell between two scan layers) is debris, not surface: it goes too. On request,
// a small hole the data covers (the mesher's, not the scan's) is closed.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>

#include <algorithm>
#include <cstddef>
#include <span>

namespace clustersurf {

/// Options of trim_to_points().
struct TrimOptions {
  /// A triangle is dropped when a vertex lies farther from the nearest input point than this
  /// many times that point's spread (mean distance to its `neighbors` nearest points): about
  /// 3 sample spacings by default. A vertex within 1.5 times that reach is kept when its 16
  /// nearest points lie on one sheet, it lies within a spread of their plane, and they lie all
  /// around it: a gap between random samples (or a hole or slit as narrow), not the data's
  /// edge. Within the reach, a vertex farther than half a spread from the nearest point goes
  /// when its 16 nearest points lie on one sheet (or, where they wrap around a thin part, its
  /// 8 nearest lie within half a spread of theirs), it lies more than a spread off that plane,
  /// and a neighbour along its triangles is as far off or beyond the reach: a flap or bubble
  /// the blend raises near the data, not the data's surface (a lone such vertex is a spike,
  /// which the refit takes back). 0 keeps every triangle.
  double spread_factor = 2.0;
  std::size_t neighbors = 8;
  /// The reach never exceeds this many typical spreads (`typical_spread`), whatever the
  /// nearest point's: where the points thin out towards a scan's rim (views at a grazing angle),
  /// their spread grows past what they resolve, and the blend's extrapolation past the rim (a
  /// lip curling inwards, several spacings off the data) would stay within the reach. 3 is 1.5
  /// times the reach of a point of typical spread. 0: no bound.
  double max_reach_spreads = 3.0;
  /// The points' typical spread over the surface: the pipeline gives typical_spread() of its
  /// tree, the same in every tile; 0: the median spread of the mesh vertices' nearest points.
  double typical_spread = 0;
  /// A connected component is kept only when at least this many input points have their
  /// nearest mesh vertex on it (about what the support of a small leaf holds); 0 keeps every
  /// component. A real part as small as one cluster of the tree is kept.
  std::size_t min_component_points = 30;
  /// Close the mesh's pinholes: a boundary loop whose centroid lies within the trim's reach of
  /// the data (spread_factor spreads, 2 with the trim off) is closed by a fan, facing like its
  /// surroundings. The data is there, so the hole is the mesher's (a few grid cells where the
  /// blend was undefined), not the scan's; holes with no data inside stay open. Off by default:
  /// the flat fans lie up to a few percent farther from the true surface than an open hole does.
  bool close_pinholes = false;
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<TrimOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("spread_factor", o.spread_factor);
  f("neighbors", o.neighbors);
  f("max_reach_spreads", o.max_reach_spreads);
  f("typical_spread", o.typical_spread);
  f("min_component_points", o.min_component_points);
  f("close_pinholes", o.close_pinholes);
}

/// TrimOptions::typical_spread for a mesh of `tree`: the median over the surface's area of its
/// leaves' point spacings (a leaf's extent over √(2 × its points), weighted by its extent
/// squared), about the mean distance of a point to its 8 nearest on evenly sampled data. Over
/// the area, not the points: where points come in clumps, the surface is mostly where they are
/// sparse.
double typical_spread(const ClusterTree& tree);

/// What trim_to_points() removed.
struct TrimReport {
  std::size_t removed_triangles = 0;
  std::size_t removed_vertices = 0;
  std::size_t removed_components = 0;  ///< components without the data's support (see TrimOptions)
  std::size_t closed_pinholes = 0;     ///< boundary loops closed (TrimOptions::close_pinholes)
};

/// `mesh` without the triangles that reach beyond the data, without the components the data does
/// not support, with its pinholes closed (see TrimOptions), and without the vertices no
/// triangle uses; vertex order, normals and colors are kept for the rest (a closed pinhole's
/// centroid and fan come last).
/// Deterministic and independent of the thread count.
TriangleMesh trim_to_points(const TriangleMesh& mesh, const Points& points, const TrimOptions& options = {},
                            TrimReport* report = nullptr);
/// The same with the points' k-d tree given (`data`, over the points: CloudIndex::rows()) and,
/// when the caller has them, each point's spread over its options.neighbors nearest (`spread`,
/// one per point of `data`: CloudIndex::Subset::spread); empty: measured here.
TriangleMesh trim_to_points(const TriangleMesh& mesh, const KdTree& data, const TrimOptions& options = {},
                            TrimReport* report = nullptr, std::span<const double> spread = {});

}  // namespace clustersurf
