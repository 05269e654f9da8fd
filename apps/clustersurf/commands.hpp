#pragma once
// The subcommands of the CLI. Each takes its parsed arguments and returns the exit code;
// failures are thrown as clustersurf::Error and turned into messages once, in main().

#include "console.hpp"

#include <clustersurf/evaluation/range_scan.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/io/surface_sampling.hpp>
#include <clustersurf/pipeline/option_schema.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/render/render_option_schema.hpp>
#include <clustersurf/view/html_viewer.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf::cli {

/// Arguments shared by commands that read a point cloud.
struct InputArgs {
  std::string file;
  bool drop_non_finite = false;
  std::size_t mesh_samples = ReadOptions{}.mesh_samples;
};

/// Options of the mesh stage, shared by `mesh` and `reconstruct --mesh`: the option schema's
/// mesh options as given (set_options()) and how to write the mesh.
struct MeshArgs {
  OptionValues options;  // the schema's mesh-stage options given, as text
  std::string points;    // input cloud for the trim and the input or distance colors (mesh command)
  bool ascii = false;
};

struct ConvertArgs {
  InputArgs input;
  std::string output;
  std::optional<std::size_t> subsample;
  std::optional<double> voxel;
  std::uint64_t seed = 1;
  bool ascii = false;
  bool double_precision = false;
};
int run_convert(Console& console, const ConvertArgs& args);

struct StatsArgs {
  InputArgs input;
};
int run_stats(Console& console, const StatsArgs& args);

/// `reconstruct`: the option schema's build options as given, the mesh stage's and the
/// out-of-core run's.
struct ReconstructArgs {
  InputArgs input;
  std::string tree_output;  // .cstree (optional when mesh_output is given)
  std::string mesh_output;  // .ply/.obj (optional)
  MeshArgs mesh;
  OptionValues build;        // the schema's build-stage options given, as text
  std::string memory_limit;  // parse_memory_size(); empty: in core
  std::string work_dir;      // out of core: the run's files (default: the output's name + .work)
  bool keep_work_dir = false;
};
int run_reconstruct(Console& console, const ReconstructArgs& args);

struct InfoArgs {
  std::string tree;
};
int run_info(Console& console, const InfoArgs& args);

struct MeshCommandArgs {
  std::string tree;
  std::string output;
  MeshArgs mesh;
};
int run_mesh(Console& console, const MeshCommandArgs& args);

struct SampleArgs {
  std::string mesh;
  std::string output;
  std::size_t count = SurfaceSamplingOptions{}.count;
  double noise = SurfaceSamplingOptions{}.noise;
  double outliers = SurfaceSamplingOptions{}.outliers;
  std::uint64_t seed = SurfaceSamplingOptions{}.seed;
  bool ascii = false;
  bool no_normals = false;
  std::size_t scanner = 0;  // 0: area-uniform samples; N: a virtual range scanner at N viewpoints
  double registration = RangeScanOptions{}.registration;
  double noise_correlation = RangeScanOptions{}.noise_correlation;
  double flipped_normals = RangeScanOptions{}.flipped_normals;
  double scanner_distance = RangeScanOptions{}.distance;
};
int run_sample(Console& console, const SampleArgs& args);

struct EvalArgs {
  std::string reconstruction;
  std::string reference;
  std::size_t samples = ComparisonOptions{}.samples;
  std::uint64_t seed = ComparisonOptions{}.seed;
};
int run_eval(Console& console, const EvalArgs& args);

/// `check`: is a mesh ready to print (check_mesh()); reports only, exit code 0 either way.
struct CheckArgs {
  std::string mesh;
};
int run_check(Console& console, const CheckArgs& args);

struct RenderArgs {
  std::vector<std::string> inputs;  // tree files (.cstree), meshes or point clouds
  std::string output;               // .png
  OptionValues options;             // render_option_schema()'s, as given
  std::string points;               // input cloud for the error view
  std::optional<std::uint32_t> lod_depth;
  std::optional<double> lod_error;  // fraction of the bbox diagonal
  bool grid = false;
  int columns = 0;
};
int run_render(Console& console, const RenderArgs& args);

struct ViewArgs {
  std::string tree;    // .cstree
  std::string output;  // .html
  std::string points;  // the tree's input cloud (optional: without it, no points are shown)
  std::string mesh;    // .ply/.obj (optional)
  std::size_t max_points = ViewerOptions{}.max_points;  // 0: all
};
int run_view(Console& console, const ViewArgs& args);

}  // namespace clustersurf::cli
