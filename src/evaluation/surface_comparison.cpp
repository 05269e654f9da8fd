#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/mesh_distance.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/io/surface_sampling.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/spatial/resample.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace clustersurf {

namespace {

bool is_mesh(const TriangleMesh& s) { return s.triangles.rows() > 0; }

/// Points spread over a surface: area-uniform samples of a mesh, or (a subset of) a cloud.
PointCloud samples_of(const TriangleMesh& surface, const ComparisonOptions& options, std::uint64_t seed) {
  if (is_mesh(surface)) {
    SurfaceSamplingOptions o;
    o.count = options.samples;
    o.seed = seed;
    return sample_surface(surface, o);
  }
  PointCloud cloud;
  cloud.positions = surface.vertices;
  cloud.normals = surface.normals;
  if (static_cast<std::size_t>(cloud.size()) > options.samples) cloud = subsample(cloud, options.samples, seed);
  return cloud;
}

/// Nearest-point queries against one surface: its triangles, or its points.
class Target {
 public:
  explicit Target(const TriangleMesh& surface) : surface_(surface) {
    if (is_mesh(surface))
      mesh_.emplace(surface);
    else
      points_.emplace(surface.vertices);
  }
  /// The points' index when the surface is a cloud, else null.
  const KdTree* points() const { return points_ ? &*points_ : nullptr; }
  bool has_normals() const { return mesh_.has_value() || surface_.normals.rows() == surface_.vertices.rows(); }
  /// Distance to the surface and the unit normal there (zero when unknown).
  std::pair<double, Eigen::Vector3d> nearest(const Eigen::Vector3d& p) const {
    if (mesh_) {
      const ClosestPoint c = mesh_->closest(p);
      return {std::sqrt(c.distance_squared), mesh_->triangle_normal(c.triangle)};
    }
    thread_local std::vector<Neighbor> nb;
    points_->knn(p, 1, nb);
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    if (surface_.normals.rows() == surface_.vertices.rows()) {
      n = surface_.normals.row(nb[0].index).transpose();
      if (n.norm() > 0) n.normalize();
    }
    return {std::sqrt(nb[0].distance_squared), n};
  }

 private:
  const TriangleMesh& surface_;
  std::optional<MeshDistance> mesh_;
  std::optional<KdTree> points_;
};

struct Direction {
  std::vector<double> distance;  // per sample, in input units
  double normal_sum = 0;         // Σ |n · n'| over samples with both normals
  std::size_t normal_count = 0;
};

Direction measure(const PointCloud& from, const Target& to) {
  const auto n = static_cast<std::size_t>(from.size());
  Direction d;
  d.distance.resize(n);
  std::vector<double> agreement(n, std::numeric_limits<double>::quiet_NaN());
  const bool normals = from.has_normals() && to.has_normals();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const auto [dist, normal] = to.nearest(from.positions.row(static_cast<Eigen::Index>(i)).transpose());
      d.distance[i] = dist;
      if (!normals) continue;
      Eigen::Vector3d a = from.normals.row(static_cast<Eigen::Index>(i)).transpose();
      if (a.norm() > 0 && normal.norm() > 0) agreement[i] = std::abs(a.normalized().dot(normal));
    }
  });
  for (double a : agreement)  // serial sums: the same result for any thread count
    if (!std::isnan(a)) d.normal_sum += a, ++d.normal_count;
  return d;
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / static_cast<double>(v.size());
}

/// The q-quantile (nearest rank) of the values of `a` and `b` together; 0 when both are empty.
double percentile(const std::vector<double>& a, const std::vector<double>& b, double q) {
  std::vector<double> all(a);
  all.insert(all.end(), b.begin(), b.end());
  if (all.empty()) return 0;
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(all.size()))) - 1;
  const auto k = std::min(rank, all.size() - 1);
  std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(k), all.end());
  return all[k];
}

double share_within(const std::vector<double>& v, double tau) {
  std::size_t k = 0;
  for (double x : v) k += x <= tau;
  return v.empty() ? 0 : static_cast<double>(k) / static_cast<double>(v.size());
}

}  // namespace

SurfaceComparison compare_surfaces(const TriangleMesh& given, const TriangleMesh& reference,
                                   const ComparisonOptions& options) {
  if (given.vertices.rows() == 0) throw OptionError("the reconstruction is empty");
  if (!given.origin.allFinite() || !reference.origin.allFinite())
    throw OptionError("the surfaces' origins must be finite");
  // The reconstruction in the reference's frame: both near zero, whatever their files' origins.
  std::optional<TriangleMesh> moved;
  if (given.origin != reference.origin) {
    moved = given;
    moved->vertices.rowwise() += (given.origin - reference.origin).transpose();
    moved->origin = reference.origin;
  }
  const TriangleMesh& reconstruction = moved ? *moved : given;
  if (reference.vertices.rows() == 0) throw OptionError("the reference is empty");
  if (options.samples == 0) throw OptionError("the number of samples must be positive");
  SurfaceComparison e;
  const BoundingBox box = bounding_box(reference.vertices);
  e.diagonal = box.diagonal();
  if (!(e.diagonal > 0)) throw OptionError("the reference has a zero-size bounding box");

  const PointCloud recon_samples = samples_of(reconstruction, options, options.seed);
  const PointCloud ref_samples = samples_of(reference, options, options.seed + 1);
  e.reconstruction_samples = static_cast<std::size_t>(recon_samples.size());
  e.reference_samples = static_cast<std::size_t>(ref_samples.size());
  const Target reference_target(reference);
  const Direction forward = measure(recon_samples, reference_target);
  const Direction backward = measure(ref_samples, Target(reconstruction));

  const double scale = 1.0 / e.diagonal;
  e.accuracy = mean(forward.distance) * scale;
  e.completeness = mean(backward.distance) * scale;
  e.chamfer = 0.5 * (e.accuracy + e.completeness);
  const auto max_of = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
  };
  e.hausdorff = std::max(max_of(forward.distance), max_of(backward.distance)) * scale;
  e.distance_p95 = percentile(forward.distance, backward.distance, 0.95) * scale;
  const std::size_t nc = forward.normal_count + backward.normal_count;
  e.normal_consistency = nc > 0 && forward.normal_count > 0 && backward.normal_count > 0
                             ? (forward.normal_sum + backward.normal_sum) / static_cast<double>(nc)
                             : std::numeric_limits<double>::quiet_NaN();
  for (double tau : options.fscore_thresholds) {
    FScore f;
    f.threshold = tau;
    f.precision = share_within(forward.distance, tau * e.diagonal);
    f.recall = share_within(backward.distance, tau * e.diagonal);
    f.fscore = f.precision + f.recall > 0 ? 2 * f.precision * f.recall / (f.precision + f.recall) : 0;
    e.fscores.push_back(f);
  }
  e.far_share = std::numeric_limits<double>::quiet_NaN();
  if (const KdTree* points = reference_target.points()) {
    e.reference_spacing = point_spacing(*points).median;
    // Most points coinciding leave no spacing to measure by.
    if (e.reference_spacing > 0)
      e.far_share = 1 - share_within(forward.distance, options.far_spacings * e.reference_spacing);
  }
  e.reconstruction_topology = mesh_topology(reconstruction);
  e.reference_topology = mesh_topology(reference);
  e.volume_iou = std::numeric_limits<double>::quiet_NaN();
  const auto closed = [](const TriangleMesh& m, const MeshTopology& t) { return is_mesh(m) && t.boundary_edges == 0; };
  if (options.volume_samples > 0 && closed(reconstruction, e.reconstruction_topology) &&
      closed(reference, e.reference_topology)) {
    VolumeOverlapOptions volume;
    volume.samples = options.volume_samples;
    volume.seed = options.seed;
    e.volume_iou = volume_overlap(reconstruction, reference, volume).iou;
  }
  return e;
}

}  // namespace clustersurf
