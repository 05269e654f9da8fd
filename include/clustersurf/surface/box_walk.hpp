#pragma once
// The walk of an implicit surface's tree for every point of one box, done once: what the
// mesher's blocks of grid corners share.

#include <clustersurf/surface/implicit_surface.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf {

/// The walk for every point of one box, done once. Queries in a small box (a block of mesh
/// grid corners) repeat most of the same descent from the root; a BoxWalk keeps the cut nodes
/// whose supports may reach into the box, in the walk's order, and the bounding spheres that
/// part of the box lies outside of (the others are passed by all of it or by none of it, beyond
/// any rounding). A query through it visits the same nodes in the same order as
/// for_each_support(), so it gives the same values to the bit; a point outside the box is
/// walked from the root. Holds a reference to the surface, which must outlive it and stay
/// unchanged (not be assigned another surface).
class ImplicitSurface::BoxWalk {
 public:
  /// The walk of `surface` for the points of `box` (closed: its faces included). An empty box
  /// keeps nothing: every query is walked from the root.
  BoxWalk(const ImplicitSurface& surface, const BoundingBox& box);

  /// for_each_support() of the surface at x.
  template <class Visit>
  void for_each_support(const Eigen::Vector3d& x, Visit&& visit) const;
  /// The surface it walks.
  const ImplicitSurface& surface() const noexcept { return *surface_; }
  /// Whether a query at x goes through the box's walk (x in the box) rather than from the root.
  bool covers(const Eigen::Vector3d& x) const noexcept {
    return (x.array() >= box_.min.array()).all() && (x.array() <= box_.max.array()).all();
  }
  /// The nodes kept (each tested or visited per query in the box).
  std::size_t size() const noexcept { return steps_.size(); }

 private:
  /// A node of the walk: `test`: x must lie inside its bounding sphere, else the walk goes on
  /// at `skip` (past its subtree); `visit`: a cut node, its support tested and visited.
  struct Step {
    std::int32_t node;
    std::int32_t skip;
    bool test;
    bool visit;
  };
  const ImplicitSurface* surface_;
  BoundingBox box_;
  std::vector<Step> steps_;
};

template <class Visit>
void ImplicitSurface::BoxWalk::for_each_support(const Eigen::Vector3d& x, Visit&& visit) const {
  if (!covers(x)) {
    surface_->for_each_support(x, visit);
    return;
  }
  for (std::size_t k = 0; k < steps_.size();) {
    const Step& step = steps_[k];
    if (step.test && !surface_->bound(step.node).contains(x)) {
      k = static_cast<std::size_t>(step.skip);
      continue;
    }
    if (step.visit) surface_->visit_support(step.node, x, visit);
    ++k;
  }
}

}  // namespace clustersurf
