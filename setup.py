"""Builds the `clustersurf` Python package with the project's own CMake build.

`pip install --no-build-isolation .` (or `pip wheel --no-build-isolation .`) runs this with
Debian's python3-setuptools and python3-wheel; nothing is downloaded. The extension
`clustersurf._clustersurf` and the `clustersurf` command-line tool are built by CMake (Release, for
the interpreter running pip) and copied into the package next to its Python files, type stubs
and py.typed marker; the `clustersurf` console script runs the packaged tool.

Environment:
  CLUSTERSURF_BUILD_DIR   an existing, configured build folder to build in and copy from (its
                          configuration is left as it is), instead of a fresh one under build/pip
  CMAKE_ARGS              extra arguments for the fresh configuration (space-separated)
  CMAKE_BUILD_PARALLEL_LEVEL  jobs for the build (default: the machine's cores)
"""

import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent
# setuptools' own build and metadata folders, under the build tree rather than the sources.
(ROOT / "build" / "setuptools").mkdir(parents=True, exist_ok=True)


def project_version() -> str:
    """The version in CMakeLists.txt's project() (one place for both)."""
    text = (ROOT / "CMakeLists.txt").read_text()
    match = re.search(r"project\(clustersurf\s+VERSION\s+([0-9.]+)", text)
    if not match:
        raise RuntimeError("CMakeLists.txt does not declare project(clustersurf VERSION ...)")
    return match.group(1)


class CMakeExtension(Extension):
    """The pybind11 module built by CMake's target `_clustersurf`."""

    def __init__(self, name: str) -> None:
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    """Builds the extension and the CLI with CMake and puts both where the package expects them."""

    def build_extension(self, ext: Extension) -> None:
        given = os.environ.get("CLUSTERSURF_BUILD_DIR")
        build_dir = pathlib.Path(given).resolve() if given else ROOT / "build" / "pip"
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        if not (build_dir / "CMakeCache.txt").exists() or not given:
            generator = ["-G", "Ninja"] if shutil.which("ninja") and not (build_dir / "Makefile").exists() else []
            self.spawn(["cmake", "-S", str(ROOT), "-B", str(build_dir), *generator, "-DCMAKE_BUILD_TYPE=Release",
                        f"-DPython3_EXECUTABLE={sys.executable}", "-DCLUSTERSURF_PYTHON=ON",
                        "-DCLUSTERSURF_BUILD_TESTS=OFF", "-DCLUSTERSURF_BUILD_BENCH=OFF", "-DCLUSTERSURF_INSTALL=OFF",
                        *shlex.split(os.environ.get("CMAKE_ARGS", ""))])
        self.spawn(["cmake", "--build", str(build_dir), "--target", "_clustersurf", "clustersurf_cli", "-j", jobs])

        built = next((build_dir / "python" / "clustersurf").glob("_clustersurf*.so"), None)
        if built is None:
            raise RuntimeError(f"the CMake build in {build_dir} made no _clustersurf module")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built, target)
        tool = target.parent / "bin" / "clustersurf"
        tool.parent.mkdir(exist_ok=True)
        shutil.copy2(build_dir / "clustersurf", tool)


setup(
    version=project_version(),
    packages=["clustersurf"],
    package_dir={"": "python"},
    package_data={"clustersurf": ["*.pyi", "py.typed"]},
    ext_modules=[CMakeExtension("clustersurf._clustersurf")],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": "build/setuptools"}, "egg_info": {"egg_base": "build/setuptools"}},
    zip_safe=False,
)
