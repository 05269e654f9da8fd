"""clustersurf.distributed: a tiled run's tasks on a Dask cluster (a LocalCluster of 2 worker
processes) give the mesh of the same run done task after task; a worker killed mid-run and a
run started again change nothing; the command line writes the mesh and reports."""

import json
import os
import signal
import subprocess
import sys

import numpy as np
import pytest

import clustersurf
from clustersurf import distributed as cd

pytest.importorskip("distributed", reason="Dask's python3-distributed is not installed (scripts/setup installs it)")

REGION_POINTS = 5000


def torus_points(n: int, seed: int = 3):
    """n points area-uniform on a torus (R = 1, r = 0.35) and their outward normals."""
    rng = np.random.default_rng(seed)
    big, small = 1.0, 0.35
    u, v = [], []
    while len(u) < n:
        a, b = rng.uniform(0, 2 * np.pi, 2 * n), rng.uniform(0, 2 * np.pi, 2 * n)
        keep = rng.uniform(0, 1, 2 * n) < (big + small * np.cos(b)) / (big + small)
        u.extend(a[keep])
        v.extend(b[keep])
    u, v = np.array(u[:n]), np.array(v[:n])
    normals = np.stack([np.cos(v) * np.cos(u), np.cos(v) * np.sin(u), np.sin(v)], axis=1)
    centers = np.stack([big * np.cos(u), big * np.sin(u), np.zeros(n)], axis=1)
    return centers + small * normals, normals


@pytest.fixture(scope="module")
def cloud_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("distributed") / "torus.ply"
    points, normals = torus_points(30000)
    # Colored in two halves, as a scan's RGB: the colors go through the tasks too.
    colors = np.where(points[:, :1] > 0, [200, 60, 20], [20, 90, 180]).astype(np.uint8)
    clustersurf.write_points(path, points, normals, colors)
    return path


@pytest.fixture(scope="module")
def serial_mesh(cloud_file, tmp_path_factory):
    """The mesh file of the same tiled run, its tasks one after another in this process."""
    work = tmp_path_factory.mktemp("serial")
    run = clustersurf.TiledRun.partition(cloud_file, work / "run", max_region_points=REGION_POINTS)
    assert run.regions >= 4
    for stage in ("survey", "build"):
        for r in range(run.regions):
            getattr(run, stage)(r)
    run.merge()
    for r in range(run.regions):
        run.mesh(r)
    path = work / "serial.ply"
    clustersurf.write_mesh(path, run.join())
    return path.read_bytes()


@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster)
    yield client
    client.close()
    cluster.close()


def test_cluster_gives_the_serial_runs_mesh(cloud_file, serial_mesh, client, tmp_path):
    report = cd.reconstruct_distributed(cloud_file, client=client, work_dir=tmp_path / "run", mesh=tmp_path / "mesh.ply",
                                        tree=tmp_path / "tree.cstree", max_region_points=REGION_POINTS)
    assert (tmp_path / "mesh.ply").read_bytes() == serial_mesh
    colors = clustersurf.read_mesh(tmp_path / "mesh.ply").colors
    assert colors is not None and set(map(tuple, colors)) >= {(200, 60, 20), (20, 90, 180)}
    assert report["tasks"] == {"survey": report["regions"], "build": report["regions"], "mesh": report["regions"]}
    assert clustersurf.load(tmp_path / "tree.cstree").info()["leaves"] == report["leaves"]
    assert not (tmp_path / "run").exists()  # the run's files are removed at the end, and the folder it made


def test_one_input_through_the_three_paths(cloud_file, serial_mesh, client, tmp_path):
    """The same cloud in core, out of core (the library's driver, its tasks in this process) and on
    Dask: the two tiled paths write the same bytes; the in-core mesh differs from them only by the
    leaves along the region borders (a tiled tree's leaves stop at its regions' cells), within a
    small share of the point spacing, with the same topology."""
    out_of_core = tmp_path / "out_of_core.ply"
    _, report = clustersurf._clustersurf._run_regions(cloud_file, mesh=out_of_core, max_region_points=REGION_POINTS,
                                                      work_dir=tmp_path / "run")
    assert report["regions"] >= 4
    dask = tmp_path / "dask.ply"
    cd.reconstruct_distributed(cloud_file, client=client, work_dir=tmp_path / "dask-run", mesh=dask,
                               max_region_points=REGION_POINTS)
    assert out_of_core.read_bytes() == dask.read_bytes() == serial_mesh

    cloud = clustersurf.read_points(cloud_file)
    tree = clustersurf.reconstruct(cloud.positions, cloud.normals)
    in_core = tree.mesh(points=cloud.positions)
    tiled = clustersurf.read_mesh(out_of_core)
    spacing = tree.info()["point_spacing"]
    diagonal = float(np.linalg.norm(cloud.positions.max(axis=0) - cloud.positions.min(axis=0)))
    compared = clustersurf.compare_surfaces(in_core.vertices, in_core.faces, tiled.vertices, tiled.faces)
    assert compared["chamfer"] * diagonal < 0.05 * spacing and compared["hausdorff"] * diagonal < 0.5 * spacing, compared
    for mesh in (in_core, tiled):
        check = clustersurf.check_mesh(mesh.vertices, mesh.faces)
        assert check["boundary_edges"] == 0 and check["components"] == 1 and check["genus"] == 1, check


def _users_folder(path):
    path.mkdir()
    (path / "thesis.txt").write_text("my thesis\n")
    return path


def test_a_users_work_dir_keeps_their_files(cloud_file, serial_mesh, client, tmp_path):
    precious = _users_folder(tmp_path / "precious")
    report = cd.reconstruct_distributed(cloud_file, client=client, work_dir=precious, mesh=tmp_path / "mesh.ply",
                                        max_region_points=REGION_POINTS)
    assert (tmp_path / "mesh.ply").read_bytes() == serial_mesh
    assert sorted(p.name for p in precious.iterdir()) == ["thesis.txt"]  # only the run's own files went
    assert (precious / "thesis.txt").read_text() == "my thesis\n"
    assert report["work_bytes"] > 30000 * 48  # the region files, not the user's


def test_a_failed_or_cancelled_run_keeps_the_users_files(cloud_file, serial_mesh, client, tmp_path):
    precious = _users_folder(tmp_path / "precious")
    with pytest.raises(clustersurf.IoError):  # fails half way: the join cannot write its mesh
        cd.reconstruct_distributed(cloud_file, client=client, work_dir=precious, mesh=tmp_path / "no such folder" / "mesh.ply",
                                   max_region_points=REGION_POINTS)
    assert (precious / "thesis.txt").read_text() == "my thesis\n"

    def cancel(stage, fraction):
        return stage != "building regions"

    other = _users_folder(tmp_path / "other")
    with pytest.raises(clustersurf.Cancelled):
        cd.reconstruct_distributed(cloud_file, client=client, work_dir=other, mesh=tmp_path / "mesh.ply",
                                   max_region_points=REGION_POINTS, progress=cancel)
    assert (other / "thesis.txt").read_text() == "my thesis\n"
    assert not (tmp_path / "mesh.ply").exists()
    cd.reconstruct_distributed(cloud_file, client=client, work_dir=other, mesh=tmp_path / "mesh.ply",
                               max_region_points=REGION_POINTS)  # resumes, then cleans up after itself
    assert (tmp_path / "mesh.ply").read_bytes() == serial_mesh
    assert sorted(p.name for p in other.iterdir()) == ["thesis.txt"]


def test_a_work_dir_that_cannot_be_one_is_refused(cloud_file, client, tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("data\n")
    with pytest.raises(clustersurf.OptionError, match="is not a directory"):
        cd.reconstruct_distributed(cloud_file, client=client, work_dir=afile, mesh=tmp_path / "mesh.ply",
                                   max_region_points=REGION_POINTS)
    assert afile.read_text() == "data\n"
    foreign = _users_folder(tmp_path / "foreign")
    (foreign / "plan.txt").write_text("my plan\n")
    with pytest.raises(clustersurf.OptionError, match="holds plan.txt"):
        cd.reconstruct_distributed(cloud_file, client=client, work_dir=foreign, mesh=tmp_path / "mesh.ply",
                                   max_region_points=REGION_POINTS)
    assert sorted(p.name for p in foreign.iterdir()) == ["plan.txt", "thesis.txt"]


def test_a_worker_killed_mid_run_changes_nothing(cloud_file, serial_mesh, client, tmp_path):
    killed = []

    def kill_a_worker(stage, fraction):
        # Once the first build task is back, kill a worker process outright: its running task
        # is lost with it and must be run again elsewhere.
        if stage == "building regions" and not killed:
            pids = client.run(os.getpid)
            victim = sorted(pids.values())[0]
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)
        return True

    cd.reconstruct_distributed(cloud_file, client=client, work_dir=tmp_path / "run", mesh=tmp_path / "mesh.ply",
                               max_region_points=REGION_POINTS, progress=kill_a_worker)
    assert killed
    assert (tmp_path / "mesh.ply").read_bytes() == serial_mesh
    client.wait_for_workers(2, timeout=60)  # the nanny restarts it, for the next tests


def test_a_run_started_again_redoes_only_what_is_missing(cloud_file, serial_mesh, client, tmp_path):
    work = tmp_path / "run"
    run = clustersurf.TiledRun.partition(cloud_file, work, max_region_points=REGION_POINTS)
    for r in range(run.regions):
        run.survey(r)
    run.build(0)  # then the run stopped
    report = cd.reconstruct_distributed(cloud_file, client=client, work_dir=work, mesh=tmp_path / "mesh.ply",
                                        max_region_points=REGION_POINTS, keep_work_dir=True)
    assert report["tasks"]["survey"] == 0
    assert report["tasks"]["build"] == run.regions - 1
    assert (tmp_path / "mesh.ply").read_bytes() == serial_mesh
    # Other options in the same directory are refused, not mixed with these results.
    with pytest.raises(clustersurf.OptionError):
        cd.reconstruct_distributed(cloud_file, client=client, work_dir=work, mesh=tmp_path / "other.ply",
                                   max_region_points=REGION_POINTS, tolerance=0.001)


def _command(*args):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([os.path.dirname(os.path.dirname(clustersurf.__file__)), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "clustersurf.distributed", *map(str, args)], env=env, capture_output=True,
                          text=True, timeout=600)


def test_command_line_writes_the_mesh_and_reports(cloud_file, serial_mesh, tmp_path):
    out = tmp_path / "mesh.ply"
    done = _command(cloud_file, "--mesh", out, "--local-workers", 2, "--max-region-points", REGION_POINTS, "--json")
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert report["regions"] >= 4 and report["triangles"] > 10000
    assert out.read_bytes() == serial_mesh


def test_command_line_keeps_the_users_work_dir(cloud_file, serial_mesh, tmp_path):
    precious = _users_folder(tmp_path / "precious")
    done = _command(cloud_file, "--mesh", tmp_path / "mesh.ply", "--local-workers", 1, "--max-region-points", REGION_POINTS,
                    "--work-dir", precious, "--quiet")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "mesh.ply").read_bytes() == serial_mesh
    assert sorted(p.name for p in precious.iterdir()) == ["thesis.txt"]
    afile = tmp_path / "afile"
    afile.write_text("data\n")
    refused = _command(cloud_file, "--mesh", tmp_path / "m.ply", "--local-workers", 1, "--work-dir", afile)
    assert refused.returncode == 2 and "is not a directory" in refused.stderr, refused.stderr
    assert afile.read_text() == "data\n"


def test_command_line_errors_are_clear(tmp_path):
    missing = _command(tmp_path / "missing.ply", "--mesh", tmp_path / "m.ply", "--local-workers", 1)
    assert missing.returncode == 4 and "missing.ply" in missing.stderr, missing.stderr
    assert not (tmp_path / "m.ply").exists()
    nothing = _command(tmp_path / "missing.ply")
    assert nothing.returncode == 2 and "nothing to write" in nothing.stderr
