#pragma once
// A mesh's vertices moved onto a local fit of the input points around each of them, by the
// share of the move that stands above the noise.

#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/surface/implicit_surface.hpp>

#include <cstdint>
#include <span>

namespace clustersurf {

/// The fewest points a vertex's local fit takes: a quadratic's six coefficients.
inline constexpr std::uint32_t kMinRefitPoints = 6;

/// Options of refit_vertices().
struct VertexRefitOptions {
  /// Input points each vertex's narrowest local fit takes (a wider one takes twice as many): its
  /// nearest, weighted by (1 − d²/h²)³ with h the farthest one's distance (the fewest a
  /// quadratic's refit takes, as a leaf's support's).
  /// 0 leaves the vertices where the blend of the leaves puts them; otherwise at least
  /// kMinRefitPoints.
  std::uint32_t points = 12;
  /// The rings of mesh neighbours over which a vertex's move is weighed against the noise.
  std::uint32_t rings = 2;
  /// After the moves, each vertex goes out along its normal by the mean sag of its triangles'
  /// chords under the surface (the lumped L² projection of the smooth surface through the
  /// vertices and normals onto the mesh): the triangles straddle a curved surface instead of
  /// cutting under it. false leaves the vertices on the fits.
  bool chord_offset = true;
};

/// Throws OptionError, naming refit_points, when options.points is neither 0 nor at least
/// kMinRefitPoints.
void check_refit_options(const VertexRefitOptions& options);

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<VertexRefitOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("points", o.points);
  f("rings", o.rings);
  f("chord_offset", o.chord_offset);
}

/// What refit_vertices() did.
struct VertexRefitReport {
  std::size_t refitted = 0;      ///< vertices whose local fit was determined
  double mean_move = 0;          ///< mean |move| over all vertices, in the mesh's units
  double mean_share = 0;         ///< mean share of the local fits' moves taken (0: none, 1: all)
  double mean_chord_offset = 0;  ///< mean |offset| of the vertices by their chords' sag
};

/// Moves each vertex of `mesh` (a mesh of `surface`) along its normal (mesh.normals;
/// recomputed from the triangles when absent) towards the weighted quadratic height field
/// fitted, in the frame of that normal, to its nearest points of `data` (its tree's clustered
/// input): VertexRefitOptions::points of them, or twice as many where the wider fit's move lies
/// within the confidence interval of the narrower's (both intervals ±2 standard deviations
/// under the noise, the margin of the tree's noise tests, and intersecting: the rule of the
/// intersection of confidence intervals, which widens a fit while its bias stays below its
/// noise). Of that local fit's move c, whose variance under the noise is s² (the fit's variance
/// through the weighted least squares less the blend's, which averages the same points over the
/// leaves' supports; under the smaller of the tree's noise estimate and the noise the narrow
/// and wide fits' residuals show over the same window without their relief, at the margin the
/// narrow fits' degrees of freedom allow: the tree reads relief as noise where a cluster's
/// quadratic leaves some), it takes the Wiener share P / (P + s²), with
/// P = max(0, ⟨c²⟩ − q(m) ⟨s²⟩) the moves' power above their noise: the means over the vertex
/// and its mesh neighbours within `rings` rings, m the independent fits that window holds (its
/// area over a fit's), q(m) the chi-square quantile of a mean of m squares as far out as the
/// tree's noise tests reach (noise_variance_quantile()). Where the moves are
/// the noise's the vertices stay; where they stand above it (the blend's error on clean or
/// sparse data) they are taken. A fit that its points do not determine, that misses the error
/// a cluster of the tree may keep (cluster_error_threshold(): a sharp edge, both sides of a
/// thin part), or whose move would reach past its farthest point or farther than the points'
/// typical spread (typical_spread() of the tree: the blend lies within it), moves nothing; nor
/// do the vertices where a crease leaf blends (its planes hold the sharp edge), those whose
/// `fixed` value is positive (a closed mesh's filled vertices), the corners of a triangle
/// the moves would turn by more than 60 degrees (a fold), and the corners of a triangle that a
/// move of more than a tenth of the typical spread makes intersect another part of the mesh
/// (the far side of a thin part; intersections the moves did not make are left as they are).
/// The normals are kept. Then, with options.chord_offset, the vertices are offset by their
/// triangles' mean chord sag (the sag of the quadratic their normals give: not where the
/// normals turn by more than the mesh grid resolves, nor at `fixed` vertices). Deterministic
/// for any thread count and any numbering of the vertices and of the data. Throws OptionError
/// for invalid options (check_refit_options()).
VertexRefitReport refit_vertices(TriangleMesh& mesh, const KdTree& data, const ImplicitSurface& surface,
                                 const VertexRefitOptions& options = {}, std::span<const float> fixed = {});

}  // namespace clustersurf
