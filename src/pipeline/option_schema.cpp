#include <clustersurf/core/errors.hpp>
#include <clustersurf/pipeline/option_schema.hpp>

#include "core/option_builders.hpp"

#include <cstdint>
#include <limits>

namespace clustersurf {

namespace {

using detail::unset_by_default;
using detail::with_alias;
using detail::with_words;

constexpr std::uint32_t kMaxUint32 = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint64_t kMaxSize = std::numeric_limits<std::int64_t>::max();

using Get = std::function<std::string(const ReconstructOptions&)>;
using Set = std::function<void(ReconstructOptions&, std::string_view)>;

OptionSpec spec(std::string name, OptionStage stage, OptionKind kind, std::string help, Get get, Set set) {
  return detail::spec<ReconstructOptions>(std::move(name), stage, kind, std::move(help), std::move(get),
                                          std::move(set));
}

template <class Field>
OptionSpec flag_spec(std::string name, OptionStage stage, std::string help, Field field, bool negated = false) {
  return detail::flag_spec<ReconstructOptions>(std::move(name), stage, std::move(help), field, negated);
}

template <class Field, class Parse>
OptionSpec word_spec(std::string name, OptionStage stage, std::vector<std::string> words, std::string help, Field field,
                     Parse parse) {
  return detail::word_spec<ReconstructOptions>(std::move(name), stage, std::move(words), std::move(help), field, parse);
}

BuildOptions& build(ReconstructOptions& o) { return o.build; }
const BuildOptions& build(const ReconstructOptions& o) { return o.build; }
SurfaceMeshOptions& meshing(ReconstructOptions& o) { return o.meshing; }
const SurfaceMeshOptions& meshing(const ReconstructOptions& o) { return o.meshing; }

/// A whole-number field of BuildOptions from `low` to `high`.
template <class T>
OptionSpec build_whole(std::string name, std::string help, T BuildOptions::*member, std::uint64_t low,
                       std::uint64_t high) {
  return spec(
      name, OptionStage::Build, OptionKind::Whole, std::move(help),
      [member](const ReconstructOptions& o) { return std::to_string(build(o).*member); },
      [member, name, low, high](ReconstructOptions& o, std::string_view text) {
        build(o).*member = static_cast<T>(parse_whole(name, text, low, high));
      });
}

/// A real field of BuildOptions within `bound`.
OptionSpec build_real(std::string name, std::string help, double BuildOptions::*member, RealBound bound) {
  return spec(
      name, OptionStage::Build, OptionKind::Number, std::move(help),
      [member](const ReconstructOptions& o) { return number_text(build(o).*member); },
      [member, name, bound](ReconstructOptions& o, std::string_view text) {
        build(o).*member = parse_real(name, text, bound);
      });
}

/// The build options on the proxies, the splitter and the leaves' error threshold.
std::vector<OptionSpec> build_threshold_options() {
  const BuildOptions defaults;
  std::vector<OptionSpec> out;
  out.push_back(word_spec(
      "proxy", OptionStage::Build, {"plane", "poly", "quadric"},
      "Proxy per cluster: plane, poly (bivariate quadratic) or quadric",
      [](auto& o) -> auto& { return build(o).proxy; }, parse_proxy_kind));
  out.push_back(word_spec(
      "splitter", OptionStage::Build, {"split-plane", "lloyd"}, "Cluster splitting: split-plane or lloyd",
      [](auto& o) -> auto& { return build(o).splitter; }, parse_splitter));
  out.push_back(with_alias(
      with_words(
          spec(
              "tolerance", OptionStage::Build, OptionKind::Number,
              "The error a leaf may keep beyond the estimated scanner noise, as a fraction of the bbox diagonal (a "
              "leaf's RMS error must be <= hypot(tolerance, noise)); auto = " +
                  number_text(defaults.tolerance),
              [](const ReconstructOptions& o) {
                const BuildOptions& b = build(o);
                return b.threshold_mode == ThresholdMode::Absolute || b.tolerance == BuildOptions{}.tolerance
                           ? std::string("auto")
                           : number_text(b.tolerance);
              },
              [](ReconstructOptions& o, std::string_view text) {
                BuildOptions& b = build(o);
                if (text == "auto") {
                  b.tolerance = BuildOptions{}.tolerance;
                  return;
                }
                b.tolerance = parse_real("tolerance", text, RealBound::NonNegative, "auto");
              }),
          {"auto"}),
      "max_error"));
  out.push_back(with_alias(unset_by_default(spec(
                               "absolute_tolerance", OptionStage::Build, OptionKind::Number,
                               "Leaf error threshold in the input's units, noise included (overrides tolerance)",
                               [](const ReconstructOptions& o) {
                                 const BuildOptions& b = build(o);
                                 return b.threshold_mode == ThresholdMode::Absolute ? number_text(b.tolerance)
                                                                                    : std::string();
                               },
                               [](ReconstructOptions& o, std::string_view text) {
                                 BuildOptions& b = build(o);
                                 b.tolerance = parse_real("absolute_tolerance", text, RealBound::NonNegative);
                                 b.threshold_mode = ThresholdMode::Absolute;
                               })),
                           "absolute_error"));
  out.push_back(word_spec(
      "error", OptionStage::Build, {"rms", "max"}, "Error compared with the threshold: rms or max",
      [](auto& o) -> auto& { return build(o).metric; }, parse_error_metric));
  out.push_back(with_words(
      spec(
          "min_points", OptionStage::Build, OptionKind::Whole,
          "No cluster below this many points, or auto: from the estimated noise against the point spacing (12 for "
          "clean or sparse data up to 20 for noise of half a spacing or more), and two thirds of that where relief "
          "finer than the clusters needs it",
          [](const ReconstructOptions& o) {
            const std::uint32_t n = build(o).min_points;
            return n == 0 ? std::string("auto") : std::to_string(n);
          },
          [](ReconstructOptions& o, std::string_view text) {
            build(o).min_points =
                text == "auto" ? 0 : static_cast<std::uint32_t>(parse_whole("min_points", text, 1, 1u << 30, "auto"));
          }),
      {"auto"}));
  return out;
}

/// The build options on the tree's depth, the splitter's search, the supports and the inputs' use.
std::vector<OptionSpec> build_fit_options() {
  std::vector<OptionSpec> out;
  out.push_back(build_whole("max_depth", "Maximum tree depth", &BuildOptions::max_depth, 0, kMaxUint32));
  out.push_back(with_words(
      spec(
          "alpha", OptionStage::Build, OptionKind::Number,
          "Support radius = alpha x cluster bbox diagonal, or auto: from the estimated noise against the point "
          "spacing (0.75 for clean or sparse data up to 1 for noise of half a spacing or more)",
          [](const ReconstructOptions& o) {
            const double a = build(o).alpha;
            return a == 0 ? std::string("auto") : number_text(a);
          },
          [](ReconstructOptions& o, std::string_view text) {
            build(o).alpha = text == "auto" ? 0 : parse_real("alpha", text, RealBound::Positive, "auto");
          }),
      {"auto"}));
  out.push_back(build_whole("kstep", "Split-plane sweep step (0: at most 64 candidates per split)",
                            &BuildOptions::kstep, 0, kMaxUint32));
  out.push_back(
      build_whole("lloyd_restarts", "Lloyd splitter: 2-means restarts", &BuildOptions::lloyd_restarts, 1, 1000));
  out.push_back(build_whole("proxy_lloyd", "Lloyd splitter: proxy-Lloyd refinement rounds",
                            &BuildOptions::proxy_lloyd_iterations, 0, kMaxUint32));
  out.push_back(build_real("noise_factor",
                           "Noise counted in the threshold = this x the estimated noise (0: ignore the noise, no "
                           "estimate)",
                           &BuildOptions::noise_factor, RealBound::NonNegative));
  out.push_back(build_real("support_factor",
                           "A leaf's weighted RMS error over the points in its support sphere must be <= this x the "
                           "threshold (0: no check)",
                           &BuildOptions::support_factor, RealBound::NonNegative));
  out.push_back(build_whole("support_points",
                            "A leaf's support grows until it holds this many input points (MPU's N_min; 0: no growth)",
                            &BuildOptions::support_points, 0, kMaxUint32));
  out.push_back(build_whole("seed", "Seed for every random choice", &BuildOptions::seed, 0,
                            std::numeric_limits<std::uint64_t>::max()));
  out.push_back(flag_spec(
      "ignore_normals", OptionStage::Build, "Orient by propagation even when the input has normals",
      [](auto& o) -> auto& { return build(o).use_normals; }, true));
  out.push_back(flag_spec(
      "no_creases", OptionStage::Build,
      "No crease leaves: a cluster on the two faces of a sharp edge is split like any other instead of fitted by two "
      "planes meeting at the edge",
      [](auto& o) -> auto& { return build(o).creases; }, true));
  out.push_back(flag_spec(
      "keep_outliers", OptionStage::Build,
      "Cluster every input point; by default isolated points (mean distance to their 8 nearest neighbours over 3x "
      "their neighbours' or 6x the cloud's median) are left out",
      [](auto& o) -> auto& { return build(o).remove_outliers; }, true));
  out.push_back(flag_spec(
      "no_point_leaves", OptionStage::Build, "Do not store each point's leaf in the tree file",
      [](auto& o) -> auto& { return build(o).keep_point_leaves; }, true));
  return out;
}

/// An optional real field of SurfaceMeshOptions, unset by default.
OptionSpec optional_real(std::string name, std::string help, std::optional<double>& (*field)(ReconstructOptions&),
                         const std::optional<double>& (*read)(const ReconstructOptions&), RealBound bound) {
  return unset_by_default(spec(
      name, OptionStage::Mesh, OptionKind::Number, std::move(help),
      [read](const ReconstructOptions& o) {
        const std::optional<double>& v = read(o);
        return v ? number_text(*v) : std::string();
      },
      [field, name, bound](ReconstructOptions& o, std::string_view text) {
        field(o) = parse_real(name, text, bound);
      }));
}

std::vector<OptionSpec> mesh_options() {
  const SurfaceMeshOptions defaults;
  std::vector<OptionSpec> out;
  out.push_back(with_words(
      spec(
          "resolution", OptionStage::Mesh, OptionKind::Whole,
          "Mesh grid cells along the longest bbox side (2 to 100000), or auto: cells two median point spacings of "
          "the input wide, finer (down to one spacing) where the leaves' curvature needs it (a cell at most half "
          "the radius of curvature of 90 % of their area), coarser where clumped points would give over 4 "
          "surface cells per point (the spacing stored in the tree; a version-1 tree file without its points gets " +
              std::to_string(defaults.grid.resolution) + " cells)",
          [](const ReconstructOptions& o) {
            const SurfaceMeshOptions& m = meshing(o);
            return m.auto_resolution ? std::string("auto") : std::to_string(m.grid.resolution);
          },
          [](ReconstructOptions& o, std::string_view text) {
            SurfaceMeshOptions& m = meshing(o);
            m.auto_resolution = text == "auto";
            m.grid.resolution = m.auto_resolution
                                    ? SurfaceMeshOptions{}.grid.resolution
                                    : static_cast<std::uint32_t>(parse_whole("resolution", text, 2, 100000, "auto"));
          }),
      {"auto"}));
  out.push_back(optional_real(
      "voxel_size", "Mesh grid cell size (overrides resolution)",
      [](ReconstructOptions& o) -> std::optional<double>& { return meshing(o).grid.voxel_size; },
      [](const ReconstructOptions& o) -> const std::optional<double>& { return meshing(o).grid.voxel_size; },
      RealBound::Positive));
  out.push_back(unset_by_default(spec(
      "lod_depth", OptionStage::Mesh, OptionKind::Whole, "Blend the tree cut at this depth instead of the leaves",
      [](const ReconstructOptions& o) {
        const auto& d = meshing(o).lod_depth;
        return d ? std::to_string(*d) : std::string();
      },
      [](ReconstructOptions& o, std::string_view text) {
        meshing(o).lod_depth = static_cast<std::uint32_t>(parse_whole("lod_depth", text, 0, kMaxUint32));
      })));
  out.push_back(optional_real(
      "lod_error", "Blend the shallowest nodes with error <= this fraction of the diagonal",
      [](ReconstructOptions& o) -> std::optional<double>& { return meshing(o).lod_error; },
      [](const ReconstructOptions& o) -> const std::optional<double>& { return meshing(o).lod_error; },
      RealBound::NonNegative));
  out.push_back(word_spec(
      "color", OptionStage::Mesh, {"input", "none", "leaf", "distance", "intensity"},
      "Vertex colors: input (the input points' own colors, when they have them: a scan's RGB), none, leaf (per "
      "blended node), distance (to the input points) or intensity (the scanner's intensity as grey; in core only)",
      [](auto& o) -> auto& { return meshing(o).coloring; }, parse_mesh_coloring));
  return out;
}

/// A real field of the mesh options (`field(o)` gives it) within `bound`.
template <class Field>
OptionSpec mesh_real(std::string name, std::string help, Field field, RealBound bound) {
  return spec(
      name, OptionStage::Mesh, OptionKind::Number, std::move(help),
      [field](const ReconstructOptions& o) { return number_text(field(o)); },
      [field, name, bound](ReconstructOptions& o, std::string_view text) { field(o) = parse_real(name, text, bound); });
}

/// The mesh options on the trim, the closing and the decimation.
std::vector<OptionSpec> mesh_finishing_options() {
  std::vector<OptionSpec> out;
  out.push_back(mesh_real(
      "trim",
      "Drop triangles farther from the input points than this x the nearest point's spread (mean distance to its 8 "
      "neighbours), where the data stops (up to 1.5x that where the data lies all around: a gap between samples), "
      "and within that reach the flaps that stand more than a spread off the sheet the points form; needs the input "
      "points. 0 keeps every triangle",
      [](auto& o) -> auto& { return meshing(o).trim.spread_factor; }, RealBound::NonNegative));
  out.push_back(mesh_real(
      "max_reach_spreads",
      "The trim's reach never exceeds this many typical spreads of the points over the surface, where they thin out "
      "(a scan's rim seen at a grazing angle) and their spread grows; 0: no bound",
      [](auto& o) -> auto& { return meshing(o).trim.max_reach_spreads; }, RealBound::NonNegative));
  out.push_back(spec(
      "min_component_points", OptionStage::Mesh, OptionKind::Whole,
      "Drop loose fragments on which fewer than this many input points lie nearest (needs the input points, as trim "
      "does). 0 keeps every fragment",
      [](const ReconstructOptions& o) { return std::to_string(meshing(o).trim.min_component_points); },
      [](ReconstructOptions& o, std::string_view text) {
        meshing(o).trim.min_component_points = parse_whole("min_component_points", text, 0, kMaxSize);
      }));
  out.push_back(flag_spec(
      "close_pinholes", OptionStage::Mesh,
      "Close the small holes the input points cover with a fan each (fewer boundary edges, a little less accuracy; "
      "needs the input points, as trim does)",
      [](auto& o) -> auto& { return meshing(o).trim.close_pinholes; }));
  out.push_back(mesh_real(
      "coarsen",
      "Merge the vertices of flat blocks of the mesh's grid (2, 4, … cells wide: coarsen_levels sizes) into one "
      "each, moving the surface by at most this share of the input's estimated noise (without an estimate, of the "
      "error a leaf may keep): fewer triangles where the surface is flat against the noise (tiled meshes keep "
      "every vertex near their regions' borders). 0 keeps every vertex",
      [](auto& o) -> auto& { return meshing(o).coarsening.noise_share; }, RealBound::NonNegative));
  out.push_back(spec(
      "coarsen_levels", OptionStage::Mesh, OptionKind::Whole,
      "How many block sizes coarsen tries: blocks of 2, 4, … up to 2^coarsen_levels grid cells",
      [](const ReconstructOptions& o) { return std::to_string(meshing(o).coarsening.levels); },
      [](ReconstructOptions& o, std::string_view text) {
        meshing(o).coarsening.levels =
            static_cast<std::uint32_t>(parse_whole("coarsen_levels", text, 1, kMaxCoarseningLevels));
      }));
  out.push_back(spec(
      "refit_points", OptionStage::Mesh, OptionKind::Whole,
      "Move each vertex towards a quadratic fitted to this many nearest input points, or to twice as many where that "
      "wider fit agrees with the narrow one within its confidence interval, by the share of the move that stands "
      "above the estimated noise (needs the input points, as trim does). 0 keeps the vertices where the leaves' "
      "blend puts them",
      [](const ReconstructOptions& o) { return std::to_string(meshing(o).refit.points); },
      [](ReconstructOptions& o, std::string_view text) {
        meshing(o).refit.points = static_cast<std::uint32_t>(parse_whole("refit_points", text, 0, kMaxUint32));
        check_refit_options(meshing(o).refit);
      }));
  out.push_back(flag_spec(
      "no_chord_offset", OptionStage::Mesh,
      "Leave the vertices on the fitted surface; by default each moves along its normal by the mean sag of its "
      "triangles' chords under the curved surface, so that the triangles straddle it rather than cut under it",
      [](auto& o) -> auto& { return meshing(o).refit.chord_offset; }, true));
  out.push_back(spec(
      "decimate", OptionStage::Mesh, OptionKind::Whole,
      "Reduce the mesh to at most this many triangles (edge collapses that keep vertices in place and the mesh's "
      "rims fixed). 0 keeps them all",
      [](const ReconstructOptions& o) { return std::to_string(meshing(o).decimation.target_triangles); },
      [](ReconstructOptions& o, std::string_view text) {
        meshing(o).decimation.target_triangles = parse_whole("decimate", text, 0, kMaxSize);
      }));
  out.push_back(mesh_real(
      "decimate_tolerance",
      "Reduce the mesh while the surface moves by at most this distance (input units); with decimate, stop at "
      "whichever comes first. 0: no such reduction",
      [](auto& o) -> auto& { return meshing(o).decimation.max_deviation; }, RealBound::NonNegative));
  out.push_back(flag_spec(
      "watertight", OptionStage::Mesh,
      "A closed, manifold mesh whatever holes the data has: where the leaves define the surface it is the same; "
      "elsewhere the surface is filled smoothly and its vertices are marked (\"filled\")",
      [](auto& o) -> auto& { return meshing(o).closing.enabled; }));
  out.push_back(mesh_real(
      "fill_holes",
      "With watertight: fill only holes up to this size (input units); larger openings stay open. 0 fills every "
      "hole",
      [](auto& o) -> auto& { return meshing(o).closing.max_hole_size; }, RealBound::NonNegative));
  return out;
}

}  // namespace

std::vector<OptionSpec> reconstruct_option_schema() {
  std::vector<OptionSpec> out = build_threshold_options();
  for (auto* part : {&build_fit_options, &mesh_options, &mesh_finishing_options})
    for (OptionSpec& s : part()) out.push_back(std::move(s));
  return out;
}

void set_options(ReconstructOptions& o, const OptionValues& values, std::vector<OptionStage> stages) {
  set_options(o, reconstruct_option_schema(), values, stages);
}

}  // namespace clustersurf
