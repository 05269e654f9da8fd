"""examples/python_quickstart.py runs start to end (its Open3D cell only with Open3D), and a
georeferenced cloud's mesh comes out where the cloud is."""

import os
import subprocess
import sys

import numpy as np

import clustersurf
from conftest import SOURCE_DIR


def test_quickstart_runs(tmp_path, bunny_file):
    # The bunny at a UTM position (metres): read next to zero, its mesh written back there.
    site = np.array([636590.49, 849216.55, 400.25])
    bunny = clustersurf.read_points(bunny_file)
    far = tmp_path / "bunny_utm.ply"
    clustersurf.write_points(far, bunny.positions, bunny.normals, origin=bunny.origin + site)
    script = SOURCE_DIR / "examples" / "python_quickstart.py"
    result = subprocess.run([sys.executable, str(script), str(far), str(tmp_path)], capture_output=True,
                            text=True, env=dict(os.environ), timeout=600)
    assert result.returncode == 0, result.stderr
    assert "mesh:" in result.stdout
    assert (tmp_path / "tree.cstree").exists() and (tmp_path / "mesh.ply").exists()
    mesh = clustersurf.read_mesh(tmp_path / "mesh.ply")
    world = mesh.vertices + mesh.origin
    lo, hi = bunny.positions.min(axis=0) + bunny.origin + site, bunny.positions.max(axis=0) + bunny.origin + site
    assert np.all(world.min(axis=0) > lo - 0.01) and np.all(world.max(axis=0) < hi + 0.01)
