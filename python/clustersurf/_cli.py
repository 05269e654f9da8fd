"""The `clustersurf` command of an installed package: runs the command-line tool built with it."""

import os
import pathlib
import sys


def tool() -> pathlib.Path:
    """Where the package keeps the command-line tool (bin/clustersurf next to this file)."""
    return pathlib.Path(__file__).resolve().parent / "bin" / "clustersurf"


def main() -> int:
    path = tool()
    if not os.access(path, os.X_OK):
        sys.stderr.write(f"clustersurf: the command-line tool is not in this package ({path}); "
                         "the package was not installed with pip: run the CMake build's clustersurf\n")
        return 127
    os.execv(path, [str(path), *sys.argv[1:]])
    return 0  # not reached: execv replaces the process
