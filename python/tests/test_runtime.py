"""Behaviour around the Python runtime: the GIL is released during long work, pictures equal
the CLI's PNG, and `cmake --install` gives an importable package."""

import os
import pathlib
import struct
import subprocess
import sys
import threading
import zlib

import numpy as np
import pytest

import clustersurf

from conftest import sphere_points


def test_gil_is_released_while_evaluating(sphere_tree):
    xyz = np.random.default_rng(1).uniform(-1.2, 1.2, size=(400_000, 3))
    ticks = 0
    running = True

    def count():
        nonlocal ticks
        while running:
            ticks += 1

    thread = threading.Thread(target=count)
    thread.start()
    try:
        for _ in range(3):
            sphere_tree.evaluate(xyz)
            sphere_tree.gradient(xyz)
    finally:
        running = False
        thread.join()
    # With the GIL held through each call the counter would barely move between them.
    assert ticks > 10_000


def test_threads_build_the_same_tree():
    points, normals = sphere_points(3000)
    results = [None] * 4

    def build(k):
        results[k] = clustersurf.reconstruct(points, normals).to_bytes()

    threads = [threading.Thread(target=build, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(r == results[0] for r in results)


def decode_png(data: bytes) -> np.ndarray:
    """The pixels of an 8-bit RGBA, non-interlaced PNG (what the CLI writes)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, color = struct.unpack(">IIBB", body[:10])
            assert (depth, color) == (8, 6)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * 4
    out = np.zeros((height, stride), dtype=np.int32)
    for y in range(height):
        line = raw[y * (stride + 1):(y + 1) * (stride + 1)]
        kind, row = line[0], np.frombuffer(line[1:], dtype=np.uint8).astype(np.int32)
        prev = out[y - 1] if y > 0 else np.zeros(stride, dtype=np.int32)
        cur = np.zeros(stride, dtype=np.int32)
        for x in range(stride):
            a = cur[x - 4] if x >= 4 else 0
            b = prev[x]
            c = prev[x - 4] if x >= 4 else 0
            if kind == 0:
                pred = 0
            elif kind == 1:
                pred = a
            elif kind == 2:
                pred = b
            elif kind == 3:
                pred = (a + b) // 2
            else:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            cur[x] = (row[x] + pred) & 0xFF
        out[y] = cur
    return out.astype(np.uint8).reshape(height, width, 4)


def test_render_equals_the_cli_png(tmp_path, cli, bunny_file):
    tree_file = tmp_path / "b.cstree"
    subprocess.run([cli, "--quiet", "reconstruct", str(bunny_file), "-o", str(tree_file)], check=True)
    subprocess.run([cli, "--quiet", "render", str(tree_file), "-o", str(tmp_path / "b.png"), "--width", "40",
                    "--height", "30", "--show", "clusters", "--azimuth", "60", "--background", "#102030"], check=True)
    picture = clustersurf.load(tree_file).render(width=40, height=30, show="clusters", azimuth=60,
                                                 background="#102030")
    np.testing.assert_array_equal(picture, decode_png((tmp_path / "b.png").read_bytes()))


def test_cmake_install_gives_an_importable_package(tmp_path):
    build = os.environ.get("CLUSTERSURF_BUILD_DIR")
    if not build or not pathlib.Path(build, "CMakeCache.txt").exists():
        pytest.skip("CLUSTERSURF_BUILD_DIR (the CMake build folder) is not set")
    cmake = os.environ.get("CLUSTERSURF_CMAKE", "cmake")
    subprocess.run([cmake, "--install", build, "--prefix", str(tmp_path / "prefix")], check=True, capture_output=True)
    packages = list((tmp_path / "prefix").rglob("clustersurf/__init__.py"))
    assert len(packages) == 1
    for typed in ("py.typed", "__init__.pyi", "_clustersurf.pyi", "_open3d.py"):  # PEP 561: stubs ship along
        assert (packages[0].parent / typed).exists(), typed
    env = dict(os.environ, PYTHONPATH=str(packages[0].parent.parent))
    result = subprocess.run([sys.executable, "-c", "import clustersurf; print(clustersurf.__file__)"], env=env,
                            cwd=tmp_path, capture_output=True, text=True, check=True)
    assert result.stdout.startswith(str(tmp_path / "prefix"))


def test_the_installed_package_is_the_one_tested():
    # scripts/test-python-package installs the package with pip into a fresh virtual environment
    # and says where: then the tests import that copy, with its stubs, its marker and its tool.
    prefix = os.environ.get("CLUSTERSURF_EXPECT_INSTALLED")
    if not prefix:
        pytest.skip("not a run against a pip-installed package (scripts/test-python-package)")
    package = pathlib.Path(clustersurf.__file__).resolve().parent
    assert str(package).startswith(str(pathlib.Path(prefix).resolve())), package
    for typed in ("py.typed", "__init__.pyi", "_clustersurf.pyi"):
        assert (package / typed).exists(), typed
    tool = pathlib.Path(prefix) / "bin" / "clustersurf"
    result = subprocess.run([str(tool), "--version"], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == f"clustersurf {clustersurf.__version__}"
    result = subprocess.run([sys.executable, "-m", "clustersurf.distributed", "--help"], capture_output=True, text=True,
                            check=True, cwd=pathlib.Path(prefix))
    assert "--scheduler" in result.stdout
