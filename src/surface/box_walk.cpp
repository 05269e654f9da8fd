// The walk of the implicit surface's tree for every point of one box, done once.

#include <clustersurf/surface/box_walk.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace clustersurf {

namespace {

/// How much of a box lies inside a sphere, judged with a relative guard far above the rounding
/// of the sphere test (a few units in the last place): All and None hold for the test as
/// computed at every point of the box; Part leaves the test to each point.
enum class Reach { None, Part, All };

/// Rounding guard of reach(): the nearest and farthest squared distances from the sphere's
/// center to the box must clear r² by this fraction of it.
constexpr double kRoundingGuard = 1e-9;

Reach reach(const Sphere& sphere, const BoundingBox& box) {
  double nearest = 0, farthest = 0;
  for (int a = 0; a < 3; ++a) {
    const double below = box.min(a) - sphere.center(a), above = sphere.center(a) - box.max(a);
    const double gap = std::max({below, above, 0.0});
    const double span = std::max(sphere.center(a) - box.min(a), box.max(a) - sphere.center(a));
    nearest += gap * gap;
    farthest += span * span;
  }
  const double r2 = sphere.radius * sphere.radius;
  if (!(r2 >= std::numeric_limits<double>::min())) return Reach::Part;  // a relative guard needs a normal r²
  if (nearest > r2 * (1 + kRoundingGuard)) return Reach::None;
  if (farthest < r2 * (1 - kRoundingGuard)) return Reach::All;
  return Reach::Part;
}

}  // namespace

ImplicitSurface::BoxWalk::BoxWalk(const ImplicitSurface& surface, const BoundingBox& box)
    : surface_(&surface), box_(box) {
  if (surface.walk_nodes_.empty() || box.empty()) return;
  // The walk's pre-order (left subtree first). A negative entry −1 − k closes the subtree of
  // step k: a point outside its bounding sphere goes on after it.
  std::vector<std::int32_t> stack{0};
  while (!stack.empty()) {
    const std::int32_t i = stack.back();
    stack.pop_back();
    if (i < 0) {
      steps_[static_cast<std::size_t>(-1 - i)].skip = static_cast<std::int32_t>(steps_.size());
      continue;
    }
    const WalkNode& n = surface.walk_nodes_[static_cast<std::size_t>(i)];
    const Reach bound = reach(n.bound, box);
    if (bound == Reach::None) continue;
    const bool test = bound == Reach::Part;
    if (n.in_cut) {
      // A support that misses the whole box is never visited from it.
      if (reach(surface.supports_[static_cast<std::size_t>(i)], box) != Reach::None)
        steps_.push_back({i, static_cast<std::int32_t>(steps_.size() + 1), test, true});
      continue;
    }
    if (n.left < 0) continue;
    if (test) {
      stack.push_back(-1 - static_cast<std::int32_t>(steps_.size()));
      steps_.push_back({i, 0, true, false});
    }
    stack.push_back(n.right);
    stack.push_back(n.left);
  }
}

}  // namespace clustersurf
