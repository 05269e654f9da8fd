#pragma once
// A tiled reconstruction on disk: the input partitioned into region files, then each region
// surveyed, built and meshed as a task of its own that reads and writes files in one work
// directory. Run one task after another, the whole stays within a memory limit (out-of-core);
// run the tasks of a stage in parallel, on machines sharing the directory, it is distributed
// (the Python module clustersurf.distributed runs them on Dask).

#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/regions/regions.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace clustersurf {

/// Options of TiledRun::partition().
struct PartitionOptions {
  RegionOptions regions;
  /// Points read from the input per block.
  std::size_t block_points = 1u << 20;
  /// Memory for the region files' write buffers, shared by all regions.
  std::size_t buffer_bytes = 256u << 20;
  ReadOptions read;
};

/// The most points a region may hold with its halo for its build and its tile to fit in
/// `memory_limit` bytes: kRegionBytesPerPoint per point (the points, their k-d trees, the tree
/// under construction, the tile's lattice and mesh) over kProcessBytes (the program itself),
/// as measured on 100 M points. Throws OptionError for a limit under 128 MiB.
std::uint64_t region_points_for_memory(std::uint64_t memory_limit);
inline constexpr std::uint64_t kRegionBytesPerPoint = 1400;
inline constexpr std::uint64_t kProcessBytes = std::uint64_t{64} << 20;

/// A size in bytes from text: a number with an optional suffix K, M, G or T (powers of 1024),
/// e.g. "4G" or "512M". Throws OptionError otherwise.
std::uint64_t parse_memory_size(std::string_view text);
/// `bytes` as parse_memory_size() reads it back exactly: with the largest suffix that divides it
/// ("4G", "512M"), else in bytes.
std::string format_memory_size(std::uint64_t bytes);

/// Where an out-of-core run writing `output` (its mesh, else its tree) keeps its files when
/// OutOfCoreOptions::work_directory is not given: the output's name + ".work".
std::filesystem::path default_work_directory(const std::filesystem::path& output);

/// The options that decide what a tiled run stores, as text, one "name value" line per field
/// (TiledRun::claim() keeps it in options.txt): every field of `options`, found through the
/// structs' for_each_field(), but whether to mesh, the walk's memory guard and what the join
/// applies to the welded tiles (closing, decimation, the distance colors' scale). A field added
/// to an option struct is in it without more code.
std::string options_fingerprint(const ReconstructOptions& options);

/// A mesh a tiled run wrote to a file, and what made it.
struct WrittenMesh {
  std::filesystem::path file;
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t removed_components = 0;  ///< fragments the data did not support
  /// Joined straight into the file (binary PLY without decimation), never whole in memory.
  bool streamed = false;
  std::size_t blended_nodes = 0;
  MeshReport grid;              ///< the tiles' cells and corners, summed
  CoarseningReport coarsening;  ///< the tiles' merges, summed (triangles before and after: those the tiles own)
  DecimationReport decimation;
  double seconds = 0;
};

/// The report of `mesh` as one JSON object, the same for every front end: file, vertices,
/// triangles, streamed, blended_nodes, voxel_size, surface_cells, removed_components,
/// coarsened_from_triangles, coarsening_tolerance and mesh_seconds.
std::string written_mesh_json(const WrittenMesh& mesh);

/// A work directory of a tiled reconstruction. Every task writes its result atomically (a
/// temporary file renamed into place) and does nothing when that result is already there, so
/// a task that failed can simply run again, and a run started again redoes only what is
/// missing. Tasks of one stage are independent of each other; a stage needs the results of
/// the one before (InputError naming the missing file otherwise).
///
/// Files: clustersurf-run.txt (the run record, first), plan.txt (the partition, written last), region-R.own /
/// region-R.halo (points), survey-R.txt, tree-R.cstree and orientation-R.txt, merge.txt and tree.cstree (merged),
/// tile-R.bin.
class TiledRun {
 public:
  /// Partitions `input` into region files under `directory` (created if missing): one pass
  /// over the input for its count, bounding box and an even sample, the plan (plan_regions()),
  /// and one pass writing each point to its region's file and to the halo files of the regions
  /// near it. A directory already holding a partition of the same input (same size and
  /// modification time) and options is reused as it is; one holding another input's or other
  /// options' partition is an OptionError. A directory that is not a run's is used alongside
  /// the files it holds (none is touched), unless one of them has the name of a run's file
  /// (OptionError, before anything is written); a path that is not a directory is an
  /// OptionError. The run's directory() is the canonical path of `directory`, and only the
  /// levels of it that did not exist are made (and counted as the run's). Throws IoError,
  /// InputError, OptionError, Cancelled.
  static TiledRun partition(const std::filesystem::path& input, const std::filesystem::path& directory,
                            const PartitionOptions& options = {}, const ProgressCallback& progress = {});

  /// Opens a partitioned directory; InputError when its plan is missing or malformed.
  explicit TiledRun(const std::filesystem::path& directory);
  ~TiledRun();
  TiledRun(TiledRun&&) noexcept;
  TiledRun& operator=(TiledRun&&) noexcept;

  const std::filesystem::path& directory() const noexcept;
  const RegionPlan& plan() const noexcept;
  std::size_t regions() const noexcept { return plan().regions(); }
  /// Points in the input, and whether they carry normals.
  std::uint64_t input_points() const noexcept;
  bool has_normals() const noexcept;
  /// Where the region files' positions are relative to (the input's origin_shift()).
  const Eigen::Vector3d& origin() const noexcept;

  /// The points of a region (own, then halo), relative to origin(). InputError when a region
  /// file is missing, truncated or not a region file.
  RegionCloud load(std::int32_t region) const;

  /// Stage 1, per region: survey_region() → survey-R.txt.
  void survey(std::int32_t region, const BuildOptions& options) const;
  /// The scale every region's build shares (combine_surveys() of every survey).
  CloudScale scale() const;
  /// Stage 2, per region: outliers marked and the subtree built (build_region_tree()) →
  /// orientation-R.txt, tree-R.cstree. The point-leaf table is not kept.
  void build(std::int32_t region, const BuildOptions& options) const;
  /// Stage 3, once: merge_region_trees() → merge.txt (how it merged), then tree.cstree;
  /// returns the merged tree (read from its file when the merge was done before).
  ClusterTree merge() const;
  /// How the merge joined the regions (merge.txt), all the mesh tasks need besides the region
  /// trees their tiles meet (tile_regions(), tile_tree()).
  RegionMerge merge_record() const;
  /// The regions' orientation reports summed (after every build): normals or scanners when
  /// every non-empty region used them.
  OrientationReport orientation() const;
  /// Stage 4, per region: mesh_tile() → tile-R.bin, of the tile's tree (tile_tree() of the
  /// region trees tile_regions() names: the merged tree's tile, to the bit, without holding
  /// the merged tree), the region's outliers marked as its build did (options.build). The lattice's cell:
  /// options.meshing.grid's voxel size, else from the tree's spacing (auto resolution), else its resolution along the
  /// longest side.
  void mesh(std::int32_t region, const ReconstructOptions& options) const;
  /// Stage 5, once: join_tiles(), decimated and colored as mesh_tree() does, with the tree's
  /// origin (only colors by node read the merged tree). Returns the mesh and what made it.
  SurfaceMesh join(const SurfaceMeshOptions& options) const;
  /// Stage 5 into a file (format by extension): a binary PLY without decimation is joined
  /// straight into it, tile by tile (join_tiles_to_ply(): the same bytes as join() written,
  /// never the whole mesh in memory); any other mesh is join()'s, written with `ply`.
  WrittenMesh write_mesh(const std::filesystem::path& file, const SurfaceMeshOptions& options,
                         const PlyWriteOptions& ply = {}) const;

  /// OptionError when `file`, an output of the run, would be one of the run's own files in its
  /// directory (the clean-up would remove it); write_mesh() checks its file so.
  void check_output(const std::filesystem::path& file) const;

  /// The bytes of the run's files in its directory now (no other file is counted).
  std::uintmax_t file_bytes() const;

  /// Whether a region's stage result is there: "survey", "build" or "mesh".
  bool done(std::string_view stage, std::int32_t region) const;

  /// Records the options of the run (options.txt), or, when the directory already holds
  /// results, checks that they were made with the same: OptionError otherwise (a resumed run
  /// must not mix results of different options).
  void claim(const ReconstructOptions& options) const;

 private:
  struct Impl;
  explicit TiledRun(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Removes what a tiled run made in `directory`: the files it wrote there (named by its run
/// record, clustersurf-run.txt), the temporary files of its writes that a killed task left,
/// and the directory itself, with the parents the run created, where that leaves them empty.
/// Nothing else is touched; a directory without a run record is left as it is. IoError when a
/// removal fails, InputError when the run record is malformed.
void remove_tiled_run(const std::filesystem::path& directory);

/// Runs the missing tasks of one stage of a tiled run ("survey", "build" or "mesh"), one per
/// region listed: each opens the run from its directory (TiledRun(directory)) and calls the
/// stage with the run's options, so the tasks may run in any order, at once, on any machine
/// that sees the directory (clustersurf.distributed submits them to Dask). Returns when every
/// task is done and rethrows a task's error; reports progress(stage, fraction) as tasks finish
/// (false: cancel).
using RegionTaskRunner = std::function<void(std::string_view stage, std::span<const std::int32_t> regions,
                                            const ProgressCallback& progress)>;

/// Options of reconstruct_out_of_core().
struct OutOfCoreOptions {
  /// Memory for one region's build and tile, in bytes: sets the regions' size
  /// (region_points_for_memory()). The merge holds the merged tree (about 24 bytes per input
  /// point), and the join 13 bytes per output vertex: 100 M points within 4G peak at
  /// about 3.8 GB.
  std::uint64_t memory_limit = std::uint64_t{4} << 30;
  /// The most points a region holds with its halo; 0: region_points_for_memory(memory_limit).
  std::uint64_t max_region_points = 0;
  /// Runs the region tasks of each stage; empty: one after another in this process.
  RegionTaskRunner run_tasks;
  /// The work directory (required).
  std::filesystem::path work_directory;
  /// The mesh file (required when the options ask for a mesh), and how a PLY is written.
  std::filesystem::path mesh_output;
  PlyWriteOptions ply;
  /// Remove the run's files once it is done (remove_tiled_run(): nothing the run did not make).
  bool remove_work_directory = true;
  /// How the input is read.
  ReadOptions read;
};

/// What reconstruct_out_of_core() made.
struct OutOfCoreReconstruction {
  ClusterTree tree;  ///< merged, without a point-leaf table
  OrientationReport orientation;
  double build_seconds = 0;  ///< the partition, the surveys, the builds and the merge
  std::optional<WrittenMesh> mesh;
  /// Wall time of each stage, in order: partition, survey, build, merge, mesh (the tiles), join.
  std::vector<std::pair<std::string, double>> stage_seconds;
  std::size_t regions = 0;
  std::uint64_t input_points = 0;
  /// The tasks each stage ran, in order: survey, build, mesh (a run resumed runs fewer).
  std::vector<std::pair<std::string, std::size_t>> stage_tasks;
  std::uintmax_t work_bytes = 0;  ///< the work directory's files at their largest (before the cleanup)
};

/// The whole pipeline over the regions of a work directory, the one driver of every tiled run:
/// TiledRun::partition(), then each stage's tasks (out_of_core.run_tasks, or one region at a
/// time here), the merge, and the mesh written to out_of_core.mesh_output
/// (TiledRun::write_mesh()); the tree and the mesh equal reconstruct_tiled()'s of the same cloud
/// and plan, however the tasks ran. Resumes a run interrupted in the same work directory.
/// Throws IoError, InputError, OptionError, Cancelled.
OutOfCoreReconstruction reconstruct_out_of_core(const std::filesystem::path& input, const ReconstructOptions& options,
                                                const OutOfCoreOptions& out_of_core,
                                                const ProgressCallback& progress = {});

}  // namespace clustersurf
