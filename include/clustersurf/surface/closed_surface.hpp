#pragma once
// Inside and outside everywhere: the blend f of an ImplicitSurface extended to the whole of
// space, so that its zero set is closed whatever holes the data has. Where f is defined it is
// kept as it is; elsewhere (unscanned holes, the inside of a closed part beyond every support)
// a harmonic fill takes over: on a coarse grid over the bounding box, the nodes where f is
// undefined solve Laplace's equation with f as boundary values at the nodes where it is
// defined and no flux through the grid's border; beyond the grid everything is outside (Davis,
// Marschner, Garr & Levoy 2002, volumetric
// diffusion; here on the tree's blend instead of line-of-sight distances). A hole then closes
// with the smoothest field that agrees with the surface around it, like a soap film bounded
// by the hole's rim, and the inside of a part stays inside. Between the two, where the blend's
// weight falls below its confidence floor, f fades into the fill, so F has no seam (a jump
// there would be a zero crossing of its own: sheets along the rims, handles).

#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/core/progress.hpp>
#include <clustersurf/surface/implicit_surface.hpp>

#include <cstdint>
#include <vector>

namespace clustersurf {

/// Options of closing a surface (ClosedSurface, `--watertight`).
struct ClosingOptions {
  /// Close the mesh (mesh_tree(), `--watertight`). Off by default: holes stay where no
  /// scanner saw the surface.
  bool enabled = false;
  /// Fill only holes whose filled patch spans at most this distance (input units; the
  /// patch's bounding-box diagonal); larger openings stay open. 0: fill every hole.
  double max_hole_size = 0;
  /// Cells of the fill grid along the longest side of the bounding box. The fill is smooth,
  /// so a coarse grid serves; the surface where f is defined keeps the mesher's resolution.
  std::uint32_t resolution = 128;
};

/// Calls f(name, field) for every field of `o`, in declaration order.
template <OptionsOf<ClosingOptions> Options, class F>
void for_each_field(Options& o, F&& f) {
  f("enabled", o.enabled);
  f("max_hole_size", o.max_hole_size);
  f("resolution", o.resolution);
}

/// F: the blend where it is defined (total weight above min_weight), the harmonic fill where
/// no support reaches, and between them the two mixed by smoothstep(weight / min_weight): with
/// min_weight > 0, F is continuous inside the fill grid. Positive outside. Immutable once built;
/// value() and inside() are thread-safe.
class ClosedSurface {
 public:
  /// Builds the fill grid (evaluating f at its nodes, then solving). Deterministic and
  /// independent of the thread count. Throws OptionError for a resolution below 8 or above
  /// 1024 or a negative or non-finite `min_weight`, Cancelled when `progress` says stop.
  ClosedSurface(const ImplicitSurface& surface, const ClosingOptions& options = {}, double min_weight = kMinWeight,
                const ProgressCallback& progress = {});

  /// F at x: f where the blend is defined, the fill (trilinear on the grid) where no support
  /// reaches, the two mixed below the confidence floor; beyond the grid, positive (outside),
  /// growing with the distance to it.
  double value(const Eigen::Vector3d& x) const;
  /// The fill alone at x (what value() returns where no support reaches).
  double fill_value(const Eigen::Vector3d& x) const;
  /// Whether x lies inside the closed surface (F < 0).
  bool inside(const Eigen::Vector3d& x) const { return value(x) < 0; }
  /// Whether F at x is (at least in part) the fill, not f: the blend is not above its
  /// confidence floor there, or x lies beyond the fill grid.
  bool filled(const Eigen::Vector3d& x) const;

  const ImplicitSurface& surface() const noexcept { return *surface_; }
  /// The fill grid's cell size.
  double cell_size() const noexcept { return cell_; }
  /// How many grid nodes the fill solved for (where f is undefined).
  std::size_t filled_nodes() const noexcept { return unknowns_; }

 private:
  double node(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return grid_[static_cast<std::size_t>((k * dims_[1] + j) * dims_[0] + i)];
  }

  const ImplicitSurface* surface_;
  /// Whether x lies inside the fill grid (its border included).
  bool in_grid(const Eigen::Vector3d& x) const;

  double min_weight_;
  Eigen::Vector3d corner_;  // the grid's first node
  double cell_ = 0;
  std::int64_t dims_[3] = {0, 0, 0};  // nodes per axis
  std::vector<float> grid_;           // F at the nodes, x fastest
  double outside_ = 0;                // the value on the grid's border
  std::size_t unknowns_ = 0;
};

}  // namespace clustersurf
