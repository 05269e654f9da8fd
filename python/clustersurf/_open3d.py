"""Conversions to and from Open3D, which is optional: it is imported only when one is called.

Open3D has no origin: its coordinates are the file's (a clustersurf object's relative
coordinates + origin). Colors are floats in [0, 1] there, uint8 here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Tuple, Union

import numpy as np

from . import _clustersurf as _cs
from ._types import Mesh, PointCloud

if TYPE_CHECKING:
    import open3d


def _import_open3d() -> Any:
    try:
        import open3d
    except (ImportError, OSError) as e:  # OSError: a shared library of the wheel is missing
        raise ImportError(
            "this needs Open3D, which is not installed or does not load: install the Debian package "
            f"python3-open3d (or `pip install open3d`) ({e})") from e
    return open3d


def _vectors(o3d: Any, array: np.ndarray) -> Any:
    return o3d.utility.Vector3dVector(np.ascontiguousarray(array, dtype=np.float64))


def _float_colors(colors: np.ndarray) -> np.ndarray:
    return np.asarray(colors, dtype=np.float64) / 255.0


def _byte_colors(colors: np.ndarray) -> np.ndarray:
    return np.clip(np.rint(np.asarray(colors, dtype=np.float64) * 255.0), 0, 255).astype(np.uint8)


def mesh_to_open3d(mesh: Mesh) -> "open3d.geometry.TriangleMesh":
    """Mesh.to_open3d()."""
    o3d = _import_open3d()
    out = o3d.geometry.TriangleMesh(
        _vectors(o3d, mesh.world_vertices),
        o3d.utility.Vector3iVector(np.ascontiguousarray(mesh.faces, dtype=np.int32).reshape(-1, 3)))
    if mesh.normals is not None:
        out.vertex_normals = _vectors(o3d, mesh.normals)
    if mesh.colors is not None:
        out.vertex_colors = _vectors(o3d, _float_colors(mesh.colors))
    return out


def cloud_to_open3d(cloud: PointCloud) -> "open3d.geometry.PointCloud":
    """PointCloud.to_open3d()."""
    o3d = _import_open3d()
    out = o3d.geometry.PointCloud(_vectors(o3d, cloud.world_positions))
    if cloud.normals is not None:
        out.normals = _vectors(o3d, cloud.normals)
    if cloud.colors is not None:
        out.colors = _vectors(o3d, _float_colors(cloud.colors))
    return out


def _shift_to_origin(positions: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(positions - shift, shift) by the readers' rule, the library's own (origin_shift() in C++):
    along each axis whose bounding-box center lies more than 16 diagonals and more than the box's
    width from zero, the center moves to zero. Both the subtraction and adding the shift back
    are then exact."""
    if len(positions) == 0 or not np.isfinite(positions).all():
        return positions, np.zeros(3)
    shift = np.asarray(_cs._origin_shift(positions.min(axis=0), positions.max(axis=0)))
    if not shift.any():
        return positions, np.zeros(3)
    return positions - shift, shift


def from_open3d(obj: Union["open3d.geometry.TriangleMesh", "open3d.geometry.PointCloud"], *,
                shift: bool = True) -> Union[Mesh, PointCloud]:
    """A clustersurf Mesh from an Open3D TriangleMesh, or a PointCloud from an Open3D PointCloud.

    ``obj``: an open3d.geometry.TriangleMesh or PointCloud (or their open3d.t.geometry tensor
    versions). Positions are copied as float64, faces as int32, normals when Open3D has them,
    colors from floats in [0, 1] to uint8. ``shift`` (default True): move geometry that lies far
    from zero next to it, as read_points() does, keeping its place in ``origin`` (exactly:
    ``world_positions`` / ``world_vertices`` are Open3D's coordinates bit for bit); False keeps
    Open3D's coordinates as they are, with a zero origin. Raises TypeError for other objects.
    """
    o3d = _import_open3d()
    if hasattr(obj, "to_legacy") and not isinstance(obj, (o3d.geometry.TriangleMesh, o3d.geometry.PointCloud)):
        obj = obj.to_legacy()
    if isinstance(obj, o3d.geometry.TriangleMesh):
        vertices = np.array(obj.vertices, dtype=np.float64).reshape(-1, 3)
        origin = np.zeros(3)
        if shift:
            vertices, origin = _shift_to_origin(vertices)
        return Mesh(vertices, np.array(obj.triangles, dtype=np.int32).reshape(-1, 3),
                    normals=np.array(obj.vertex_normals, dtype=np.float64) if obj.has_vertex_normals() else None,
                    colors=_byte_colors(np.asarray(obj.vertex_colors)) if obj.has_vertex_colors() else None,
                    origin=origin)
    if isinstance(obj, o3d.geometry.PointCloud):
        positions = np.array(obj.points, dtype=np.float64).reshape(-1, 3)
        origin = np.zeros(3)
        if shift:
            positions, origin = _shift_to_origin(positions)
        return PointCloud(positions,
                          normals=np.array(obj.normals, dtype=np.float64) if obj.has_normals() else None,
                          colors=_byte_colors(np.asarray(obj.colors)) if obj.has_colors() else None,
                          origin=origin)
    raise TypeError(f"from_open3d takes an open3d.geometry.TriangleMesh or PointCloud, not {type(obj).__name__}")
