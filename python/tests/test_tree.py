"""reconstruct() and the Tree: info, nodes, evaluation, meshing, rendering, files, errors."""

import pickle

import numpy as np
import pytest

import clustersurf

from conftest import sphere_points


def test_info_has_the_cli_keys(sphere_tree):
    info = sphere_tree.info()
    for key in ("nodes", "leaves", "depth", "input_points", "has_point_leaves", "bbox_min", "bbox_max", "diagonal",
                "leaf_proxies", "leaf_size", "leaf_rms_error", "leaves_over_threshold", "noise_sigma",
                "error_threshold", "parameters"):
        assert key in info
    assert info["nodes"] == len(sphere_tree) == 2 * info["leaves"] - 1
    assert info["input_points"] == 2000
    p = info["parameters"]
    # min_points and alpha "auto" resolve, for this clean sphere, to the clean values.
    assert (p["proxy"], p["splitter"], p["min_points"], p["alpha"], p["support_factor"], p["seed"]) == (
        "poly", "split-plane", 12, 0.75, 1.0, 1)


def test_nodes_form_the_tree(sphere_tree):
    nodes = sphere_tree.nodes
    assert nodes[0].parent is None and nodes[0].index == 0
    assert sphere_tree.root.point_count == 2000
    leaves = sphere_tree.leaves
    assert leaves.dtype == np.int32 and len(leaves) == sphere_tree.info()["leaves"]
    for n in nodes:
        if n.is_leaf:
            assert n.children == [] and n.left is None
        else:
            left, right = n.children
            assert (left.index, right.index) == (n.left, n.right)
            assert left.parent == n.index and left.depth == n.depth + 1
            assert left.point_count + right.point_count == n.point_count
        center, radius = n.support
        assert center.shape == (3,) and radius > 0
        length = {"point": 3, "plane": 6, "poly": 18, "quadric": 14}[n.proxy_type]
        assert n.coefficients.shape == (length,)
        assert n.proxy["type"] == n.proxy_type
    assert sphere_tree[-1].index == len(sphere_tree) - 1
    with pytest.raises(IndexError):
        sphere_tree.node(len(sphere_tree))


def test_leaf_of_points(sphere_tree):
    leaf = sphere_tree.leaf_of_points()
    assert leaf.dtype == np.int32 and leaf.shape == (2000,)
    assert set(np.unique(leaf)) <= set(sphere_tree.leaves.tolist())
    counts = np.bincount(leaf, minlength=len(sphere_tree))
    for i in sphere_tree.leaves:
        assert counts[i] == sphere_tree.node(i).point_count


def test_no_point_leaves(sphere):
    tree = clustersurf.reconstruct(sphere[0], sphere[1], no_point_leaves=True)
    assert not tree.info()["has_point_leaves"]
    with pytest.raises(clustersurf.OptionError, match="no leaf per point"):
        tree.leaf_of_points()


def test_evaluate_is_a_signed_distance(sphere_tree):
    xyz = np.array([[0, 0, 1.05], [0, 0, 0.95], [0.0, 1.0, 0.0], [5, 5, 5]])
    f = sphere_tree.evaluate(xyz)
    assert f.shape == (4,) and f.dtype == np.float64
    assert f[0] == pytest.approx(0.05, abs=0.01)
    assert f[1] == pytest.approx(-0.05, abs=0.01)
    assert abs(f[2]) < 0.01
    assert np.isnan(f[3])  # no support reaches: undefined
    g = sphere_tree.gradient(xyz)
    assert g.shape == (4, 3)
    np.testing.assert_allclose(g[0] / np.linalg.norm(g[0]), [0, 0, 1], atol=0.05)
    assert np.isnan(g[3]).all()
    np.testing.assert_array_equal(sphere_tree.evaluate(xyz.astype(np.float32)),
                                  sphere_tree.evaluate(xyz.astype(np.float32).astype(np.float64)))


def test_mesh_is_a_closed_sphere(sphere_tree):
    vertices, faces, normals, colors = sphere_tree.mesh(resolution=48).astuple()
    assert colors is None
    assert vertices.dtype == np.float64 and faces.dtype == np.int32 and normals.shape == vertices.shape
    np.testing.assert_allclose(np.linalg.norm(vertices, axis=1), 1.0, atol=0.01)
    # Outward: the normals point away from the center.
    assert (np.einsum("ij,ij->i", vertices, normals) > 0).all()
    e = clustersurf.evaluate(vertices, faces, vertices, faces, samples=1000)  # the old name still works
    assert e["reconstruction_mesh"]["watertight"]
    coarse = sphere_tree.mesh(resolution=48, lod_depth=2).vertices
    assert len(coarse) > 0


def test_render_gives_rgba_pixels(sphere_tree):
    picture = sphere_tree.render(width=64, height=48)
    assert picture.shape == (48, 64, 4) and picture.dtype == np.uint8
    assert (picture[24, 32, :3] < 250).any()  # the sphere is in the middle
    assert tuple(picture[0, 0]) == (255, 255, 255, 255)  # white background in the corner
    clear = sphere_tree.render(width=16, height=12, background="transparent", show="clusters")
    assert clear[0, 0, 3] == 0
    with pytest.raises(clustersurf.OptionError, match="needs the input points"):
        sphere_tree.render(width=8, height=8, show="error")
    with pytest.raises(clustersurf.OptionError, match="background"):
        sphere_tree.render(width=8, height=8, background="pink")


def test_save_load_bytes_and_pickle(tmp_path, sphere_tree):
    path = tmp_path / "s.cstree"
    sphere_tree.save(path)
    assert path.read_bytes() == sphere_tree.to_bytes()
    loaded = clustersurf.load(path)
    assert loaded.to_bytes() == sphere_tree.to_bytes()
    assert pickle.loads(pickle.dumps(sphere_tree)).to_bytes() == sphere_tree.to_bytes()
    assert clustersurf.Tree.from_bytes(sphere_tree.to_bytes()).info() == sphere_tree.info()


def test_corrupt_tree_file(tmp_path, sphere_tree):
    data = bytearray(sphere_tree.to_bytes())
    data[len(data) // 2] ^= 0xFF
    path = tmp_path / "bad.cstree"
    path.write_bytes(bytes(data))
    with pytest.raises(clustersurf.InputError, match=r"bad\.cstree"):
        clustersurf.load(path)


def test_float32_and_float64_give_the_same_tree():
    points, normals = sphere_points(800)
    p32 = points.astype(np.float32)
    a = clustersurf.reconstruct(p32, normals.astype(np.float32))
    b = clustersurf.reconstruct(p32.astype(np.float64), normals.astype(np.float32).astype(np.float64))
    assert a.to_bytes() == b.to_bytes()


def test_point_cloud_object_and_options(sphere):
    cloud = clustersurf.PointCloud(sphere[0], sphere[1])
    a = clustersurf.reconstruct(cloud, proxy="quadric", tolerance=0.002, min_points=30)
    b = clustersurf.reconstruct(sphere[0], sphere[1], proxy="quadric", tolerance="0.002", min_points=30)
    old_name = clustersurf.reconstruct(sphere[0], sphere[1], proxy="quadric", max_error=0.002, min_points=30)
    assert a.to_bytes() == b.to_bytes() == old_name.to_bytes()
    info = a.info()
    assert info["parameters"]["proxy"] == "quadric"
    assert info["parameters"]["threshold_mode"] == "auto"  # the tolerance on top of the noise
    assert info["parameters"]["tolerance"] == 0.002
    blind = clustersurf.reconstruct(sphere[0], sphere[1], max_error=0.002, noise_factor=0)
    assert blind.info()["parameters"]["threshold_mode"] == "relative"
    assert blind.info()["noise_sigma"] == 0
    c = clustersurf.reconstruct(sphere[0], absolute_tolerance=0.001, splitter="lloyd", error="max")
    assert c.info()["parameters"]["threshold_mode"] == "absolute"
    assert c.info()["parameters"]["splitter"] == "lloyd"


@pytest.mark.parametrize("kwargs, message", [
    ({"proxy": "cubic"}, 'proxy must be plane, poly or quadric, not "cubic"'),
    ({"splitter": "kmeans"}, "splitter must be split-plane or lloyd"),
    ({"tolerance": "big"}, 'tolerance must be "auto" or a number >= 0, not "big"'),
    ({"tolerance": -1.0}, "tolerance must be"),
    ({"max_error": "big"}, 'tolerance must be "auto" or a number >= 0'),
    ({"max_error": 0.1, "tolerance": 0.2}, "give tolerance or its older name max_error, not both"),
    ({"min_points": 0}, 'min_points must be "auto" or a whole number from 1 to 1073741824, not "0"'),
    ({"min_points": "many"}, 'min_points must be "auto" or a whole number from 1 to 1073741824, not "many"'),
    ({"min_points": -5}, 'not "-5"'),
    ({"alpha": 0.0}, 'alpha must be "auto" or a positive number, not "0"'),
    ({"error": "mean"}, 'error must be rms or max, not "mean"'),
    ({"alpha": [1]}, "option alpha takes a number, a bool, a word or (x, y, z), not a list"),
    ({"smoothness": 1}, 'unknown option "smoothness"'),
    ({"resolution": 64}, 'unknown option "resolution"'),
])
def test_option_errors(sphere, kwargs, message):
    with pytest.raises(clustersurf.OptionError) as e:
        clustersurf.reconstruct(sphere[0], **kwargs)
    assert message in str(e.value)
    assert isinstance(e.value, ValueError)


def test_empty_and_mismatched_inputs():
    with pytest.raises(clustersurf.OptionError, match="empty point cloud"):
        clustersurf.reconstruct(np.zeros((0, 3)))
    with pytest.raises(clustersurf.OptionError, match="one row per point"):
        clustersurf.reconstruct(np.zeros((10, 3)), np.zeros((9, 3)))
    # The library's surface-extent check, as the CLI's.
    with pytest.raises(clustersurf.InputError, match="all 50 points coincide"):
        clustersurf.reconstruct(np.tile([1.5, 2.5, 3.5], (50, 1)))
    with pytest.raises(clustersurf.InputError, match="all 50 points lie on one line"):
        clustersurf.reconstruct(np.outer(np.arange(1, 51), [1.0, 2.0, 3.0]))


def test_progress_and_cancellation(sphere):
    stages = []

    def record(stage, fraction):
        stages.append((stage, fraction))

    clustersurf.reconstruct(sphere[0], sphere[1], progress=record)
    assert stages and all(0 <= f <= 1 for _, f in stages)
    with pytest.raises(clustersurf.Cancelled, match="cancelled"):
        clustersurf.reconstruct(sphere[0], sphere[1], progress=lambda stage, fraction: False)

    class Stop(Exception):
        pass

    def fail(stage, fraction):
        raise Stop("from the callback")

    with pytest.raises(Stop, match="from the callback"):
        clustersurf.reconstruct(sphere[0], sphere[1], progress=fail)


def test_ctrl_c_interrupts_a_build(sphere):
    import os
    import signal

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        # The first progress call comes from the calling thread: a SIGINT there is seen at once.
        with pytest.raises(KeyboardInterrupt):
            clustersurf.reconstruct(sphere[0], progress=lambda stage, fraction: os.kill(os.getpid(), signal.SIGINT))
    finally:
        signal.signal(signal.SIGINT, previous)


def test_crease_leaf_of_a_roof():
    # Two faces meeting at a ridge: one crease leaf (two planes, max), unless no_creases=True.
    x, y = np.meshgrid(np.linspace(-1, 1, 20), np.linspace(-1, 1, 20))
    roof = np.column_stack([x.ravel(), y.ravel(), -0.5 * np.abs(x.ravel())])
    tree = clustersurf.reconstruct(roof, noise_factor=0)
    assert len(tree) == 1 and tree.root.proxy_type == "crease"
    assert tree.info()["leaf_proxies"]["crease"] == 1 and tree.info()["parameters"]["creases"]
    proxy = tree.root.proxy
    assert set(proxy) == {"type", "a", "b", "convex"}
    assert len(tree.root.coefficients) == 13
    np.testing.assert_allclose(tree.root.proxy_value(roof), 0, atol=1e-9)
    # The ridge is sharp: above it f > 0 on one side, below f < 0, as the sides agree.
    above, below = tree.root.proxy_value(np.array([[0, 0, 0.1], [0, 0, -0.1]]))
    assert above * below < 0
    smooth = clustersurf.reconstruct(roof, noise_factor=0, no_creases=True)
    assert len(smooth) > 1 and "crease" not in {n.proxy_type for n in smooth.nodes}
