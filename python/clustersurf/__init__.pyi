# Type stubs of the package clustersurf (hand-written; python/tests/test_stubs.py checks them
# against the module). The extension's functions and classes are typed in _clustersurf.pyi;
# Mesh, PointCloud and from_open3d are plain Python, typed in _types.py and _open3d.py.

from ._clustersurf import Cancelled as Cancelled
from ._clustersurf import Error as Error
from ._clustersurf import InputError as InputError
from ._clustersurf import IoError as IoError
from ._clustersurf import Node as Node
from ._clustersurf import OptionError as OptionError
from ._clustersurf import TiledRun as TiledRun
from ._clustersurf import Tree as Tree
from ._clustersurf import __version__ as __version__
from ._clustersurf import compare_surfaces as compare_surfaces
from ._clustersurf import compare_surfaces as evaluate
from ._clustersurf import load as load
from ._clustersurf import option_schema as option_schema
from ._clustersurf import read_mesh as read_mesh
from ._clustersurf import read_points as read_points
from ._clustersurf import reconstruct as reconstruct
from ._clustersurf import reconstruct_mesh as reconstruct_mesh
from ._clustersurf import reconstruct_file as reconstruct_file
from ._clustersurf import region_points_for_memory as region_points_for_memory
from ._clustersurf import check_mesh as check_mesh
from ._clustersurf import measure_registration as measure_registration
from ._clustersurf import sample_surface as sample_surface
from ._clustersurf import scan_surface as scan_surface
from ._clustersurf import write_mesh as write_mesh
from ._clustersurf import write_points as write_points
from ._open3d import from_open3d as from_open3d
from ._types import Mesh as Mesh
from ._types import PointCloud as PointCloud

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
