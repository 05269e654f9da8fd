"""reconstruct_file(): out of core from Python, the same files as the CLI's --memory-limit."""

import subprocess

import pytest

import clustersurf

from test_distributed import torus_points


def test_reconstruct_file_writes_the_clis_mesh(cli, tmp_path):
    points, normals = torus_points(20000)
    cloud = tmp_path / "torus.ply"
    clustersurf.write_points(cloud, points, normals)
    tree, written = clustersurf.reconstruct_file(cloud, mesh=tmp_path / "py.ply", memory_limit="128M", work_dir=tmp_path / "work")
    assert written["streamed"] and written["triangles"] > 10000
    assert not (tmp_path / "work").exists()
    done = subprocess.run([cli, "-q", "reconstruct", str(cloud), "--mesh", str(tmp_path / "cli.ply"), "-o", str(tmp_path / "cli.cstree"),
                           "--memory-limit", "128M"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    assert clustersurf.load(tmp_path / "cli.cstree").info() == tree.info()
    # A bad option is refused before anything is written.
    with pytest.raises(clustersurf.OptionError):
        clustersurf.reconstruct_file(cloud, mesh=tmp_path / "no.ply", work_dir=tmp_path / "w2", resolution=0)  # a bad option
    assert not (tmp_path / "no.ply").exists()


def _peak_kib(command):
    """The peak resident memory (KiB) of a command, run alone in a fresh Python."""
    probe = ("import resource, subprocess, sys; done = subprocess.run(sys.argv[1:], capture_output=True); "
             "print(done.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
    out = subprocess.run(["python3", "-c", probe, *map(str, command)], capture_output=True, text=True, check=True).stdout.split()
    assert out[0] == "0", command
    return int(out[1])


def test_memory_limit_holds_on_an_input_that_needs_several_times_it(cli, tmp_path, bunny_file):
    # 600,000 points need about 500 MB in core, nearly four times the limit.
    cloud = tmp_path / "big.ply"
    subprocess.run([cli, "-q", "sample", str(bunny_file), "-o", str(cloud), "-n", "600000", "--seed", "7"], check=True)
    limit_kib = 128 * 1024
    out_of_core = _peak_kib([cli, "-q", "reconstruct", cloud, "--mesh", tmp_path / "ooc.ply", "--memory-limit", "128M"])
    in_core = _peak_kib([cli, "-q", "reconstruct", cloud, "--mesh", tmp_path / "in.ply"])
    assert in_core > 3 * limit_kib, f"the input is too small to test the limit: {in_core} KiB in core"
    assert out_of_core <= limit_kib, f"out of core peaked at {out_of_core} KiB, over the limit of {limit_kib} KiB"
