#pragma once
// A virtual range scanner: benchmark inputs that behave like real multi-view scans (occlusion
// holes, noise along the line of sight, per-scan misregistration, normals estimated from each
// scan's grid and pointing at its scanner), from a mesh whose surface is known.

#include <clustersurf/core/point_cloud.hpp>

#include <cstddef>
#include <cstdint>

namespace clustersurf {

/// How scan_surface() scans.
struct RangeScanOptions {
  /// Viewpoints, spread evenly over a sphere around the mesh (a Fibonacci sphere, so any count
  /// covers it without a preferred axis).
  std::size_t scans = 8;
  /// About this many points over all scans: each scan's square grid of rays is sized so.
  std::size_t count = 200'000;
  /// Scanner distance to the bounding-box center, in bounding-box diagonals. Each scan's grid
  /// spans the mesh's bounding sphere.
  double distance = 1.5;
  /// Standard deviation of the range noise (along the line of sight), as a fraction of the
  /// bounding-box diagonal.
  double noise = 0;
  /// How far along each scan's grid the range noise is correlated, in grid steps: the standard
  /// deviation of the Gaussian that smooths it (its variance kept); 0 for independent noise.
  /// A real scanner's range noise is correlated over a few steps (its optics and filters).
  double noise_correlation = 0;
  /// Standard deviation of each scan's misregistration, as a fraction of the diagonal: every
  /// scan is moved by a random rigid motion that displaces the bounding sphere's rim by about
  /// this much (half rotation about the center, half translation).
  double registration = 0;
  /// Fraction of the returns, in [0, 1], whose normal is flipped to point away from its scanner
  /// (drawn independently per return): the orientation errors of a real scan's normals.
  double flipped_normals = 0;
  /// Returns whose line of sight meets the surface more obliquely than this (degrees from the
  /// surface normal) are dropped, as real scanners drop grazing returns.
  double max_incidence_degrees = 80;
  /// Seed of every random choice (the noise and misregistration come from a portable
  /// generator; the ray casts are Embree's single-precision ones).
  std::uint64_t seed = 1;
};

/// The points a range scanner at each of `options.scans` viewpoints sees of `mesh`, in scan,
/// row, column order, with normals from each scan's grid neighbours (the hit facet's where a
/// return lacks neighbours in both grid directions), oriented towards its scanner.
/// Deterministic and independent of the thread count. Throws OptionError when the mesh has no
/// triangles or an option is out of range.
PointCloud scan_surface(const TriangleMesh& mesh, const RangeScanOptions& options = {});

}  // namespace clustersurf
