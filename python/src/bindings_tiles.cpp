// Out-of-core and distributed reconstruction: reconstruct_file() and the TiledRun work
// directory whose per-region tasks clustersurf.distributed runs on Dask.

#include "bindings.hpp"

#include <clustersurf/tiling/tiled_run.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

namespace clustersurf::python {

namespace {

using namespace pybind11::literals;

/// A Python TiledRun: the work directory of one run (cheap to reopen in every task).
struct RunRef {
  std::shared_ptr<const TiledRun> run;
};

/// What TiledRun::write_mesh() wrote, as a dict.
py::dict written_mesh_dict(const WrittenMesh& m) { return json_dict(written_mesh_json(m)); }

/// The one driver of a tiled run (reconstruct_out_of_core()): its tasks here, or through a Python
/// runner `run_tasks(stage, regions, report)` (clustersurf.distributed: Dask).
OutOfCoreReconstruction run_out_of_core(const std::filesystem::path& input,
                                        const std::optional<std::filesystem::path>& mesh,
                                        const std::string& memory_limit, std::uint64_t max_region_points,
                                        const std::filesystem::path& work_dir, bool keep_work_dir,
                                        const py::object& run_tasks, const py::object& progress,
                                        const py::kwargs& kwargs) {
  ReconstructOptions o = reconstruct_options(kwargs);
  o.mesh = mesh.has_value();
  OutOfCoreOptions out_of_core;
  out_of_core.memory_limit = parse_memory_size(memory_limit);
  out_of_core.max_region_points = max_region_points;
  out_of_core.work_directory = work_dir;
  out_of_core.remove_work_directory = !keep_work_dir;
  if (mesh) out_of_core.mesh_output = *mesh;
  if (!run_tasks.is_none())
    out_of_core.run_tasks = [run_tasks](std::string_view stage, std::span<const std::int32_t> regions,
                                        const ProgressCallback& report) {
      py::gil_scoped_acquire hold;
      const py::cpp_function fraction([report, name = std::string(stage)](double done) {
        py::gil_scoped_release release;
        return !report || report(name, done);
      });
      run_tasks(std::string(stage), std::vector<std::int32_t>(regions.begin(), regions.end()), fraction);
    };
  return run_released(progress, [&](const ProgressCallback& callback) {
    return reconstruct_out_of_core(input, o, out_of_core, callback);
  });
}

/// reconstruct_file(): the out-of-core run within a memory limit.
void bind_reconstruct_file(py::module_& m) {
  m.def(
      "reconstruct_file",
      [](const std::filesystem::path& input, const std::optional<std::filesystem::path>& mesh,
         const std::string& memory_limit, const std::filesystem::path& work_dir, bool keep_work_dir,
         const py::object& progress, const py::kwargs& kwargs) {
        OutOfCoreReconstruction r =
            run_out_of_core(input, mesh, memory_limit, 0, work_dir, keep_work_dir, py::none(), progress, kwargs);
        py::object tree = py::cast(TreeRef{std::make_shared<const ClusterTree>(std::move(r.tree))});
        return py::make_tuple(tree, r.mesh ? written_mesh_dict(*r.mesh) : py::object(py::none()));
      },
      py::arg("input"), py::kw_only(), py::arg("mesh") = py::none(),
      py::arg("memory_limit") = format_memory_size(OutOfCoreOptions{}.memory_limit), py::arg("work_dir"),
      py::arg("keep_work_dir") = false, py::arg("progress") = py::none(), R"doc(
Reconstructs the point file ``input`` out of core, as ``clustersurf reconstruct IN --mesh MESH
--memory-limit SIZE --work-dir DIR`` does: split into regions on disk (under ``work_dir``),
built and meshed one region at a time within about ``memory_limit`` ("4G", "512M" or bytes),
the tiles welded into the file ``mesh`` (a binary PLY is written tile by tile, never whole in
memory; no mesh when None). Returns (Tree, dict): the merged tree and what was written (file,
vertices, triangles, streamed, voxel_size, seconds), or None without a mesh. A run interrupted
and started again with the same ``work_dir`` and options resumes; the directory's files are
removed at the end unless ``keep_work_dir``. Other keyword options are reconstruct()'s and
Tree.mesh()'s (tolerance, min_points, ..., resolution, voxel_size, trim, color, decimate);
levels of detail, watertight and distance colors are not available out of core.
``progress`` as in reconstruct(); the GIL is released.)doc");
}

/// _run_regions(), the driver of clustersurf.distributed, and the work directory's and regions' defaults.
void bind_run_functions(py::module_& m) {
  m.def(
      "_run_regions",
      [](const std::filesystem::path& input, const std::optional<std::filesystem::path>& mesh,
         std::uint64_t max_region_points, const std::filesystem::path& work_dir, bool keep_work_dir,
         const py::object& run_tasks, const py::object& progress, const py::kwargs& kwargs) {
        OutOfCoreReconstruction r =
            run_out_of_core(input, mesh, format_memory_size(OutOfCoreOptions{}.memory_limit), max_region_points,
                            work_dir, keep_work_dir, run_tasks, progress, kwargs);
        py::dict seconds, tasks;
        for (const auto& [stage, s] : r.stage_seconds) seconds[py::str(stage)] = s;
        for (const auto& [stage, n] : r.stage_tasks) tasks[py::str(stage)] = n;
        py::dict report("regions"_a = r.regions, "points"_a = r.input_points, "seconds"_a = seconds, "tasks"_a = tasks,
                        "work_bytes"_a = r.work_bytes);
        if (r.mesh) report["mesh"] = written_mesh_dict(*r.mesh);
        py::object tree = py::cast(TreeRef{std::make_shared<const ClusterTree>(std::move(r.tree))});
        return py::make_tuple(tree, report);
      },
      py::arg("input"), py::kw_only(), py::arg("mesh") = py::none(), py::arg("max_region_points"), py::arg("work_dir"),
      py::arg("keep_work_dir") = false, py::arg("run_tasks") = py::none(), py::arg("progress") = py::none(), R"doc(
The driver of clustersurf.distributed: reconstruct_file() with regions of at most
``max_region_points`` points, each stage's missing tasks run by ``run_tasks(stage, regions,
report)`` (each task: TiledRun(work_dir).<stage>(region, **options); ``report(fraction)`` as
they finish returns False to cancel). Returns (Tree, report): regions, points, seconds and tasks
per stage, work_bytes, and the mesh written.)doc");

  m.def("default_work_directory", &default_work_directory, py::arg("output"),
        "Where a run writing ``output`` keeps its files when no work directory is given: its name + \".work\".");
  m.attr("DEFAULT_MEMORY_LIMIT") = format_memory_size(OutOfCoreOptions{}.memory_limit);
  m.attr("DEFAULT_MAX_REGION_POINTS") = RegionOptions{}.max_points;

  m.def(
      "region_points_for_memory",
      [](const std::string& memory_limit) { return region_points_for_memory(parse_memory_size(memory_limit)); },
      py::arg("memory_limit"),
      "The most points a region may hold for its build to fit in ``memory_limit`` (\"4G\", \"512M\" or bytes).");
}

/// A TiledRun opened or partitioned, and what it holds.
void bind_run_opening(py::class_<RunRef>& run) {
  run.def(py::init([](const std::filesystem::path& directory) {
            py::gil_scoped_release release;
            return RunRef{std::make_shared<const TiledRun>(directory)};
          }),
          py::arg("directory"), "Opens a partitioned work directory.")
      .def_static(
          "partition",
          [](const std::filesystem::path& input, const std::filesystem::path& directory,
             std::uint64_t max_region_points, double halo_spacings, const py::object& progress) {
            PartitionOptions o;
            o.regions.max_points = max_region_points;
            o.regions.halo_spacings = halo_spacings;
            return run_released(progress, [&](const ProgressCallback& callback) {
              return RunRef{std::make_shared<const TiledRun>(TiledRun::partition(input, directory, o, callback))};
            });
          },
          py::arg("input"), py::arg("directory"), py::kw_only(),
          py::arg("max_region_points") = RegionOptions{}.max_points,
          py::arg("halo_spacings") = RegionOptions{}.halo_spacings, py::arg("progress") = py::none(),
          "Splits the point file ``input`` into regions of at most ``max_region_points`` points, each with a halo "
          "``halo_spacings`` median point spacings wide, under ``directory`` (reused when it already holds this "
          "input's partition); ``progress`` as in reconstruct().")
      .def_property_readonly(
          "directory", [](const RunRef& r) { return r.run->directory(); }, "The work directory.")
      .def_property_readonly(
          "regions", [](const RunRef& r) { return r.run->regions(); }, "How many regions the plan has.")
      .def_property_readonly(
          "input_points", [](const RunRef& r) { return r.run->input_points(); }, "Points in the input file.")
      .def(
          "done",
          [](const RunRef& r, const std::string& stage, std::int32_t region) { return r.run->done(stage, region); },
          py::arg("stage"), py::arg("region"),
          "Whether the result of ``stage`` (\"survey\", \"build\" or \"mesh\") of ``region`` is there.")
      .def(
          "claim", [](const RunRef& r, const py::kwargs& kwargs) { r.run->claim(reconstruct_options(kwargs)); },
          "Records the run's options (reconstruct()'s and Tree.mesh()'s keywords), or raises OptionError when the "
          "directory holds results of other options.");
}

/// A TiledRun's region stages, each an idempotent task of one region or of the whole run.
void bind_run_stages(py::class_<RunRef>& run) {
  run.def(
         "survey",
         [](const RunRef& r, std::int32_t region, const py::kwargs& kwargs) {
           const ReconstructOptions o = reconstruct_options(kwargs);
           py::gil_scoped_release release;
           r.run->survey(region, o.build);
         },
         py::arg("region"), "Stage 1 of a region: its survey (spacing, spread, noise, box).")
      .def(
          "build",
          [](const RunRef& r, std::int32_t region, const py::kwargs& kwargs) {
            const ReconstructOptions o = reconstruct_options(kwargs);
            py::gil_scoped_release release;
            r.run->build(region, o.build);
          },
          py::arg("region"), "Stage 2 of a region: its subtree (after every survey).")
      .def(
          "merge",
          [](const RunRef& r) {
            auto tree = [&] {
              py::gil_scoped_release release;
              return std::make_shared<const ClusterTree>(r.run->merge());
            }();
            return TreeRef{std::move(tree)};
          },
          "Stage 3: the regions' subtrees as one Tree (after every build).")
      .def(
          "mesh",
          [](const RunRef& r, std::int32_t region, const py::kwargs& kwargs) {
            const ReconstructOptions o = reconstruct_options(kwargs);
            py::gil_scoped_release release;
            r.run->mesh(region, o);
          },
          py::arg("region"), "Stage 4 of a region: its tile of the mesh (after the merge).");
}

/// A TiledRun's last stage, its output check and its files.
void bind_run_output(py::class_<RunRef>& run) {
  run.def(
         "join",
         [](const RunRef& r, const py::kwargs& kwargs) {
           const ReconstructOptions o = reconstruct_options(kwargs);
           SurfaceMesh mesh = [&] {
             py::gil_scoped_release release;
             return r.run->join(o.meshing);
           }();
           return mesh_object(std::move(mesh));
         },
         "Stage 5: the tiles welded into one Mesh (after every mesh task), decimated and colored as the keyword "
         "options say.")
      .def(
          "write_mesh",
          [](const RunRef& r, const std::filesystem::path& path, const py::kwargs& kwargs) {
            const ReconstructOptions o = reconstruct_options(kwargs);
            const WrittenMesh written = [&] {
              py::gil_scoped_release release;
              return r.run->write_mesh(path, o.meshing);
            }();
            return written_mesh_dict(written);
          },
          py::arg("path"),
          "Stage 5 into the file ``path`` (format by extension): a binary PLY is joined straight into it, tile by "
          "tile, never whole in memory. Returns what was written (file, vertices, triangles, streamed, ...).")
      .def(
          "check_output", [](const RunRef& r, const std::filesystem::path& path) { r.run->check_output(path); },
          py::arg("path"),
          "Raises OptionError when ``path``, an output of the run, would be one of the run's own files in its "
          "directory.")
      .def_property_readonly(
          "file_bytes", [](const RunRef& r) { return r.run->file_bytes(); },
          "The bytes of the run's own files in its directory now.")
      .def(
          "remove_files",
          [](const RunRef& r) {
            py::gil_scoped_release release;
            remove_tiled_run(r.run->directory());
          },
          "Removes the files the run wrote and the directories it created, where that leaves them empty; nothing "
          "else in the directory is touched.")
      .def("__repr__", [](const RunRef& r) {
        return "<clustersurf.TiledRun " + r.run->directory().string() + ": " + std::to_string(r.run->regions()) +
               " regions, " + std::to_string(r.run->input_points()) + " points>";
      });
}

}  // namespace

void bind_tiles(py::module_& m) {
  bind_reconstruct_file(m);
  bind_run_functions(m);
  py::class_<RunRef> run(m, "TiledRun", R"doc(
The work directory of a tiled reconstruction: the input split into region files (partition()),
then per region a survey, a build and a mesh task, a merge between builds and meshes, and a
join at the end. Every task writes its result atomically and does nothing when it is already
there, so tasks can run in any order within a stage, on any machine sharing the directory,
and be retried. clustersurf.distributed runs them on Dask.)doc");
  bind_run_opening(run);
  bind_run_stages(run);
  bind_run_output(run);
}

}  // namespace clustersurf::python
