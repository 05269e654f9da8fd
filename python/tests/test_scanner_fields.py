"""What scanner files bring to Python (origin, attributes, scanners) and mesh arguments by duck
typing: any object with .vertices and .faces (or .triangles) stands for its arrays."""

import struct

import numpy as np
import pytest

import clustersurf

from conftest import sphere_points

TETRAHEDRON = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64),
               np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32))


class DuckMesh:
    """Neither a clustersurf type nor a numpy array: just vertices and faces, as trimesh has."""

    def __init__(self, vertices, faces):
        self.vertices = vertices
        self.faces = faces


class TriangleDuck:
    """Open3D's spelling: .triangles instead of .faces, lists instead of arrays."""

    def __init__(self, vertices, triangles):
        self.vertices = vertices.tolist()
        self.triangles = triangles.tolist()


def las_file(path, ints, scale, offset, intensity, classification):
    """A minimal LAS 1.2 file, point format 0, from integer coordinates."""
    n = len(ints)
    coords = ints * scale + offset
    header = bytearray(227)
    header[0:4] = b"LASF"
    header[24:26] = bytes([1, 2])
    struct.pack_into("<HIIBHI", header, 94, 227, 227, 0, 0, 20, n)
    struct.pack_into("<3d3d6d", header, 131, *scale, *offset, coords[:, 0].max(), coords[:, 0].min(),
                     coords[:, 1].max(), coords[:, 1].min(), coords[:, 2].max(), coords[:, 2].min())
    records = b"".join(struct.pack("<3iHBBbBH", *ints[i], intensity[i], 0, classification[i], 0, 0, 0)
                       for i in range(n))
    path.write_bytes(bytes(header) + records)
    return coords


def read_or_skip(path):
    try:
        return clustersurf.read_points(path)
    except clustersurf.InputError as e:
        if "not yet readable" in str(e):
            pytest.skip(f"the reader of {path.suffix} has not landed: {e}")
        raise


def georeferenced_las(tmp_path):
    rng = np.random.default_rng(4)
    ints = rng.integers(-20000, 20000, size=(200, 3)).astype(np.int32)
    scale, offset = np.array([0.001, 0.001, 0.01]), np.array([512000.0, 5400000.0, 300.0])
    intensity = rng.integers(0, 65535, size=200)
    classification = rng.integers(0, 31, size=200)
    path = tmp_path / "scan.las"
    coords = las_file(path, ints, scale, offset, intensity, classification)
    return path, coords, intensity, classification


def test_las_attributes_and_origin(tmp_path):
    path, coords, intensity, classification = georeferenced_las(tmp_path)
    cloud = read_or_skip(path)
    assert list(cloud.attributes) == ["intensity", "classification"]
    for name, expected in (("intensity", intensity), ("classification", classification)):
        assert cloud.attributes[name].dtype == np.float32 and cloud.attributes[name].shape == (200,)
        np.testing.assert_array_equal(cloud.attributes[name], expected.astype(np.float32))
    # Far from zero: moved next to it, the place kept exactly in the origin.
    assert cloud.origin.dtype == np.float64 and cloud.origin.shape == (3,)
    assert cloud.origin[0] > 500000 and np.abs(cloud.positions).max() < 1000
    np.testing.assert_array_equal(cloud.world_positions, coords)
    assert cloud.scanner_positions is None and cloud.scanner_of_point is None
    # The writers put the points back at their origin, bit for bit.
    clustersurf.write_points(tmp_path / "back.ply", cloud)
    again = clustersurf.read_points(tmp_path / "back.ply")
    np.testing.assert_array_equal(again.world_positions, coords)


def test_attributes_dict_round_trip():
    points, normals = sphere_points(50)
    intensity = np.arange(50, dtype=np.float64) * 0.5
    cloud = clustersurf.PointCloud(points, normals, attributes={"intensity": intensity, "label": list(range(50))})
    assert set(cloud.attributes) == {"intensity", "label"}
    assert all(a.dtype == np.float32 and a.shape == (50,) for a in cloud.attributes.values())
    np.testing.assert_array_equal(cloud.attributes["intensity"], intensity.astype(np.float32))
    kept = cloud.attributes["label"]
    cloud.attributes = dict(cloud.attributes)  # setting float32 arrays keeps them as they are
    assert cloud.attributes["label"] is kept
    cloud.attributes = {"reflectance": np.ones(50, dtype=np.float32)}
    assert list(cloud.attributes) == ["reflectance"]
    with pytest.raises(clustersurf.OptionError, match="one value per point"):
        cloud.attributes = {"short": np.ones(3)}
    assert clustersurf.PointCloud(points).attributes == {}


def test_origin_is_settable_and_written(tmp_path):
    vertices, faces = TETRAHEDRON
    mesh = clustersurf.Mesh(vertices, faces)
    np.testing.assert_array_equal(mesh.origin, np.zeros(3))
    np.testing.assert_array_equal(mesh.world_vertices, vertices)
    mesh.origin = (1000.0, -2000.0, 0.5)
    assert mesh.origin.dtype == np.float64
    np.testing.assert_array_equal(mesh.world_vertices, vertices + [1000.0, -2000.0, 0.5])
    with pytest.raises(clustersurf.OptionError, match="origin"):
        mesh.origin = (1, 2)
    clustersurf.write_mesh(tmp_path / "t.ply", mesh)
    back = clustersurf.read_mesh(tmp_path / "t.ply")
    np.testing.assert_array_equal(back.world_vertices, mesh.world_vertices)
    np.testing.assert_array_equal(back.faces, faces)
    # The origin keyword overrides the object's; arrays have none unless given.
    clustersurf.write_mesh(tmp_path / "z.obj", mesh, origin=(0, 0, 0))
    np.testing.assert_array_equal(clustersurf.read_mesh(tmp_path / "z.obj").world_vertices, vertices)
    clustersurf.write_points(tmp_path / "p.xyz", vertices, origin=[10, 20, 30])
    np.testing.assert_array_equal(clustersurf.read_points(tmp_path / "p.xyz").world_positions, vertices + [10, 20, 30])


def test_scanners_pass_through_and_are_checked():
    points, normals = sphere_points(40)
    cloud = clustersurf.PointCloud(points, normals, scanner_positions=np.array([[0, 0, 5.0], [0, 0, -5.0]]),
                                   scanner_of_point=(points[:, 2] < 0).astype(np.uint32))
    clustersurf.reconstruct(cloud, min_points=10)  # accepted with its scanners
    cloud.scanner_of_point = np.full(40, 2, dtype=np.uint32)
    with pytest.raises(clustersurf.OptionError, match="scan index"):
        clustersurf.reconstruct(cloud, min_points=10)


@pytest.mark.parametrize("duck", [DuckMesh, TriangleDuck])
def test_duck_typed_meshes_are_accepted(tmp_path, duck):
    vertices, faces = TETRAHEDRON
    obj = duck(vertices, faces)
    by_arrays = clustersurf.compare_surfaces(vertices, faces, vertices, faces, samples=500)
    for args in ((obj, obj), (obj, vertices, faces), (vertices, faces, obj)):
        e = clustersurf.compare_surfaces(*args, samples=500)
        assert e == by_arrays
    assert clustersurf.compare_surfaces(obj, ref_vertices=obj, samples=500) == by_arrays
    a = clustersurf.sample_surface(obj, n=300, seed=2)
    np.testing.assert_array_equal(a.positions, clustersurf.sample_surface(vertices, faces, n=300, seed=2).positions)
    clustersurf.write_mesh(tmp_path / "duck.off", obj)
    clustersurf.write_mesh(tmp_path / "duck.ply", obj)
    back = clustersurf.read_mesh(tmp_path / "duck.ply")
    np.testing.assert_array_equal(back.vertices, vertices)
    np.testing.assert_array_equal(back.faces, faces)


def test_compare_surfaces_takes_mesh_and_cloud_objects(bunny_file):
    mesh = clustersurf.read_mesh(bunny_file)
    cloud = clustersurf.read_points(bunny_file)
    e = clustersurf.compare_surfaces(mesh, cloud, samples=2000)
    assert e == clustersurf.compare_surfaces(mesh.vertices, mesh.faces, cloud.positions, None, ref_normals=cloud.normals,
                                             samples=2000)
    assert e["normal_consistency"] is not None  # the cloud's own normals
    # Different origins: compared where they are in the world, not in their own frames.
    moved = clustersurf.Mesh(mesh.vertices - [100.0, 0, 0], mesh.faces, origin=(100.0, 0, 0))
    assert clustersurf.compare_surfaces(moved, mesh, samples=2000)["chamfer"] < 1e-9
    with pytest.raises(clustersurf.OptionError, match="reference"):
        clustersurf.compare_surfaces(mesh)
    with pytest.raises(clustersurf.OptionError, match="two surfaces"):
        clustersurf.compare_surfaces(mesh, mesh, mesh)


def test_faces_are_required_for_arrays(tmp_path):
    vertices, _ = TETRAHEDRON
    with pytest.raises(clustersurf.OptionError, match="faces are required"):
        clustersurf.sample_surface(vertices, n=10)
    with pytest.raises(clustersurf.OptionError, match="faces are required"):
        clustersurf.write_mesh(tmp_path / "x.ply", vertices)


def test_tree_keeps_the_origin_of_its_input():
    points, normals = sphere_points()
    cloud = clustersurf.PointCloud(points, normals, origin=(600000.0, 0, 0))
    tree = clustersurf.reconstruct(cloud)
    np.testing.assert_array_equal(tree.origin, [600000.0, 0, 0])
    again = clustersurf.Tree.from_bytes(tree.to_bytes())  # stored in the tree file
    np.testing.assert_array_equal(again.origin, tree.origin)
    mesh = again.mesh(resolution=32, points=cloud)
    np.testing.assert_array_equal(mesh.origin, [600000.0, 0, 0])
    np.testing.assert_array_equal(mesh.world_vertices, mesh.vertices + [600000.0, 0, 0])
    plain = clustersurf.reconstruct(points, normals=normals)
    np.testing.assert_array_equal(plain.origin, np.zeros(3))
    # A loaded tree has no points: it meshes without the trim and the vertex refit they drive.
    np.testing.assert_array_equal(plain.mesh(resolution=32, refit_points=0).vertices,
                                  again.mesh(resolution=32).vertices)
