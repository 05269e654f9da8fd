"""Reading and writing clouds and meshes with numpy; error classes and messages."""

import numpy as np
import pytest

import clustersurf


def test_points_round_trip_bit_exact(tmp_path, sphere):
    points, normals = sphere
    colors = (np.arange(len(points) * 3) % 256).astype(np.uint8).reshape(-1, 3)
    for name, kwargs in (("c.ply", {"double": True}), ("c.xyz", {})):
        path = tmp_path / name
        clustersurf.write_points(path, points, normals, colors if name.endswith(".ply") else None, **kwargs)
        cloud = clustersurf.read_points(path)
        assert isinstance(cloud, clustersurf.PointCloud)
        assert cloud.positions.dtype == np.float64 and cloud.positions.shape == points.shape
        np.testing.assert_array_equal(cloud.positions, points)
        np.testing.assert_array_equal(cloud.normals, normals)
        if name.endswith(".ply"):
            assert cloud.colors.dtype == np.uint8
            np.testing.assert_array_equal(cloud.colors, colors)
        else:
            assert cloud.colors is None


def test_float32_points_are_accepted(tmp_path, sphere):
    points32 = sphere[0].astype(np.float32)
    clustersurf.write_points(tmp_path / "f.ply", points32)
    cloud = clustersurf.read_points(tmp_path / "f.ply")
    np.testing.assert_array_equal(cloud.positions, points32.astype(np.float64))
    assert cloud.normals is None


def test_mesh_round_trip(tmp_path):
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])  # int64: converted
    for name in ("t.ply", "t.obj"):
        clustersurf.write_mesh(tmp_path / name, vertices, faces)
        mesh = clustersurf.read_mesh(tmp_path / name)
        assert isinstance(mesh, clustersurf.Mesh)
        assert mesh.faces.dtype == np.int32
        np.testing.assert_array_equal(mesh.vertices, vertices)
        np.testing.assert_array_equal(mesh.faces, faces)


def test_missing_file_is_an_io_error(tmp_path):
    with pytest.raises(clustersurf.IoError) as e:
        clustersurf.read_points(tmp_path / "missing.ply")
    assert isinstance(e.value, OSError) and isinstance(e.value, clustersurf.Error)
    assert "missing.ply" in str(e.value)


def test_malformed_file_names_the_line(tmp_path):
    path = tmp_path / "bad.xyz"
    path.write_text("0 0 0\n1 2 oops\n")
    with pytest.raises(clustersurf.InputError) as e:
        clustersurf.read_points(path)
    assert isinstance(e.value, ValueError)
    assert str(e.value).startswith(f"{path}:2: ")


def test_bad_shapes_are_option_errors(tmp_path):
    with pytest.raises(clustersurf.OptionError, match=r"shape \(n, 3\), not \(4, 2\)"):
        clustersurf.write_points(tmp_path / "x.ply", np.zeros((4, 2)))
    with pytest.raises(clustersurf.OptionError, match="vertex index"):
        clustersurf.write_mesh(tmp_path / "x.ply", np.zeros((3, 3)), np.array([[0, 1, 3]]))
    with pytest.raises(clustersurf.OptionError, match="finite"):
        clustersurf.reconstruct(np.full((30, 3), np.nan))


def test_sample_surface_is_deterministic(bunny_file):
    mesh = clustersurf.read_mesh(bunny_file)
    a = clustersurf.sample_surface(mesh.vertices, mesh.faces, n=1000, seed=3)
    b = clustersurf.sample_surface(mesh.vertices, mesh.faces, n=1000, seed=3)
    assert a.positions.shape == (1000, 3) and a.normals.shape == (1000, 3)
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_allclose(np.linalg.norm(a.normals, axis=1), 1.0, rtol=1e-9)


def test_evaluate_identical_surfaces(bunny_file):
    mesh = clustersurf.read_mesh(bunny_file)
    e = clustersurf.compare_surfaces(mesh.vertices, mesh.faces, mesh.vertices, mesh.faces, samples=2000)
    assert e["chamfer"] < 1e-9
    assert e["fscore"][0]["fscore"] == pytest.approx(1.0)
    assert e["reference_mesh"]["triangles"] == len(mesh.faces)
    assert e["normal_consistency"] == pytest.approx(1.0)  # meshes: triangle normals
