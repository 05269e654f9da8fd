// Partition-of-unity blending of the proxies of a tree cut.

#include <clustersurf/errors.hpp>
#include <clustersurf/implicit_surface.hpp>

#include <tbb/parallel_for.h>

#include <cmath>

namespace clustersurf {

std::vector<std::int32_t> lod_cut(const ClusterTree& tree, const LevelOfDetail& lod) {
  std::vector<std::int32_t> cut;
  if (tree.nodes.empty()) return cut;
  const ErrorMetric metric = tree.parameters.metric;
  std::vector<std::int32_t> stack{0};
  while (!stack.empty()) {
    const std::int32_t i = stack.back();
    stack.pop_back();
    const ClusterNode& n = tree.nodes[static_cast<std::size_t>(i)];
    const double e = metric == ErrorMetric::Rms ? n.rms_error : n.max_error;
    const bool stop = n.is_leaf() || (lod.max_depth && n.depth >= *lod.max_depth) || (lod.error_limit && e <= *lod.error_limit);
    if (stop) {
      cut.push_back(i);
    } else {
      stack.push_back(n.right);
      stack.push_back(n.left);
    }
  }
  return cut;
}

LevelOfDetail level_of_detail(const ClusterTree& tree, std::optional<std::uint32_t> depth, std::optional<double> error_fraction) {
  LevelOfDetail lod;
  lod.max_depth = depth;
  if (error_fraction) {
    if (!(*error_fraction >= 0) || !std::isfinite(*error_fraction))
      throw OptionError("the level-of-detail error must be a non-negative fraction of the diagonal");
    lod.error_limit = *error_fraction * tree.bbox.diagonal();
  }
  return lod;
}

ImplicitSurface::ImplicitSurface(const ClusterTree& tree, const LevelOfDetail& lod)
    : tree_(&tree), cut_(lod_cut(tree, lod)), walk_nodes_(tree.nodes.size()), supports_(tree.nodes.size()) {
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    walk_nodes_[i].left = tree.nodes[i].left;
    walk_nodes_[i].right = tree.nodes[i].right;
  }
  for (auto i : cut_) walk_nodes_[static_cast<std::size_t>(i)].in_cut = 1;
  grow_by_margin();
}

ImplicitSurface ImplicitSurface::with_margin(double margin) const {
  ImplicitSurface out = *this;
  out.margin_ = std::max(margin, 0.0);
  out.grow_by_margin();
  return out;
}

void ImplicitSurface::grow_by_margin() {
  for (std::size_t i = 0; i < tree_->nodes.size(); ++i) {
    const ClusterNode& n = tree_->nodes[i];
    walk_nodes_[i].bound = Sphere{n.bound.center, n.bound.radius + margin_};
    supports_[i] = Sphere{n.support.center, n.support.radius + margin_};
  }
}

SurfaceSample ImplicitSurface::sample(const Eigen::Vector3d& x) const {
  // f = A / W with A = Σ w Q and W = Σ w; ∇f = (∇A − f ∇W) / W.
  double a = 0, w_sum = 0;
  Eigen::Vector3d grad_a = Eigen::Vector3d::Zero(), grad_w = Eigen::Vector3d::Zero();
  for_each_support(x, [&](std::int32_t i, double s) {
    const ClusterNode& n = tree_->nodes[static_cast<std::size_t>(i)];
    const double one_minus = 1 - s;
    const double w = blend_weight(s);
    const double r = radius(i);
    const Eigen::Vector3d dw = (-6 * one_minus * one_minus / (r * r)) * (x - supports_[static_cast<std::size_t>(i)].center);
    const double q = n.proxy.value(x);
    a += w * q;
    w_sum += w;
    grad_a += dw * q + w * n.proxy.gradient(x);
    grad_w += dw;
  });
  SurfaceSample out;
  out.weight = w_sum;
  if (!(w_sum > 0)) return out;
  out.defined = true;
  out.value = a / w_sum;
  out.gradient = (grad_a - out.value * grad_w) / w_sum;
  return out;
}

std::pair<double, double> ImplicitSurface::weighted_sum(const Eigen::Vector3d& x) const {
  double a = 0, w_sum = 0;
  for_each_support(x, [&](std::int32_t i, double s) {
    const double w = blend_weight(s);
    a += w * tree_->nodes[static_cast<std::size_t>(i)].proxy.value(x);
    w_sum += w;
  });
  return {a, w_sum};
}

std::optional<double> ImplicitSurface::value(const Eigen::Vector3d& x, double min_weight) const {
  const auto [a, w_sum] = weighted_sum(x);
  if (!(w_sum > 0) || !(w_sum > min_weight)) return std::nullopt;
  return a / w_sum;
}

std::vector<SurfaceSample> ImplicitSurface::sample_all(const Points& points) const {
  std::vector<SurfaceSample> out(static_cast<std::size_t>(points.rows()));
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, points.rows(), 256), [&](const auto& r) {
    for (Eigen::Index i = r.begin(); i != r.end(); ++i) out[static_cast<std::size_t>(i)] = sample(Eigen::Vector3d(points.row(i).transpose()));
  });
  return out;
}

}  // namespace clustersurf
