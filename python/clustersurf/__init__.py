"""clustersurf: surfaces from point clouds by hierarchical clustering.

Build a binary tree of point clusters with a small surface proxy per cluster, blend the leaf
proxies into one implicit surface f (positive outside), then mesh it, evaluate it or render it::

    import clustersurf
    cloud = clustersurf.read_points("data/bunny.ply")
    tree = clustersurf.reconstruct(cloud.positions, cloud.normals)   # options as the CLI's
    mesh = tree.mesh(points=cloud)                                  # a Mesh, trimmed to the points
    clustersurf.write_mesh("bunny.ply", mesh.vertices, mesh.faces, mesh.normals)
    tree.save("bunny.cstree")                                       # == `clustersurf reconstruct`

Arrays are numpy (n, 3) float64 (float32 input is converted). Long operations release the GIL.
Errors are raised as InputError (malformed file), IoError (an OSError), OptionError (a
ValueError) or Cancelled, all subclasses of clustersurf.Error, with the CLI's messages.
"""

from ._types import Mesh, PointCloud
from ._clustersurf import (
    Cancelled,
    Error,
    InputError,
    IoError,
    Node,
    OptionError,
    Tree,
    __version__,
    compare_surfaces,
    load,
    read_mesh,
    read_points,
    reconstruct,
    sample_surface,
    scan_surface,
    write_mesh,
    write_points,
)

evaluate = compare_surfaces  # the old name of compare_surfaces

__all__ = [
    "Cancelled",
    "Error",
    "InputError",
    "IoError",
    "Mesh",
    "Node",
    "OptionError",
    "PointCloud",
    "Tree",
    "__version__",
    "compare_surfaces",
    "evaluate",
    "load",
    "read_mesh",
    "read_points",
    "reconstruct",
    "sample_surface",
    "scan_surface",
    "write_mesh",
    "write_points",
]
