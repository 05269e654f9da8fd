# Type stubs of the extension module clustersurf._clustersurf (python/src/*.cpp), hand-written:
# python/tests/test_stubs.py fails when a binding, a keyword name or a default differs from them.

import os
import pathlib
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._types import Mesh, PointCloud

__version__: str

_Path = Union[str, os.PathLike[str]]
# progress(stage, fraction): returning False cancels (Cancelled is raised).
_Progress = Optional[Callable[[str, float], Optional[bool]]]
# An (n, 3) array of points, or an object holding them: a PointCloud, or anything with
# .positions or .vertices.
_Points = Union[ArrayLike, PointCloud, Mesh, Any]
# An (n, 3) vertex array (its faces beside it), or a whole mesh or cloud in its place: a Mesh,
# PointCloud, trimesh.Trimesh, Open3D TriangleMesh, anything with .vertices (or .positions) and
# .faces or .triangles.
_Surface = Union[ArrayLike, Mesh, PointCloud, Any]
_Vector3 = Union[Sequence[float], ArrayLike]

class Error(Exception):
    """Base of every clustersurf error; str(e) is the message the CLI prints."""

class InputError(Error, ValueError):
    """A file's content is malformed or unsupported; the message names the file and the line or byte."""

class IoError(Error, OSError):
    """The operating system refused an I/O operation (missing file, permission, disk full)."""

class OptionError(Error, ValueError):
    """An invalid option or argument (out of range, wrong array shape, inconsistent)."""

class Cancelled(Error):
    """A progress callback returned False; the operation left no partial output."""

def read_points(path: _Path, drop_non_finite: bool = False, mesh_samples: int = 100000) -> PointCloud: ...
def read_mesh(path: _Path) -> Mesh: ...
def write_points(
    path: _Path,
    positions: _Points,
    normals: Optional[ArrayLike] = None,
    colors: Optional[ArrayLike] = None,
    ascii: bool = False,
    double: bool = False,
    origin: Optional[_Vector3] = None,
) -> None: ...
def write_mesh(
    path: _Path,
    vertices: _Surface,
    faces: Optional[ArrayLike] = None,
    normals: Optional[ArrayLike] = None,
    colors: Optional[ArrayLike] = None,
    ascii: bool = False,
    origin: Optional[_Vector3] = None,
) -> None: ...
def check_mesh(vertices: _Surface, faces: Optional[ArrayLike] = None) -> Dict[str, Any]: ...
def measure_registration(points: _Points) -> Dict[str, Any]: ...
def sample_surface(
    vertices: _Surface,
    faces: Optional[ArrayLike] = None,
    n: int = 200000,
    noise: float = 0.0,
    outliers: float = 0.0,
    seed: int = 1,
) -> PointCloud: ...
def scan_surface(
    vertices: _Surface,
    faces: Optional[ArrayLike] = None,
    n: int = 200000,
    scans: int = 8,
    noise: float = 0.0,
    registration: float = 0.0,
    flipped_normals: float = 0.0,
    distance: float = 1.5,
    seed: int = 1,
    noise_correlation: float = 0.0,
) -> PointCloud: ...
def compare_surfaces(
    recon_vertices: _Surface,
    recon_faces: Optional[Union[ArrayLike, _Surface]] = None,
    ref_vertices: Optional[_Surface] = None,
    ref_faces: Optional[ArrayLike] = None,
    recon_normals: Optional[ArrayLike] = None,
    ref_normals: Optional[ArrayLike] = None,
    samples: int = 200000,
    seed: int = 1,
    fscore_thresholds: List[float] = [0.005, 0.01],
) -> Dict[str, Any]: ...
def reconstruct(
    points: _Points,
    normals: Optional[ArrayLike] = None,
    *,
    proxy: str = "poly",
    splitter: str = "split-plane",
    tolerance: Union[str, float] = "auto",
    absolute_tolerance: Optional[float] = None,
    error: str = "rms",
    min_points: Union[str, int] = "auto",
    max_depth: int = 200,
    alpha: Union[str, float] = "auto",
    kstep: int = 0,
    lloyd_restarts: int = 4,
    proxy_lloyd: int = 0,
    noise_factor: float = 1.0,
    support_factor: float = 1.0,
    support_points: int = 12,
    seed: int = 1,
    ignore_normals: bool = False,
    no_creases: bool = False,
    keep_outliers: bool = False,
    no_point_leaves: bool = False,
    progress: _Progress = None,
) -> Tree: ...
def reconstruct_mesh(
    points: _Points,
    normals: Optional[ArrayLike] = None,
    *,
    progress: _Progress = None,
    **kwargs: Any,
) -> Mesh: ...
def load(path: _Path) -> Tree: ...
def option_schema() -> List[Dict[str, Any]]: ...
def reconstruct_file(
    input: _Path,
    *,
    mesh: Optional[_Path] = None,
    memory_limit: str = "4G",
    work_dir: _Path,
    keep_work_dir: bool = False,
    progress: _Progress = None,
    **kwargs: Any,
) -> Tuple[Tree, Optional[Dict[str, Any]]]: ...
def _run_regions(
    input: _Path,
    *,
    mesh: Optional[_Path] = None,
    max_region_points: int,
    work_dir: _Path,
    keep_work_dir: bool = False,
    run_tasks: Optional[Callable[[str, List[int], Callable[[float], bool]], None]] = None,
    progress: _Progress = None,
    **kwargs: Any,
) -> Tuple[Tree, Dict[str, Any]]: ...
def _origin_shift(lo: ArrayLike, hi: ArrayLike) -> NDArray[np.float64]: ...
def region_points_for_memory(memory_limit: str) -> int: ...
def default_work_directory(output: _Path) -> pathlib.Path: ...

DEFAULT_MEMORY_LIMIT: str
DEFAULT_MAX_REGION_POINTS: int

class TiledRun:
    """The work directory of a tiled reconstruction (TiledRun(directory) opens one); its tasks are
    idempotent (clustersurf.distributed)."""

    @staticmethod
    def partition(
        input: _Path,
        directory: _Path,
        *,
        max_region_points: int = 4000000,
        halo_spacings: float = 64.0,
        progress: _Progress = None,
    ) -> TiledRun: ...
    @property
    def directory(self) -> str: ...
    @property
    def regions(self) -> int: ...
    @property
    def input_points(self) -> int: ...
    def done(self, stage: str, region: int) -> bool: ...
    def claim(self, **kwargs: Any) -> None: ...
    def survey(self, region: int, **kwargs: Any) -> None: ...
    def build(self, region: int, **kwargs: Any) -> None: ...
    def merge(self) -> Tree: ...
    def mesh(self, region: int, **kwargs: Any) -> None: ...
    def join(self, **kwargs: Any) -> Mesh: ...
    def write_mesh(self, path: _Path, **kwargs: Any) -> Dict[str, Any]: ...
    def check_output(self, path: _Path) -> None: ...
    @property
    def file_bytes(self) -> int: ...
    def remove_files(self) -> None: ...

class Node:
    """One node of a Tree (a view: it keeps the tree alive), numbered in depth-first pre-order."""

    @property
    def index(self) -> int: ...
    @property
    def parent(self) -> Optional[int]: ...
    @property
    def left(self) -> Optional[int]: ...
    @property
    def right(self) -> Optional[int]: ...
    @property
    def children(self) -> List[Node]: ...
    @property
    def is_leaf(self) -> bool: ...
    @property
    def depth(self) -> int: ...
    @property
    def point_count(self) -> int: ...
    @property
    def rms_error(self) -> float: ...
    @property
    def max_error(self) -> float: ...
    @property
    def proxy_type(self) -> str: ...
    @property
    def proxy(self) -> Dict[str, Any]: ...
    @property
    def coefficients(self) -> NDArray[np.float64]: ...
    @property
    def support(self) -> Tuple[NDArray[np.float64], float]: ...
    @property
    def bound(self) -> Tuple[NDArray[np.float64], float]: ...
    def proxy_value(self, xyz: ArrayLike) -> NDArray[np.float64]: ...

class Tree:
    """A cluster tree: made by reconstruct() or load(), immutable, pickles as its .cstree bytes."""

    def save(self, path: _Path) -> None: ...
    def to_bytes(self) -> bytes: ...
    @staticmethod
    def from_bytes(data: bytes) -> Tree: ...
    def info(self) -> Dict[str, Any]: ...
    def __len__(self) -> int: ...
    def node(self, index: int) -> Node: ...
    def __getitem__(self, index: int) -> Node: ...
    @property
    def root(self) -> Node: ...
    @property
    def nodes(self) -> List[Node]: ...
    @property
    def leaves(self) -> NDArray[np.int32]: ...
    @property
    def depth(self) -> int: ...
    @property
    def bbox(self) -> Tuple[NDArray[np.float64], NDArray[np.float64]]: ...
    @property
    def origin(self) -> NDArray[np.float64]: ...
    def leaf_of_points(self) -> NDArray[np.int32]: ...
    def evaluate(
        self,
        xyz: ArrayLike,
        *,
        min_weight: float = 0.02,
        lod_depth: Optional[int] = None,
        lod_error: Optional[float] = None,
    ) -> NDArray[np.float64]: ...
    def gradient(
        self,
        xyz: ArrayLike,
        *,
        min_weight: float = 0.02,
        lod_depth: Optional[int] = None,
        lod_error: Optional[float] = None,
    ) -> NDArray[np.float64]: ...
    def mesh(
        self,
        *,
        resolution: Union[str, int] = "auto",
        voxel_size: Optional[float] = None,
        lod_depth: Optional[int] = None,
        lod_error: Optional[float] = None,
        color: str = "input",
        trim: float = 2.0,
        max_reach_spreads: float = 3.0,
        min_component_points: int = 30,
        close_pinholes: bool = False,
        coarsen: float = 0.05,
        coarsen_levels: int = 3,
        refit_points: int = 12,
        no_chord_offset: bool = False,
        decimate: int = 0,
        decimate_tolerance: float = 0.0,
        watertight: bool = False,
        fill_holes: float = 0.0,
        points: Optional[_Points] = None,
        progress: _Progress = None,
    ) -> Mesh: ...
    def inside(self, xyz: ArrayLike, *, resolution: int = 128) -> NDArray[np.bool_]: ...
    def render(
        self,
        *,
        width: int = 1280,
        height: int = 960,
        samples: int = 1,
        mode: str = "implicit",
        show: str = "surface",
        level: Optional[int] = None,
        highlight: Optional[int] = None,
        error_scale: Optional[float] = None,
        azimuth: float = 30.0,
        elevation: float = 20.0,
        distance: Optional[float] = None,
        fov: float = 35.0,
        eye: Optional[_Vector3] = None,
        target: Optional[_Vector3] = None,
        up: Optional[_Vector3] = None,
        background: str = "white",
        ao: bool = False,
        min_weight: float = 0.02,
        point_radius: float = 0.0,
        points: Optional[_Points] = None,
        lod_depth: Optional[int] = None,
        lod_error: Optional[float] = None,
        progress: _Progress = None,
    ) -> NDArray[np.uint8]: ...
