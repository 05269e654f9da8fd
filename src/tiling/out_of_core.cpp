// The whole pipeline out of core: a tiled run's tasks one after another within a memory limit.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

#include "tiling/tiled_run_files.hpp"
#include "tiling/tiles.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace clustersurf {

std::uint64_t region_points_for_memory(std::uint64_t memory_limit) {
  if (memory_limit < 2 * kProcessBytes) throw OptionError("the memory limit must be at least 128M");
  return (memory_limit - kProcessBytes) / kRegionBytesPerPoint;
}

std::uint64_t parse_memory_size(std::string_view text) {
  std::string s(text);
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string suffix = s.substr(used);
  for (const char* tail : {"iB", "B"})
    if (suffix.size() > 1 && suffix.ends_with(tail)) suffix.resize(suffix.size() - std::strlen(tail));
  double scale = 1;
  if (suffix == "K" || suffix == "k")
    scale = 1024.0;
  else if (suffix == "M" || suffix == "m")
    scale = 1024.0 * 1024;
  else if (suffix == "G" || suffix == "g")
    scale = 1024.0 * 1024 * 1024;
  else if (suffix == "T" || suffix == "t")
    scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!suffix.empty())
    used = 0;
  const double bytes = value * scale;
  if (used == 0 || !(bytes >= 1) || !(bytes < 1.8e19))
    throw OptionError("a memory size is a number with an optional K, M, G or T (e.g. 4G), not \"" + s + "\"");
  return static_cast<std::uint64_t>(bytes);
}

std::string format_memory_size(std::uint64_t bytes) {
  for (const auto& [suffix, shift] : {std::pair{"T", 40}, std::pair{"G", 30}, std::pair{"M", 20}, std::pair{"K", 10}})
    if (bytes > 0 && bytes % (std::uint64_t{1} << shift) == 0) return std::to_string(bytes >> shift) + suffix;
  return std::to_string(bytes);
}

std::filesystem::path default_work_directory(const std::filesystem::path& output) {
  std::filesystem::path work = output;
  work += ".work";
  return work;
}

namespace {

/// The partition of an out-of-core run: regions, buffers and blocks within its memory limit.
PartitionOptions partition_within(const OutOfCoreOptions& out_of_core) {
  PartitionOptions partition;
  partition.regions.max_points = out_of_core.max_region_points > 0 ? out_of_core.max_region_points
                                                                   : region_points_for_memory(out_of_core.memory_limit);
  partition.read = out_of_core.read;
  // An eighth of the working memory for the region files' buffers, a sixteenth for a block of
  // points (48 bytes each).
  const std::uint64_t working = out_of_core.memory_limit - kProcessBytes;
  partition.buffer_bytes = static_cast<std::size_t>(std::min<std::uint64_t>(partition.buffer_bytes, working / 8));
  partition.block_points =
      static_cast<std::size_t>(std::clamp<std::uint64_t>(working / 16 / 48, 4096, partition.block_points));
  return partition;
}

/// Runs the tasks of stage `name` that are not done, through the runner or one after another
/// here, reporting under `label`; returns how many there were.
std::size_t run_stage(const TiledRun& run, const char* name, const char* label, const ReconstructOptions& options,
                      const OutOfCoreOptions& out_of_core, const ProgressCallback& progress) {
  const auto n = static_cast<std::int32_t>(run.regions());
  std::vector<std::int32_t> todo;
  for (std::int32_t k = 0; k < n; ++k)
    if (!run.done(name, k)) todo.push_back(k);
  const auto report = [&](std::string_view, double fraction) {
    const double done =
        static_cast<double>(n - static_cast<std::int32_t>(todo.size())) + fraction * static_cast<double>(todo.size());
    return !progress || progress(label, done / static_cast<double>(n));
  };
  if (out_of_core.run_tasks) {
    out_of_core.run_tasks(name, todo, report);
    for (const std::int32_t k : todo)
      if (!run.done(name, k))
        throw Error(std::string("the ") + name + " task of region " + std::to_string(k) + " did not finish");
    return todo.size();
  }
  for (std::size_t i = 0; i < todo.size(); ++i) {
    if (!report(name, static_cast<double>(i) / static_cast<double>(todo.size()))) throw Cancelled();
    const std::int32_t k = todo[i];
    const std::string_view which = name;
    if (which == "survey")
      run.survey(k, options.build);
    else if (which == "build")
      run.build(k, options.build);
    else
      run.mesh(k, options);
  }
  return todo.size();
}

}  // namespace

OutOfCoreReconstruction reconstruct_out_of_core(const std::filesystem::path& input, const ReconstructOptions& options,
                                                const OutOfCoreOptions& out_of_core, const ProgressCallback& progress) {
  if (out_of_core.work_directory.empty()) throw OptionError("an out-of-core run needs a work directory");
  if (options.mesh && out_of_core.mesh_output.empty())
    throw OptionError("an out-of-core run writes its mesh to a file: give one");
  if (options.mesh) require_tiled_meshing(options.meshing);
  const auto start = std::chrono::steady_clock::now();
  OutOfCoreReconstruction out;
  auto lap = std::chrono::steady_clock::now();
  const auto timed = [&](const char* name) {
    const auto now = std::chrono::steady_clock::now();
    out.stage_seconds.emplace_back(name, std::chrono::duration<double>(now - lap).count());
    lap = now;
  };
  const TiledRun run = TiledRun::partition(input, out_of_core.work_directory, partition_within(out_of_core), progress);
  run.claim(options);
  if (options.mesh) run.check_output(out_of_core.mesh_output);  // before any work, not after it
  timed("partition");
  out.regions = run.regions();
  out.input_points = run.input_points();
  const auto stage = [&](const char* name, const char* label) {
    out.stage_tasks.emplace_back(name, run_stage(run, name, label, options, out_of_core, progress));
    timed(name);
  };
  stage("survey", "surveying regions");
  stage("build", "building regions");
  run.merge();  // not held while the tiles are meshed: the tasks read the region trees
  out.orientation = run.orientation();
  timed("merge");
  out.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (options.mesh) {
    const auto mesh_start = std::chrono::steady_clock::now();
    stage("mesh", "meshing tiles");
    if (progress && !progress("joining tiles", 1)) throw Cancelled();
    out.mesh = run.write_mesh(out_of_core.mesh_output, options.meshing, out_of_core.ply);
    timed("join");
    out.mesh->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - mesh_start).count();
  }
  out.tree = run.merge();  // read back from its file
  out.work_bytes = run.file_bytes();
  if (out_of_core.remove_work_directory) remove_tiled_run(run.directory());
  return out;
}

}  // namespace clustersurf
