"""Plain value types returned by the readers: numpy arrays with names."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np


@dataclass
class PointCloud:
    """Points with optional per-point normals and colors.

    positions: (n, 3) float64; normals: (n, 3) float64 or None; colors: (n, 3) uint8 or None.
    Pass it to reconstruct() directly (its normals are used) or take its arrays.
    """

    positions: np.ndarray
    normals: Optional[np.ndarray] = None
    colors: Optional[np.ndarray] = None

    def __len__(self) -> int:
        return len(self.positions)


@dataclass
class Mesh:
    """An indexed triangle mesh.

    vertices: (n, 3) float64; faces: (m, 3) int32; normals: (n, 3) float64 or None;
    colors: (n, 3) uint8 or None (per vertex).
    """

    vertices: np.ndarray
    faces: np.ndarray
    normals: Optional[np.ndarray] = None
    colors: Optional[np.ndarray] = None

    def astuple(self) -> tuple:
        """(vertices, faces, normals, colors), the arrays themselves (not copies)."""
        return self.vertices, self.faces, self.normals, self.colors
