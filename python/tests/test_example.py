"""examples/python_quickstart.py runs start to end (its Open3D cell only with Open3D)."""

import os
import subprocess
import sys

from conftest import SOURCE_DIR


def test_quickstart_runs(tmp_path, bunny_file):
    script = SOURCE_DIR / "examples" / "python_quickstart.py"
    result = subprocess.run([sys.executable, str(script), str(bunny_file), str(tmp_path)], capture_output=True,
                            text=True, env=dict(os.environ), timeout=600)
    assert result.returncode == 0, result.stderr
    assert "mesh:" in result.stdout
    assert (tmp_path / "tree.cstree").exists() and (tmp_path / "mesh.ply").exists()
