// The proxy patches the viewer draws: each node's frame, the extent of its cluster's points in
// it, and a grid of its proxy's heights over that extent.

#include "view/patch_grid.hpp"

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <variant>

namespace clustersurf::detail {

namespace {

/// The frame a node's patch is drawn in, or nothing for point proxies.
struct PatchFrame {
  Eigen::Vector3d origin;
  Eigen::Matrix3d axes;  // columns e1, e2, e3
};

Eigen::Matrix3d basis_around(const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d a = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = (a - a.dot(n) * n).normalized();
  Eigen::Matrix3d axes;
  axes << e1, n.cross(e1), n;
  return axes;
}

std::optional<PatchFrame> patch_frame(const ClusterNode& node) {
  const Proxy::Variant& v = node.proxy.variant();
  if (const auto* poly = std::get_if<PolyProxy>(&v)) return PatchFrame{poly->frame.origin, poly->frame.axes};
  if (const auto* plane = std::get_if<PlaneProxy>(&v)) {
    const Eigen::Vector3d c = node.support.center;
    return PatchFrame{c - plane->normal.dot(c - plane->point) * plane->normal, basis_around(plane->normal)};
  }
  if (std::holds_alternative<QuadricProxy>(v) || std::holds_alternative<CreaseProxy>(v))
    return PatchFrame{node.support.center, basis_around(node.proxy.normal())};
  return std::nullopt;
}

/// [umin, umax] × [vmin, vmax] of a cluster's points in its patch frame.
struct Extent {
  double umin = std::numeric_limits<double>::infinity(), umax = -std::numeric_limits<double>::infinity();
  double vmin = std::numeric_limits<double>::infinity(), vmax = -std::numeric_limits<double>::infinity();
  void extend(double u, double v) {
    umin = std::min(umin, u), umax = std::max(umax, u);
    vmin = std::min(vmin, v), vmax = std::max(vmax, v);
  }
  void merge(const Extent& e) {
    umin = std::min(umin, e.umin), umax = std::max(umax, e.umax);
    vmin = std::min(vmin, e.vmin), vmax = std::max(vmax, e.vmax);
  }
};

std::vector<Extent> cluster_extents(const ClusterTree& tree, const Points& positions,
                                    const std::vector<std::optional<PatchFrame>>& frames) {
  const std::size_t n = tree.nodes.size();
  tbb::combinable<std::vector<Extent>> partial([n] { return std::vector<Extent>(n); });
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, positions.rows(), 4096), [&](const auto& r) {
    std::vector<Extent>& extents = partial.local();
    for (Eigen::Index p = r.begin(); p != r.end(); ++p) {
      const Eigen::Vector3d x = positions.row(p).transpose();
      for (std::int32_t i = tree.point_leaf[static_cast<std::size_t>(p)]; i >= 0;
           i = tree.nodes[static_cast<std::size_t>(i)].parent) {
        const auto& f = frames[static_cast<std::size_t>(i)];
        if (!f) continue;
        const Eigen::Vector3d d = x - f->origin;
        extents[static_cast<std::size_t>(i)].extend(f->axes.col(0).dot(d), f->axes.col(1).dot(d));
      }
    }
  });
  std::vector<Extent> extents(n);  // min/max: the merge order does not change the result
  partial.combine_each([&](const std::vector<Extent>& e) {
    for (std::size_t i = 0; i < n; ++i) extents[i].merge(e[i]);
  });
  return extents;
}

/// Height of the node's proxy above (u, v) in its patch frame, NaN where it has none within
/// the support radius.
float patch_height(const ClusterNode& node, const PatchFrame& f, double u, double v) {
  constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
  const double radius = node.support.radius;
  const Proxy::Variant& proxy = node.proxy.variant();
  double h = 0;
  if (const auto* poly = std::get_if<PolyProxy>(&proxy)) {
    h = poly->height(u, v);
  } else if (std::holds_alternative<QuadricProxy>(proxy) || std::holds_alternative<CreaseProxy>(proxy)) {
    const Eigen::Vector3d x = f.origin + u * f.axes.col(0) + v * f.axes.col(1);
    const Eigen::Vector3d e3 = f.axes.col(2);
    const auto up = node.proxy.intersect(Ray{x, e3}, 0, radius);
    const auto down = node.proxy.intersect(Ray{x, -e3}, 0, radius);
    if (!up && !down) return kNone;
    h = up && (!down || *up <= *down) ? *up : -*down;
  }
  return std::isfinite(h) && std::abs(h) <= radius ? static_cast<float>(h) : kNone;
}

}  // namespace

PatchGrid patch_grid(const ClusterTree& tree, const PointCloud* cloud, const Eigen::Vector3d& center, std::size_t g) {
  const std::size_t n = tree.nodes.size();
  std::vector<std::optional<PatchFrame>> frames(n);
  for (std::size_t i = 0; i < n; ++i) frames[i] = patch_frame(tree.nodes[i]);
  std::vector<Extent> extents(n);
  if (cloud != nullptr) extents = cluster_extents(tree, cloud->positions, frames);
  std::vector<float> patch_frames(16 * n, 0.0f);
  std::vector<float> heights(g * g * n, std::numeric_limits<float>::quiet_NaN());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const auto& f = frames[i];
      Extent e = extents[i];
      if (cloud == nullptr && f) {  // no points: a square of the support's size
        const double s = 0.5 * tree.nodes[i].support.radius;
        e = Extent{-s, s, -s, s};
      }
      if (!f || !(e.umax > e.umin) || !(e.vmax > e.vmin)) continue;
      float* out = patch_frames.data() + 16 * i;
      for (int c = 0; c < 3; ++c) {
        out[c] = static_cast<float>(f->origin[c] - center[c]);
        for (int a = 0; a < 3; ++a) out[3 + 3 * a + c] = static_cast<float>(f->axes(c, a));
      }
      out[12] = static_cast<float>(e.umin), out[13] = static_cast<float>(e.umax);
      out[14] = static_cast<float>(e.vmin), out[15] = static_cast<float>(e.vmax);
      for (std::size_t a = 0; a < g; ++a)
        for (std::size_t b = 0; b < g; ++b) {
          const double u = e.umin + (e.umax - e.umin) * static_cast<double>(a) / static_cast<double>(g - 1);
          const double v = e.vmin + (e.vmax - e.vmin) * static_cast<double>(b) / static_cast<double>(g - 1);
          heights[g * g * i + a * g + b] = patch_height(tree.nodes[i], *f, u, v);
        }
    }
  });
  return {std::move(patch_frames), std::move(heights)};
}

}  // namespace clustersurf::detail
