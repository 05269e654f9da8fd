"""Tiled reconstruction on a Dask cluster.

    python3 -m clustersurf.distributed IN --mesh OUT [--scheduler ADDRESS | --local-workers N]

The input is split into regions under a work directory (``--work-dir``, default OUT.work),
which every worker must see: one machine, or a filesystem the machines share. A directory
that already holds other files is used alongside them, and at the end only the run's own files
are removed (and the directory, when the run created it and that leaves it empty). Each region's
survey, build and mesh are then Dask tasks that pass the directory and the region's number,
never points; each writes its result atomically and does nothing when the result is already
there, so a task lost with its worker is simply run again, and a run started again redoes only
what is missing. The library's driver of tiled runs (reconstruct_out_of_core, the one
``clustersurf reconstruct IN --mesh OUT --memory-limit ...`` runs) sequences the stages here, in
the client, and runs the merge and the final weld; only the region tasks go to the workers. The
C++ work releases the GIL. The mesh is the one the command line makes from the same regions.
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



def _task(stage: str, directory: str, region: int, options: Dict[str, Any]) -> int:
    """One region's stage, in a worker: reopens the run and does the work (or nothing when done)."""
    run = _cs.TiledRun(directory)
    getattr(run, stage)(region, **options)
    return region


def _dask_runner(client: Any, directory: str, options: Dict[str, Any], retries: int) -> Callable:
    """The library driver's task runner on ``client``: submits a stage's regions and waits."""

    def run_tasks(stage: str, regions: list, report: Callable[[float], bool]) -> None:
        from distributed import as_completed

        futures = [
            client.submit(_task, stage, directory, r, options, retries=retries, pure=False,
                          key=f"clustersurf-{stage}-{r}-{os.getpid()}-{time.monotonic_ns()}")
            for r in regions
        ]
        done = 0
        for future in as_completed(futures):
            future.result()  # raises the task's error (after its retries)
            done += 1
            if report(done / len(futures)) is False:
                client.cancel(futures)  # finished tasks' files stay: a run started again resumes
                raise _cs.Cancelled("cancelled")

    return run_tasks


def reconstruct_distributed(input: str | os.PathLike, *, client: Any, work_dir: str | os.PathLike,
                            mesh: Optional[str | os.PathLike] = None, tree: Optional[str | os.PathLike] = None,
                            max_region_points: int = _cs.DEFAULT_MAX_REGION_POINTS, keep_work_dir: bool = False,
                            progress: Optional[Progress] = None, retries: int = 3, **options: Any) -> Dict[str, Any]:
    """Reconstructs the point file ``input`` with the tasks of a tiled run on ``client``
    (a distributed.Client); writes the mesh to ``mesh`` and the tree to ``tree`` when given.
    The library's driver runs the run (the one ``clustersurf reconstruct --memory-limit`` runs);
    only its region tasks go to Dask.
    ``progress(stage, fraction)`` returning False raises Cancelled, the finished tasks' files kept.
    ``options`` are reconstruct()'s and Tree.mesh()'s keyword options. Returns a report: regions,
    points, triangles, the tasks each stage ran and its seconds."""
    if mesh is None and tree is None:
        raise _cs.OptionError("nothing to write: give a mesh and/or a tree file")
    start = time.monotonic()
    runner = _dask_runner(client, os.fspath(work_dir), options, retries)
    merged, run_report = _cs._run_regions(input, mesh=mesh, max_region_points=max_region_points, work_dir=work_dir,
                                          keep_work_dir=keep_work_dir, run_tasks=runner, progress=progress, **options)
    report: Dict[str, Any] = {"input": os.fspath(input), "regions": run_report["regions"],
                              "points": run_report["points"], "seconds": dict(run_report["seconds"]),
                              "tasks": dict(run_report["tasks"]), "leaves": merged.info()["leaves"],
                              "work_bytes": run_report["work_bytes"]}
    if mesh is not None:
        report["mesh"] = os.fspath(mesh)
        report["vertices"] = run_report["mesh"]["vertices"]
        report["triangles"] = run_report["mesh"]["triangles"]
    if tree is not None:
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
