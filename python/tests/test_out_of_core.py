"""reconstruct_file(): out of core from Python, the same files as the CLI's --memory-limit."""

import subprocess

import pytest

import clustersurf

from test_distributed import torus_points


def test_reconstruct_file_writes_the_clis_mesh(cli, tmp_path):
    points, normals = torus_points(20000)
    cloud = tmp_path / "torus.ply"
    clustersurf.write_points(cloud, points, normals)
    tree, written = clustersurf.reconstruct_file(cloud, mesh=tmp_path / "py.ply", memory_limit="64M", work_dir=tmp_path / "work")
    assert written["streamed"] and written["triangles"] > 10000
    assert not (tmp_path / "work").exists()
    done = subprocess.run([cli, "-q", "reconstruct", str(cloud), "--mesh", str(tmp_path / "cli.ply"), "-o", str(tmp_path / "cli.cstree"),
                           "--memory-limit", "64M"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    assert clustersurf.load(tmp_path / "cli.cstree").info() == tree.info()
    # A bad option is refused before anything is written.
    with pytest.raises(clustersurf.OptionError):
        clustersurf.reconstruct_file(cloud, mesh=tmp_path / "no.ply", work_dir=tmp_path / "w2", resolution=0)  # a bad option
    assert not (tmp_path / "no.ply").exists()
