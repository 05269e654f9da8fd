"""Tiled reconstruction on a Dask cluster.

    python3 -m clustersurf.distributed IN --mesh OUT [--scheduler ADDRESS | --local-workers N]

The input is split into regions under a work directory (``--work-dir``, default OUT.work),
which every worker must see: one machine, or a filesystem the machines share. A directory
that already holds other files is used alongside them, and at the end only the run's own files
are removed (and the directory, when the run created it and that leaves it empty). Each region's
survey, build and mesh are then Dask tasks that pass the directory and the region's number,
never points; each writes its result atomically and does nothing when the result is already
there, so a task lost with its worker is simply run again, and a run started again redoes only
what is missing. The merge and the final weld run here, in the client. The C++ work releases
the GIL. The mesh is the one ``clustersurf reconstruct IN --mesh OUT --memory-limit ...`` makes
from the same regions.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from typing import Any, Callable, Dict, Optional

from . import _clustersurf as _cs

Progress = Callable[[str, float], Any]

_STAGES = ("survey", "build", "mesh")


def _task(stage: str, directory: str, region: int, options: Dict[str, Any]) -> int:
    """One region's stage, in a worker: reopens the run and does the work (or nothing when done)."""
    run = _cs.TiledRun(directory)
    getattr(run, stage)(region, **options)
    return region


def _run_stage(client: Any, run: Any, stage: str, options: Dict[str, Any], progress: Optional[Progress],
               retries: int) -> int:
    """Submits the stage's missing regions and waits for them; returns how many ran."""
    from distributed import as_completed

    todo = [r for r in range(run.regions) if not run.done(stage, r)]
    futures = [
        client.submit(_task, stage, os.fspath(run.directory), r, options, retries=retries, pure=False,
                      key=f"clustersurf-{stage}-{r}-{os.getpid()}-{time.monotonic_ns()}")
        for r in todo
    ]
    done = run.regions - len(todo)
    for future in as_completed(futures):
        future.result()  # raises the task's error (after its retries)
        done += 1
        if progress is not None and progress(f"{stage} regions", done / run.regions) is False:
            client.cancel(futures)  # finished tasks' files stay: a run started again resumes
            raise _cs.Cancelled("cancelled")
    return len(todo)


def reconstruct_distributed(input: str | os.PathLike, *, client: Any, work_dir: str | os.PathLike,
                            mesh: Optional[str | os.PathLike] = None, tree: Optional[str | os.PathLike] = None,
                            max_region_points: int = 4_000_000, keep_work_dir: bool = False,
                            progress: Optional[Progress] = None, retries: int = 3, **options: Any) -> Dict[str, Any]:
    """Reconstructs the point file ``input`` with the tasks of a tiled run on ``client``
    (a distributed.Client); writes the mesh to ``mesh`` and the tree to ``tree`` when given.
    ``progress(stage, fraction)`` returning False raises Cancelled, the finished tasks' files kept.
    ``options`` are reconstruct()'s and Tree.mesh()'s keyword options. Returns a report: regions,
    points, triangles, the tasks each stage ran and its seconds."""
    if mesh is None and tree is None:
        raise _cs.OptionError("nothing to write: give a mesh and/or a tree file")
    report: Dict[str, Any] = {"input": os.fspath(input), "seconds": {}, "tasks": {}}
    start = time.monotonic()
    run = _cs.TiledRun.partition(input, work_dir, max_region_points=max_region_points, progress=progress)
    run.claim(**options)
    if mesh is not None:
        run.check_output(mesh)  # before any task runs
    report["regions"] = run.regions
    report["points"] = run.input_points
    report["seconds"]["partition"] = time.monotonic() - start
    for stage in ("survey", "build"):
        t = time.monotonic()
        report["tasks"][stage] = _run_stage(client, run, stage, options, progress, retries)
        report["seconds"][stage] = time.monotonic() - t
    t = time.monotonic()
    # Not held while the tiles are meshed: the mesh tasks read the region trees they meet.
    report["leaves"] = run.merge().info()["leaves"]
    report["seconds"]["merge"] = time.monotonic() - t
    if mesh is not None:
        t = time.monotonic()
        report["tasks"]["mesh"] = _run_stage(client, run, "mesh", options, progress, retries)
        report["seconds"]["mesh"] = time.monotonic() - t
        t = time.monotonic()
        written = run.write_mesh(mesh, **options)  # a PLY is joined straight into the file
        report["seconds"]["join"] = time.monotonic() - t
        report["mesh"] = os.fspath(mesh)
        report["vertices"] = written["vertices"]
        report["triangles"] = written["triangles"]
    merged = run.merge() if tree is not None else None  # read back from the work directory
    report["work_bytes"] = run.file_bytes
    if not keep_work_dir:
        run.remove_files()  # the run's own files only, and the directory when the run created it
    if merged is not None:
        merged.save(tree)  # after the cleanup, which would remove a tree saved as the run's own tree.cstree
        report["tree"] = os.fspath(tree)
    report["seconds"]["total"] = time.monotonic() - start
    return report


def _progress_printer() -> Optional[Progress]:
    """Progress on stderr when it is a terminal: one line rewritten in place."""
    if not sys.stderr.isatty():
        return None

    def show(stage: str, fraction: float) -> bool:
        sys.stderr.write(f"\r{stage:<24} {100 * fraction:5.1f} %")
        sys.stderr.flush()
        return True

    return show


def main(argv: Optional[list] = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m clustersurf.distributed",
                                     description="Reconstruct a point file with tiles on a Dask cluster.")
    parser.add_argument("input", help="point file (binary PLY, LAS, E57, PCD, XYZ and PTX are read in place; other formats are read whole)")
    parser.add_argument("--mesh", help="mesh file to write (.ply, .obj, .off, .stl or .glb)")
    parser.add_argument("-o", "--output", dest="tree", help="tree file to write (.cstree)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786)")
    where.add_argument("--local-workers", type=int, default=2, help="workers of a local cluster (default 2)")
    parser.add_argument("--work-dir", help="the run's files, seen by every worker (default: the output's name + .work); other files "
                        "there are left alone, and only the run's own are removed at the end")
    parser.add_argument("--keep-work-dir", action="store_true", help="keep the run's files when it is done")
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--memory-limit", help="memory of one worker's task (e.g. 4G): sets the regions' size")
    size.add_argument("--max-region-points", type=int, help="the most points of one region")
    parser.add_argument("--retries", type=int, default=3, help="times a failed task is run again (default 3)")
    parser.add_argument("--quiet", action="store_true", help="print nothing but errors")
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    args = parser.parse_args(argv)
    try:
        if args.mesh is None and args.tree is None:
            raise _cs.OptionError("nothing to write: give --mesh MESH and/or -o TREE.cstree")
        work_dir = args.work_dir or str(_cs.default_work_directory(args.mesh or args.tree))
        if args.max_region_points is not None:
            max_points = args.max_region_points
        else:
            max_points = _cs.region_points_for_memory(args.memory_limit or _cs.DEFAULT_MEMORY_LIMIT)
        from distributed import Client, LocalCluster

        if args.scheduler:
            cluster = None
            client = Client(args.scheduler)
        else:
            cluster = LocalCluster(n_workers=args.local_workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            client = Client(cluster)
        try:
            report = reconstruct_distributed(args.input, client=client, work_dir=work_dir, mesh=args.mesh, tree=args.tree,
                                             max_region_points=max_points, keep_work_dir=args.keep_work_dir,
                                             progress=None if args.quiet or args.json else _progress_printer(),
                                             retries=args.retries)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
        if sys.stderr.isatty() and not (args.quiet or args.json):
            sys.stderr.write("\n")
        if args.json:
            print(json.dumps(report, indent=2))
        elif not args.quiet:
            print(f"regions         {report['regions']} ({report['points']} points)")
            print(f"tree            {report['leaves']} leaves")
            if "triangles" in report:
                print(f"mesh            {report['vertices']} vertices, {report['triangles']} triangles")
            print("time            " + ", ".join(f"{k} {v:.2f} s" for k, v in report["seconds"].items()))
            for key in ("mesh", "tree"):
                if key in report:
                    print(f"wrote           {report[key]}")
        return 0
    except KeyboardInterrupt:
        print("interrupted: finished tasks are kept in the work directory; run again to resume", file=sys.stderr)
        return 130
    except _cs.Error as e:
        # The exit codes of the clustersurf command line.
        codes = {_cs.OptionError: 2, _cs.InputError: 3, _cs.IoError: 4, _cs.Cancelled: 130}
        print(f"error: {e}", file=sys.stderr)
        return next((code for cls, code in codes.items() if isinstance(e, cls)), 1)
    except Exception as e:  # a task lost more often than its retries, the scheduler gone
        print(f"error: the cluster failed: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
