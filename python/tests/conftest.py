"""Shared fixtures: where the CLI and the data are, synthetic clouds, a small bunny tree.

ctest passes the locations in the environment (python/CMakeLists.txt); run by hand, the tests
look next to the checkout and skip, saying why, when something is missing.
"""

import os
import pathlib

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("CLUSTERSURF_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


def _default_data() -> pathlib.Path:
    return pathlib.Path(os.environ.get("CLUSTERSURF_DEFAULT_DATA", SOURCE_DIR / "data"))


def _shared_data() -> pathlib.Path:
    for var in ("CLUSTERSURF_SHARED_DATA", "CLUSTERSURF_SHARED_DATA_DEFAULT"):
        if os.environ.get(var):
            return pathlib.Path(os.environ[var])
    return SOURCE_DIR.parent / "shared" / "data"


@pytest.fixture(scope="session")
def cli() -> str:
    """Path of the built `clustersurf` binary (for results-equal-the-CLI tests)."""
    path = os.environ.get("CLUSTERSURF_CLI", str(SOURCE_DIR / "build" / "clustersurf"))
    if not os.access(path, os.X_OK):
        pytest.skip(f"the clustersurf CLI is not built at {path} (set CLUSTERSURF_CLI)")
    return path


@pytest.fixture(scope="session")
def bunny_file() -> pathlib.Path:
    """The default input written by scripts/setup (1,839 points, with faces)."""
    path = _default_data() / "bunny.ply"
    if not path.exists():
        pytest.skip(f"{path} is missing (run scripts/setup)")
    return path


@pytest.fixture(scope="session")
def shared_data():
    """A function giving a file of the shared scans, skipping when it is absent."""

    def get(relative: str) -> pathlib.Path:
        path = _shared_data() / relative
        if not path.exists():
            pytest.skip(f"shared data {path} is absent (set CLUSTERSURF_SHARED_DATA)")
        return path

    return get


def sphere_points(n: int = 2000, radius: float = 1.0):
    """n points on a sphere (Fibonacci lattice) and their outward normals, float64."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(1.0 - z * z)
    phi = np.pi * (3.0 - np.sqrt(5.0)) * np.arange(n)
    normals = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    return radius * normals, normals


@pytest.fixture(scope="session")
def sphere():
    return sphere_points()


@pytest.fixture(scope="session")
def sphere_tree(sphere):
    import clustersurf

    points, normals = sphere
    return clustersurf.reconstruct(points, normals)
