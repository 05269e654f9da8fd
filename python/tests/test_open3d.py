"""Mesh.to_open3d(), PointCloud.to_open3d() and from_open3d() (skipped without Open3D)."""

import builtins

import numpy as np
import pytest

import clustersurf

from conftest import sphere_points
from test_scanner_fields import georeferenced_las, read_or_skip

try:
    import open3d as o3d
except (ImportError, OSError) as e:  # pragma: no cover - depends on the machine
    o3d = None
    OPEN3D_MISSING = f"Open3D does not import ({e}); Debian: python3-open3d"
else:
    OPEN3D_MISSING = ""

needs_open3d = pytest.mark.skipif(o3d is None, reason=OPEN3D_MISSING)


def colored_mesh():
    """A tetrahedron around zero (where readers and from_open3d leave it: see the shift tests)."""
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64) * 0.3 - 0.1
    vertices[0, 0] = -0.0  # even the sign of zero survives
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32)
    normals = vertices / np.linalg.norm(vertices + 1e-3, axis=1, keepdims=True)
    colors = np.array([[0, 1, 2], [127, 128, 129], [250, 254, 255], [3, 77, 200]], dtype=np.uint8)
    return clustersurf.Mesh(vertices, faces, normals, colors)


def bits(a):
    return np.ascontiguousarray(a).view(np.uint64)


@needs_open3d
def test_mesh_round_trip_through_open3d_is_bit_exact():
    mesh = colored_mesh()
    o3d_mesh = mesh.to_open3d()
    assert isinstance(o3d_mesh, o3d.geometry.TriangleMesh)
    np.testing.assert_array_equal(np.asarray(o3d_mesh.triangles), mesh.faces)
    back = clustersurf.from_open3d(o3d_mesh)
    assert isinstance(back, clustersurf.Mesh)
    np.testing.assert_array_equal(bits(back.vertices), bits(mesh.vertices))
    np.testing.assert_array_equal(bits(back.normals), bits(mesh.normals))
    assert back.faces.dtype == np.int32 and back.colors.dtype == np.uint8
    np.testing.assert_array_equal(back.faces, mesh.faces)
    np.testing.assert_array_equal(back.colors, mesh.colors)
    np.testing.assert_array_equal(back.origin, np.zeros(3))
    # Without normals and colors, none come back.
    bare = clustersurf.from_open3d(clustersurf.Mesh(mesh.vertices, mesh.faces).to_open3d())
    assert bare.normals is None and bare.colors is None


@needs_open3d
def test_tree_mesh_round_trip(sphere_tree):
    mesh = sphere_tree.mesh(resolution=24)
    back = clustersurf.from_open3d(mesh.to_open3d())
    for a, b in zip(mesh.astuple(), back.astuple()):
        if a is None:
            assert b is None
        else:
            np.testing.assert_array_equal(a, b)


@needs_open3d
def test_mesh_away_from_zero_comes_back_shifted_exactly():
    # As read_points() does with clouds, from_open3d moves a mesh whose box lies far from zero
    # (along y and z here) next to it; the coordinates stay bit for bit in vertices + origin.
    mesh = colored_mesh()
    mesh.vertices = mesh.vertices * [1, 1e-3, 1e-3] + [0.0, 370.0, -1225.0]
    back = clustersurf.from_open3d(mesh.to_open3d())
    assert back.origin[0] == 0 and back.origin[1] > 300 and back.origin[2] < -1200
    np.testing.assert_array_equal(back.world_vertices, mesh.vertices)
    again = clustersurf.from_open3d(back.to_open3d())  # the shift's own output is left as it is
    np.testing.assert_array_equal(bits(again.vertices), bits(back.vertices))
    np.testing.assert_array_equal(again.origin, back.origin)


@needs_open3d
def test_the_shift_is_the_readers(tmp_path):
    # Geometry a few diagonals from zero stays where it is, far geometry moves, for from_open3d
    # as for read_points() of the same points in a file.
    import open3d as o3d
    base = colored_mesh().vertices
    for offset, moved in (([0.0, 3.7, -6.0], False), ([0.0, 3.7, -12.25], True), ([0.0, 370.0, -1225.0], True)):
        points = base + offset
        pcd = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
        o3d.io.write_point_cloud(str(tmp_path / "p.ply"), pcd)
        read = clustersurf.read_points(tmp_path / "p.ply")
        back = clustersurf.from_open3d(pcd)
        np.testing.assert_array_equal(back.origin, read.origin)
        assert bool(back.origin.any()) == moved


@needs_open3d
def test_mesh_with_origin_goes_to_file_coordinates():
    mesh = colored_mesh()
    mesh.origin = (684000.0, 5712000.0, 0.0)
    o3d_mesh = mesh.to_open3d()
    np.testing.assert_array_equal(np.asarray(o3d_mesh.vertices), mesh.world_vertices)
    back = clustersurf.from_open3d(o3d_mesh)
    np.testing.assert_array_equal(back.world_vertices, mesh.world_vertices)
    assert np.abs(back.vertices).max() < 1  # moved next to zero again, as the readers do
    kept = clustersurf.from_open3d(o3d_mesh, shift=False)
    np.testing.assert_array_equal(kept.vertices, mesh.world_vertices)
    np.testing.assert_array_equal(kept.origin, np.zeros(3))


@needs_open3d
def test_cloud_with_origin_to_open3d_has_file_coordinates(tmp_path):
    path, coords, _, _ = georeferenced_las(tmp_path)
    cloud = read_or_skip(path)
    assert cloud.origin.any()
    pcd = cloud.to_open3d()
    assert isinstance(pcd, o3d.geometry.PointCloud)
    np.testing.assert_array_equal(np.asarray(pcd.points), coords)
    back = clustersurf.from_open3d(pcd)
    assert isinstance(back, clustersurf.PointCloud)
    # The readers' shift, recomputed from the file's coordinates: the same cloud.
    np.testing.assert_array_equal(back.origin, cloud.origin)
    np.testing.assert_array_equal(back.positions, cloud.positions)


@needs_open3d
def test_cloud_round_trip_with_normals_and_colors():
    points, normals = sphere_points(300)
    colors = (np.arange(900) % 256).astype(np.uint8).reshape(-1, 3)
    cloud = clustersurf.PointCloud(points, normals, colors, origin=(0.0, 0.0, 2.0))
    pcd = cloud.to_open3d()
    np.testing.assert_array_equal(np.asarray(pcd.points), points + [0, 0, 2.0])
    np.testing.assert_array_equal(np.asarray(pcd.normals), normals)
    back = clustersurf.from_open3d(pcd, shift=False)
    np.testing.assert_array_equal(back.positions, points + [0, 0, 2.0])
    np.testing.assert_array_equal(back.colors, colors)
    assert back.attributes == {} and back.scanner_of_point is None
    # What comes back is accepted everywhere a cloud is.
    clustersurf.reconstruct(back, min_points=10)


@needs_open3d
def test_open3d_objects_are_mesh_arguments_and_tensor_geometry_converts():
    mesh = colored_mesh()
    o3d_mesh = mesh.to_open3d()
    e = clustersurf.compare_surfaces(o3d_mesh, mesh, samples=500)
    assert e == clustersurf.compare_surfaces(mesh.vertices, mesh.faces, mesh.vertices, mesh.faces, samples=500)
    assert e["chamfer"] < 1e-12
    tensor = o3d.t.geometry.TriangleMesh.from_legacy(o3d_mesh, vertex_dtype=o3d.core.Dtype.Float64)
    np.testing.assert_array_equal(clustersurf.from_open3d(tensor).vertices, mesh.vertices)
    with pytest.raises(TypeError, match="TriangleMesh or PointCloud"):
        clustersurf.from_open3d(o3d.geometry.LineSet())


@needs_open3d
def test_an_open3d_cloud_goes_straight_into_the_pipeline():
    # An Open3D point cloud (normals and colors) is taken as from_open3d() gives it.
    points, normals = sphere_points(3000)
    cloud = clustersurf.PointCloud(points, normals, np.where(points[:, 2:] > 0, [200, 30, 30], [20, 40, 200]).astype(np.uint8))
    o3d_cloud = cloud.to_open3d()
    mesh = clustersurf.reconstruct_mesh(o3d_cloud)
    expected = clustersurf.reconstruct_mesh(clustersurf.from_open3d(o3d_cloud))
    np.testing.assert_array_equal(mesh.vertices, expected.vertices)
    np.testing.assert_array_equal(mesh.faces, expected.faces)
    assert mesh.colors is not None
    np.testing.assert_array_equal(mesh.colors, expected.colors)
    assert clustersurf.reconstruct(o3d_cloud).to_bytes() == clustersurf.reconstruct(cloud).to_bytes()


def test_missing_open3d_names_the_debian_package(monkeypatch):
    real_import = builtins.__import__

    def no_open3d(name, *args, **kwargs):
        if name == "open3d" or name.startswith("open3d."):
            raise ImportError("No module named 'open3d'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_open3d)
    with pytest.raises(ImportError, match="python3-open3d"):
        colored_mesh().to_open3d()
    with pytest.raises(ImportError, match="python3-open3d"):
        clustersurf.from_open3d(object())
