#pragma once
// Accuracy of a reconstruction against a reference surface: the figures reconstruction papers
// report (Chamfer, Hausdorff, normal consistency, F-score), measured to the true surfaces.

#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/evaluation/volume_overlap.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf {

/// How compare_surfaces() samples and scores.
struct ComparisonOptions {
  /// Points sampled (area-uniform) on each surface that is a mesh. A point cloud uses its own
  /// points, at most this many of them (an even random subset when it has more).
  std::size_t samples = 200'000;
  std::uint64_t seed = 1;
  /// F-score thresholds τ, as fractions of the reference's bounding-box diagonal.
  std::vector<double> fscore_thresholds{0.005, 0.01};
  /// SurfaceComparison::far_share counts the reconstruction's samples farther than this many
  /// of a reference cloud's median point spacings from it.
  double far_spacings = 8;
  /// Points SurfaceComparison::volume_iou tests; 0: none.
  std::size_t volume_samples = VolumeOverlapOptions{}.samples;
};

/// Precision, recall and F-score at one threshold.
struct FScore {
  double threshold = 0;  ///< τ as a fraction of the reference diagonal
  double precision = 0;  ///< share of reconstruction samples within τ of the reference
  double recall = 0;     ///< share of reference samples within τ of the reconstruction
  double fscore = 0;     ///< harmonic mean of precision and recall
};

/// The scores. Distances are fractions of the reference's bounding-box diagonal; each sample's
/// distance is to the other surface itself (nearest point on its triangles) when that surface is
/// a mesh, or to its nearest point when it is a cloud.
struct SurfaceComparison {
  double diagonal = 0;      ///< the reference's bounding-box diagonal (input units)
  double accuracy = 0;      ///< mean distance reconstruction → reference
  double completeness = 0;  ///< mean distance reference → reconstruction
  double chamfer = 0;       ///< (accuracy + completeness) / 2
  double hausdorff = 0;     ///< max of both directions' largest distance
  /// The 95th percentile of the distances of both directions' samples together: the error of
  /// all but the worst 5 % of the surface, which a mean hides and the Hausdorff distance's single
  /// worst point overstates.
  double distance_p95 = 0;
  /// Mean |n · n'| between each sample's normal and the normal of its nearest point on the other
  /// surface, over both directions; NaN when one side has no normals.
  double normal_consistency = 0;
  std::vector<FScore> fscores;
  /// When the reference is a point cloud (a scan without a true surface): the share of the
  /// reconstruction's samples farther than ComparisonOptions::far_spacings of its median point
  /// spacings from every point, the surface the data does not support. NaN for a mesh reference
  /// (or a cloud whose points mostly coincide: its median spacing is 0).
  double far_share = 0;
  /// When both surfaces are meshes without boundary edges: the volumetric intersection over union
  /// of the solids they bound (volume_overlap()). NaN otherwise: an open surface bounds none.
  double volume_iou = 0;
  /// The reference cloud's median point spacing (input units); 0 for a mesh reference.
  double reference_spacing = 0;
  std::size_t reconstruction_samples = 0;
  std::size_t reference_samples = 0;
  MeshTopology reconstruction_topology;  ///< counts only, when the reconstruction is a cloud
  MeshTopology reference_topology;
};

/// Scores `reconstruction` against `reference`. Each is a triangle mesh, or a point cloud when
/// it has no triangles (its vertices, with normals when present). The two may have different
/// origins (each is relative to its own): the reconstruction is compared in the reference's
/// frame. Deterministic for a seed. Throws OptionError when either surface is empty or an
/// origin is not finite.
SurfaceComparison compare_surfaces(const TriangleMesh& reconstruction, const TriangleMesh& reference,
                                   const ComparisonOptions& options = {});

}  // namespace clustersurf
