"""Plain value types returned by the readers: numpy arrays with names.

Coordinates: a cloud's ``positions`` and a mesh's ``vertices`` are relative to its ``origin``,
as in the C++ library. Readers move a scan that lies far from zero (georeferenced LAS, E57...)
next to it, so that every stage works on small numbers; ``world_positions`` /
``world_vertices`` (= relative + origin) are the coordinates of the file, and the writers and
``to_open3d()`` put the origin back.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Dict, Mapping, Optional, Tuple

import numpy as np

if TYPE_CHECKING:  # Open3D is optional; only its types are named here
    import open3d


def _origin(value: Any) -> np.ndarray:
    """A (3,) float64 array from any (x, y, z); None gives zero."""
    if value is None:
        return np.zeros(3)
    origin = np.array(value, dtype=np.float64)
    if origin.shape != (3,) or not np.isfinite(origin).all():
        from ._clustersurf import OptionError

        raise OptionError(f"origin must be (x, y, z): three finite numbers, not {value!r}")
    return origin


def _attributes(value: Optional[Mapping[str, Any]], count: int) -> Dict[str, np.ndarray]:
    """A dict of name -> (count,) float32 arrays (arrays already float32 are kept, not copied)."""
    out: Dict[str, np.ndarray] = {}
    for name, values in (value or {}).items():
        array = np.ascontiguousarray(values, dtype=np.float32)
        if array.shape != (count,):
            from ._clustersurf import OptionError

            raise OptionError(f"attribute {name!r} must have one value per point ({count}), not shape {array.shape}")
        out[str(name)] = array
    return out


def _world(relative: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """relative + origin as a new float64 array (a copy, bit for bit, when the origin is zero)."""
    if not origin.any():
        return np.array(relative, dtype=np.float64)
    return np.asarray(relative, dtype=np.float64) + origin


def _up(value: Any) -> str:
    if value not in ("y", "z"):
        raise ValueError(f'up must be "y" or "z", not {value!r}')
    return str(value)


@dataclass
class PointCloud:
    """Points with optional per-point normals, colors, attributes and scanners.

    positions: (n, 3) float64, relative to ``origin``; normals: (n, 3) float64 or None;
    colors: (n, 3) uint8 or None; origin: (3,) float64 (set it from any (x, y, z)): a point is
    at positions[i] + origin in the file's coordinates (``world_positions``); attributes: dict
    name -> (n,) float32 array, e.g. "intensity" and "classification" of a LAS file (assigning
    a dict converts and checks it); scanner_positions: (k, 3) float64 in the frame of
    ``positions``, where each of k scans stood, and scanner_of_point: (n,) uint32, the scan that
    saw each point; each None when the file does not say (a PLY file's "scan" property and
    scan_surface() give the scans without where they stood); up: "y" or "z", the axis that points
    up in the file's convention ("z" for LAS, E57 and PTX surveys), which meshes and pictures
    of it follow.
    Pass it to reconstruct() directly (its normals are used) or take its arrays.
    """

    positions: np.ndarray
    normals: Optional[np.ndarray] = None
    colors: Optional[np.ndarray] = None
    origin: np.ndarray = field(default_factory=lambda: np.zeros(3))
    attributes: Dict[str, np.ndarray] = field(default_factory=dict)
    scanner_positions: Optional[np.ndarray] = None
    scanner_of_point: Optional[np.ndarray] = None
    up: str = "y"

    def __setattr__(self, name: str, value: Any) -> None:
        if name == "origin":
            value = _origin(value)
        elif name == "attributes":
            value = _attributes(value, len(self.positions))
        elif name == "up":
            value = _up(value)
        object.__setattr__(self, name, value)

    def __len__(self) -> int:
        return len(self.positions)

    @property
    def world_positions(self) -> np.ndarray:
        """positions + origin: the points in the file's coordinates, a new (n, 3) float64 array."""
        return _world(self.positions, self.origin)

    def to_open3d(self) -> "open3d.geometry.PointCloud":
        """An open3d.geometry.PointCloud of the points in the file's coordinates (positions +
        origin), with the normals and the colors (as floats in [0, 1]) when present. Attributes
        and scanners have no place there. Raises ImportError without Open3D (Debian:
        python3-open3d)."""
        from ._open3d import cloud_to_open3d

        return cloud_to_open3d(self)


@dataclass
class Mesh:
    """An indexed triangle mesh.

    vertices: (n, 3) float64, relative to ``origin``; faces: (m, 3) int32; normals: (n, 3)
    float64 or None; colors: (n, 3) uint8 or None (per vertex); origin: (3,) float64 (set it from
    any (x, y, z)): a vertex is at vertices[i] + origin in the file's coordinates
    (``world_vertices``). Meshes of trees built from positions near zero have a zero origin.
    attributes: dict name -> (n,) float32, one value per vertex (``"filled"``: 1 where a
    watertight mesh was filled in, not fitted). up: "y" or "z", the up axis of the input it was
    made from (PLY files record "z"; GLB files turn such a mesh to glTF's +y up).
    report: what made a mesh that Tree.mesh(), reconstruct_mesh() or a run's join() returns
    (the JSON report of ``clustersurf mesh --json``: vertices, triangles, boundary_edges,
    voxel_size, surface_cells, trimmed_triangles, refitted_vertices, mesh_seconds, ...; a
    closed mesh's ``check``); empty for a mesh read from a file or made by hand.
    """

    vertices: np.ndarray
    faces: np.ndarray
    normals: Optional[np.ndarray] = None
    colors: Optional[np.ndarray] = None
    origin: np.ndarray = field(default_factory=lambda: np.zeros(3))
    attributes: Dict[str, np.ndarray] = field(default_factory=dict)
    up: str = "y"
    report: Dict[str, Any] = field(default_factory=dict)

    def __setattr__(self, name: str, value: Any) -> None:
        if name == "origin":
            value = _origin(value)
        elif name == "attributes":
            value = _attributes(value, len(self.vertices))
        elif name == "up":
            value = _up(value)
        object.__setattr__(self, name, value)

    @property
    def world_vertices(self) -> np.ndarray:
        """vertices + origin: the vertices in the file's coordinates, a new (n, 3) float64 array."""
        return _world(self.vertices, self.origin)

    def astuple(self) -> tuple:
        """(vertices, faces, normals, colors), the arrays themselves (not copies); the vertices
        are relative to ``origin``, which the tuple leaves out."""
        return self.vertices, self.faces, self.normals, self.colors

    def to_open3d(self) -> "open3d.geometry.TriangleMesh":
        """An open3d.geometry.TriangleMesh with the vertices in the file's coordinates (vertices +
        origin), the faces, and the vertex normals and colors (as floats in [0, 1]) when present.
        Raises ImportError without Open3D (Debian: python3-open3d)."""
        from ._open3d import mesh_to_open3d

        return mesh_to_open3d(self)


def _surface_parts(obj: Any) -> Tuple[Any, Any, Any, Any, Any, Any, Any]:
    """What the bindings take from a mesh or cloud object, None for what it lacks:
    (vertices, faces, normals, colors, origin, scanner_positions, scanner_of_point, up).

    clustersurf's Mesh and PointCloud give all they have, and so do Open3D point clouds and
    meshes (through from_open3d()). Any other object gives its ``.vertices`` (or
    ``.positions``, or ``.points``), its ``.faces`` (or ``.triangles``; none: a point set) and its ``.origin``
    if it has one, as numpy arrays (trimesh.Trimesh, ...); its normals and colors are not read,
    as their conventions differ (trimesh's colors are RGBA).
    """
    if type(obj).__module__.startswith("open3d"):
        from ._open3d import from_open3d

        obj = from_open3d(obj)
    if isinstance(obj, PointCloud):
        return (obj.positions, None, obj.normals, obj.colors, obj.origin, obj.scanner_positions,
                obj.scanner_of_point, obj.up)
    if isinstance(obj, Mesh):
        return obj.vertices, obj.faces, obj.normals, obj.colors, obj.origin, None, None, obj.up
    vertices = getattr(obj, "vertices", None)
    if vertices is None:
        vertices = getattr(obj, "positions", None)
    if vertices is None:
        vertices = getattr(obj, "points", None)
    faces = getattr(obj, "faces", None)
    if faces is None:
        faces = getattr(obj, "triangles", None)
    origin = getattr(obj, "origin", None)
    return (None if vertices is None else np.asarray(vertices), None if faces is None else np.asarray(faces), None,
            None, origin, None, None, None)
