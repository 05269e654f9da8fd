"""Closed meshes and inside/outside from Python: Tree.mesh(watertight=True, fill_holes=...) and
Tree.inside(), on a sphere whose cap was never scanned."""

import numpy as np

import clustersurf

from conftest import sphere_points


def cap_cut_tree():
    points, normals = sphere_points(8000)
    keep = points[:, 2] < 0.6
    return clustersurf.reconstruct(points[keep], normals=normals[keep])


def edges_with_one_face(faces):
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int((counts == 1).sum())


def test_watertight_mesh_is_closed_and_marks_the_fill():
    tree = cap_cut_tree()
    assert edges_with_one_face(tree.mesh().faces) > 0  # the cap is open without the option
    closed = tree.mesh(watertight=True)
    assert edges_with_one_face(closed.faces) == 0
    filled = closed.attributes["filled"]
    assert filled.dtype == np.float32 and filled.shape == (len(closed.vertices),)
    assert filled.any()
    assert (closed.vertices[filled > 0, 2] > 0.5).all()  # only the cap was invented
    report = clustersurf.check_mesh(closed)
    assert report["watertight"] and report["printable"] and report["genus"] == 0 and report["problems"] == []
    open_report = clustersurf.check_mesh(tree.mesh())
    assert not open_report["printable"]
    assert any(p.endswith("boundary edges") for p in open_report["problems"])  # the CLI's words
    smaller = tree.mesh(watertight=True, decimate=len(closed.faces) // 4)
    assert len(smaller.faces) <= len(closed.faces) // 4 and edges_with_one_face(smaller.faces) == 0
    # The solid the closed mesh bounds: scored by volume IoU, which an open mesh has none of.
    assert clustersurf.compare_surfaces(closed, closed, samples=2000)["volume_iou"] == 1.0
    assert clustersurf.compare_surfaces(tree.mesh(), closed, samples=2000)["volume_iou"] is None
    # An opening wider than the limit stays open.
    assert edges_with_one_face(tree.mesh(watertight=True, fill_holes=0.5).faces) > 0


def test_inside_everywhere():
    tree = cap_cut_tree()
    inside = tree.inside([[0, 0, 0], [0, 0, -0.5], [0, 0, 0.55], [0, 0, 1.5], [3, 0, 0], [100, 0, 0]])
    assert inside.dtype == np.bool_
    assert inside.tolist() == [True, True, True, False, False, False]
