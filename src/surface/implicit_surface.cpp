// Partition-of-unity blending of the proxies of a tree cut.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/surface/box_walk.hpp>
#include <clustersurf/surface/implicit_surface.hpp>

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
    const bool stop =
        n.is_leaf() || (lod.max_depth && n.depth >= *lod.max_depth) || (lod.error_limit && e <= *lod.error_limit);
    if (stop) {
      cut.push_back(i);
    } else {
      stack.push_back(n.right);
      stack.push_back(n.left);
    }
  }
  return cut;
}

LevelOfDetail level_of_detail(const ClusterTree& tree, std::optional<std::uint32_t> depth,
                              std::optional<double> error_fraction) {
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

namespace {

/// Σ wᵢ Qᵢ(x) and Σ wᵢ over the supports `for_each_support` enumerates at x.
template <class ForEachSupport>
std::pair<double, double> blend(const ClusterTree& tree, const Eigen::Vector3d& x, ForEachSupport&& for_each_support) {
  double a = 0, w_sum = 0;
  for_each_support(x, [&](std::int32_t i, double s) {
    const double w = blend_weight(s);
    a += w * tree.nodes[static_cast<std::size_t>(i)].proxy.value(x);
    w_sum += w;
  });
  return {a, w_sum};
}

void require_built_for(const ImplicitSurface::BoxWalk& near, const ImplicitSurface& surface) {
  if (&near.surface() != &surface) throw OptionError("a BoxWalk serves only the surface it was built for");
}

std::optional<double> defined_value(const std::pair<double, double>& sums, double min_weight) {
  const auto [a, w_sum] = sums;
  if (!(w_sum > 0) || !(w_sum > min_weight)) return std::nullopt;
  return a / w_sum;
}

/// f and ∇f at x over the supports `for_each_support` enumerates.
template <class ForEachSupport>
SurfaceSample blend_sample(const ImplicitSurface& surface, const Eigen::Vector3d& x,
                           ForEachSupport&& for_each_support) {
  // f = A / W with A = Σ w Q and W = Σ w; ∇f = (∇A − f ∇W) / W.
  double a = 0, w_sum = 0;
  Eigen::Vector3d grad_a = Eigen::Vector3d::Zero(), grad_w = Eigen::Vector3d::Zero();
  for_each_support(x, [&](std::int32_t i, double s) {
    const ClusterNode& n = surface.tree().nodes[static_cast<std::size_t>(i)];
    const double one_minus = 1 - s;
    const double w = blend_weight(s);
    const double r = surface.radius(i);
    const Eigen::Vector3d dw = (-6 * one_minus * one_minus / (r * r)) * (x - n.support.center);
    const auto [q, grad_q] = n.proxy.value_and_gradient(x);
    a += w * q;
    w_sum += w;
    grad_a += dw * q + w * grad_q;
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

}  // namespace

SurfaceSample ImplicitSurface::sample(const Eigen::Vector3d& x) const {
  return blend_sample(*this, x, [this](const Eigen::Vector3d& y, auto&& visit) { for_each_support(y, visit); });
}

SurfaceSample ImplicitSurface::sample(const Eigen::Vector3d& x, const BoxWalk& near) const {
  require_built_for(near, *this);
  return blend_sample(*this, x, [&near](const Eigen::Vector3d& y, auto&& visit) { near.for_each_support(y, visit); });
}

std::pair<double, double> ImplicitSurface::weighted_sum(const Eigen::Vector3d& x) const {
  return blend(*tree_, x, [this](const Eigen::Vector3d& y, auto&& visit) { for_each_support(y, visit); });
}

std::optional<double> ImplicitSurface::value(const Eigen::Vector3d& x, double min_weight) const {
  return defined_value(weighted_sum(x), min_weight);
}

std::optional<double> ImplicitSurface::value(const Eigen::Vector3d& x, double min_weight, const BoxWalk& near) const {
  require_built_for(near, *this);
  return defined_value(
      blend(*tree_, x, [&near](const Eigen::Vector3d& y, auto&& visit) { near.for_each_support(y, visit); }),
      min_weight);
}

std::vector<SurfaceSample> ImplicitSurface::sample_all(const Points& points) const {
  std::vector<SurfaceSample> out(static_cast<std::size_t>(points.rows()));
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, points.rows(), 256), [&](const auto& r) {
    for (Eigen::Index i = r.begin(); i != r.end(); ++i)
      out[static_cast<std::size_t>(i)] = sample(Eigen::Vector3d(points.row(i).transpose()));
  });
  return out;
}

}  // namespace clustersurf
