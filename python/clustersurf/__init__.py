"""clustersurf: surfaces from point clouds by hierarchical clustering.

Build a binary tree of point clusters with a small surface proxy per cluster, blend the leaf
proxies into one implicit surface f (positive outside), then mesh it, evaluate it or render it::

    import clustersurf
    cloud = clustersurf.read_points("data/bunny.ply")
    mesh = clustersurf.reconstruct_mesh(cloud)      # == `clustersurf reconstruct IN --mesh OUT`
    clustersurf.write_mesh("bunny.ply", mesh)
    tree = clustersurf.reconstruct(cloud)           # options as the CLI's
    mesh = tree.mesh()                              # the same Mesh: trimmed to the points it keeps
    tree.save("bunny.cstree")                       # == `clustersurf reconstruct`

Arrays are numpy (n, 3) float64 (float32 input is converted). A PointCloud's positions and a
Mesh's vertices are relative to its ``origin`` (zero unless a file lay far from zero); their
``world_positions`` / ``world_vertices`` are the file's coordinates. Wherever a mesh is taken,
a Mesh, trimesh.Trimesh or Open3D mesh (anything with ``.vertices`` and ``.faces`` or
``.triangles``) may stand for its arrays; to_open3d() / from_open3d() convert to and from
Open3D (optional, imported when used). Long operations release the GIL. Files larger than
memory: reconstruct_file(path, memory_limit="4G", work_dir=...); on a Dask cluster:
clustersurf.distributed (``python3 -m clustersurf.distributed IN --mesh OUT``).
Errors are raised as InputError (malformed file), IoError (an OSError), OptionError (a
ValueError) or Cancelled, all subclasses of clustersurf.Error, with the CLI's messages.
"""

from ._open3d import from_open3d
from ._types import Mesh, PointCloud
from ._clustersurf import (
    Cancelled,
    Error,
    InputError,
    IoError,
    Node,
    OptionError,
    TiledRun,
    Tree,
    __version__,
    compare_surfaces,
    load,
    option_schema,
    read_mesh,
    read_points,
    reconstruct,
    reconstruct_mesh,
    reconstruct_file,
    region_points_for_memory,
    check_mesh,
    measure_registration,
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
    "TiledRun",
    "Tree",
    "__version__",
    "compare_surfaces",
    "evaluate",
    "from_open3d",
    "load",
    "option_schema",
    "read_mesh",
    "read_points",
    "reconstruct",
    "reconstruct_mesh",
    "reconstruct_file",
    "region_points_for_memory",
    "check_mesh",
    "measure_registration",
    "sample_surface",
    "scan_surface",
    "write_mesh",
    "write_points",
]
