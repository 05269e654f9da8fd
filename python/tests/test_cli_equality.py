"""The module gives the CLI's results on the same input: same tree bytes, mesh, info, figures
and error messages."""

import json
import re
import subprocess

import numpy as np
import pytest

import clustersurf


def run(cli, *args, check=True):
    return subprocess.run([cli, "--quiet", *map(str, args)], capture_output=True, text=True, check=check)


OPTION_SETS = [
    ({}, []),
    ({"proxy": "quadric", "max_error": 0.002, "min_points": 30},
     ["--proxy", "quadric", "--max-error", "0.002", "--min-points", "30"]),
    ({"proxy": "plane", "splitter": "lloyd", "absolute_error": 0.01, "alpha": 0.9, "seed": 7},
     ["--proxy", "plane", "--splitter", "lloyd", "--absolute-error", "0.01", "--alpha", "0.9", "--seed", "7"]),
]


@pytest.mark.parametrize("kwargs, flags", OPTION_SETS)
def test_tree_bytes_equal_the_cli(tmp_path, cli, bunny_file, kwargs, flags):
    out = tmp_path / "cli.cstree"
    run(cli, "reconstruct", bunny_file, "-o", out, *flags)
    cloud = clustersurf.read_points(bunny_file)
    tree = clustersurf.reconstruct(cloud.positions, cloud.normals, **kwargs)
    assert tree.to_bytes() == out.read_bytes()
    tree.save(tmp_path / "py.cstree")
    assert (tmp_path / "py.cstree").read_bytes() == out.read_bytes()


def test_info_equals_cli_json(tmp_path, cli, bunny_file):
    out = tmp_path / "b.cstree"
    run(cli, "reconstruct", bunny_file, "-o", out)
    cli_info = json.loads(subprocess.run([cli, "--json", "info", str(out)], capture_output=True, text=True,
                                         check=True).stdout)
    info = clustersurf.load(out).info()
    cli_info.pop("file")
    info = json.loads(json.dumps(info))  # tuples become lists, as in the CLI's JSON
    assert info == cli_info


@pytest.mark.parametrize("kwargs, flags", [({"resolution": 64}, ["--resolution", "64"]),
                                           ({"resolution": 48, "lod_depth": 5}, ["--resolution", "48", "--lod-depth", "5"])])
def test_mesh_equals_the_cli(tmp_path, cli, bunny_file, kwargs, flags):
    tree_file = tmp_path / "b.cstree"
    run(cli, "reconstruct", bunny_file, "-o", tree_file)
    run(cli, "mesh", tree_file, "-o", tmp_path / "cli.ply", *flags)
    cli_mesh = clustersurf.read_mesh(tmp_path / "cli.ply")
    vertices, faces, normals, _ = clustersurf.load(tree_file).mesh(**kwargs).astuple()
    # The CLI writes binary PLY with float32 coordinates.
    np.testing.assert_array_equal(vertices.astype(np.float32).astype(np.float64), cli_mesh.vertices)
    np.testing.assert_array_equal(normals.astype(np.float32).astype(np.float64), cli_mesh.normals)
    np.testing.assert_array_equal(faces, cli_mesh.faces)
    # And write_mesh writes the CLI's bytes.
    clustersurf.write_mesh(tmp_path / "py.ply", vertices, faces, normals)
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()


def test_trimmed_mesh_equals_reconstruct(tmp_path, cli, bunny_file):
    # reconstruct --mesh trims the mesh to the input points; mesh(points=...) does the same.
    run(cli, "reconstruct", bunny_file, "-o", tmp_path / "b.cstree", "--mesh", tmp_path / "cli.ply", "--resolution", "64")
    cli_mesh = clustersurf.read_mesh(tmp_path / "cli.ply")
    cloud = clustersurf.read_points(bunny_file)
    mesh = clustersurf.load(tmp_path / "b.cstree").mesh(resolution=64, points=cloud)
    np.testing.assert_array_equal(mesh.vertices.astype(np.float32).astype(np.float64), cli_mesh.vertices)
    np.testing.assert_array_equal(mesh.faces, cli_mesh.faces)
    untrimmed = clustersurf.load(tmp_path / "b.cstree").mesh(resolution=64)
    assert len(untrimmed.faces) >= len(mesh.faces)


@pytest.mark.parametrize("kwargs, flags", [({}, []), ({"watertight": True}, ["--watertight"])])
def test_mesh_report_equals_the_cli(tmp_path, cli, bunny_file, kwargs, flags):
    # One report, made by the library: what `mesh --json` prints is the Mesh's report.
    run(cli, "reconstruct", bunny_file, "-o", tmp_path / "b.cstree")
    cli_report = json.loads(subprocess.run([cli, "--json", "mesh", str(tmp_path / "b.cstree"), "--points",
                                            str(bunny_file), "-o", str(tmp_path / "cli.ply"), *flags],
                                           capture_output=True, text=True, check=True).stdout)
    mesh = clustersurf.load(tmp_path / "b.cstree").mesh(points=clustersurf.read_points(bunny_file), **kwargs)
    report = dict(mesh.report)
    assert report["vertices"] == len(mesh.vertices) and report["triangles"] == len(mesh.faces)
    assert report["refitted_vertices"] > 0 and report["voxel_size"] > 0
    assert ("check" in report) == bool(kwargs)
    for r in (report, cli_report):
        assert r.pop("mesh_seconds") >= 0
    assert cli_report.pop("file") == str(tmp_path / "cli.ply")
    assert report == cli_report
    assert clustersurf.read_mesh(tmp_path / "cli.ply").report == {}


def test_auto_resolution_equals_the_cli(tmp_path, cli, bunny_file):
    # The grid matched to the points' spacing: the same mesh from both, and none without points.
    run(cli, "reconstruct", bunny_file, "-o", tmp_path / "b.cstree", "--mesh", tmp_path / "cli.ply", "--resolution", "auto")
    cli_mesh = clustersurf.read_mesh(tmp_path / "cli.ply")
    tree = clustersurf.load(tmp_path / "b.cstree")
    mesh = tree.mesh(resolution="auto", points=clustersurf.read_points(bunny_file))
    np.testing.assert_array_equal(mesh.vertices.astype(np.float32).astype(np.float64), cli_mesh.vertices)
    np.testing.assert_array_equal(mesh.faces, cli_mesh.faces)
    # The tree stores the spacing: without the points, the same grid (untrimmed), as the CLI's.
    run(cli, "mesh", tmp_path / "b.cstree", "-o", tmp_path / "cli_untrimmed.ply")
    untrimmed = tree.mesh()
    clustersurf.write_mesh(tmp_path / "py_untrimmed.ply", untrimmed.vertices, untrimmed.faces, untrimmed.normals)
    assert (tmp_path / "py_untrimmed.ply").read_bytes() == (tmp_path / "cli_untrimmed.ply").read_bytes()
    with pytest.raises(clustersurf.OptionError, match="not \"fine\""):
        tree.mesh(resolution="fine")


def test_colored_mesh_equals_the_cli(tmp_path, cli, bunny_file):
    # reconstruct --mesh --color distance: the library's colors, from both front ends.
    run(cli, "reconstruct", bunny_file, "-o", tmp_path / "b.cstree", "--mesh", tmp_path / "cli.ply", "--color", "distance")
    cloud = clustersurf.read_points(bunny_file)
    mesh = clustersurf.load(tmp_path / "b.cstree").mesh(points=cloud, color="distance")
    assert mesh.colors is not None and mesh.colors.shape == mesh.vertices.shape
    clustersurf.write_mesh(tmp_path / "py.ply", mesh.vertices, mesh.faces, mesh.normals, mesh.colors)
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    with pytest.raises(clustersurf.OptionError, match="need the tree's input points"):
        clustersurf.load(tmp_path / "b.cstree").mesh(color="distance")


def test_points_of_another_cloud_are_refused(tmp_path, cli, bunny_file):
    run(cli, "reconstruct", bunny_file, "-o", tmp_path / "b.cstree")
    with pytest.raises(clustersurf.OptionError, match="are not the tree's input"):
        clustersurf.load(tmp_path / "b.cstree").mesh(points=np.zeros((10, 3)))


def test_sample_and_eval_equal_the_cli(tmp_path, cli, bunny_file):
    run(cli, "sample", bunny_file, "-o", tmp_path / "cli.ply", "-n", 3000, "--noise", 0.001, "--seed", 5)
    mesh = clustersurf.read_mesh(bunny_file)
    cloud = clustersurf.sample_surface(mesh.vertices, mesh.faces, n=3000, noise=0.001, seed=5)
    clustersurf.write_points(tmp_path / "py.ply", cloud.positions, cloud.normals)
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()

    cli_eval = json.loads(subprocess.run([cli, "--json", "eval", str(tmp_path / "cli.ply"), "-r", str(bunny_file),
                                          "--samples", "5000"], capture_output=True, text=True, check=True).stdout)
    sampled = clustersurf.read_points(tmp_path / "cli.ply")
    e = clustersurf.compare_surfaces(sampled.positions, None, mesh.vertices, mesh.faces, recon_normals=sampled.normals,
                             samples=5000)
    for key in ("diagonal", "accuracy", "completeness", "chamfer", "distance_p95", "hausdorff", "normal_consistency"):
        assert e[key] == cli_eval[key], key
    assert [f["fscore"] for f in e["fscore"]] == [f["fscore"] for f in cli_eval["fscore"]]


def test_scan_equals_the_cli(tmp_path, cli, bunny_file):
    run(cli, "sample", bunny_file, "-o", tmp_path / "cli.ply", "-n", 5000, "--scanner", 6, "--noise", 0.0005,
        "--registration", 0.0002, "--flip-normals", 0.05, "--noise-correlation", 1.5, "--seed", 2)
    mesh = clustersurf.read_mesh(bunny_file)
    cloud = clustersurf.scan_surface(mesh.vertices, mesh.faces, n=5000, scans=6, noise=0.0005, registration=0.0002,
                                     flipped_normals=0.05, noise_correlation=1.5, seed=2)
    assert cloud.scanner_of_point is not None and cloud.scanner_of_point.max() == 5  # which scan saw each point
    clustersurf.write_points(tmp_path / "py.ply", cloud)
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()


def test_error_messages_equal_the_cli(tmp_path, cli):
    bad = tmp_path / "bad.xyz"
    bad.write_text("0 0 0\n1 2\n")
    for path, error in ((bad, clustersurf.InputError), (tmp_path / "missing.ply", clustersurf.IoError)):
        result = run(cli, "reconstruct", path, "-o", tmp_path / "x.cstree", check=False)
        assert result.returncode in (3, 4)
        with pytest.raises(error) as e:
            clustersurf.read_points(path)
        assert str(e.value) in result.stderr


def test_real_scan_equals_the_cli(tmp_path, cli, shared_data):
    scan = shared_data("bunny/scans/bun045.ply")
    out = tmp_path / "cli.cstree"
    run(cli, "reconstruct", scan, "-o", out)
    tree = clustersurf.reconstruct(clustersurf.read_points(scan))
    assert tree.to_bytes() == out.read_bytes()


def test_one_call_mesh_equals_the_cli(tmp_path, cli, shared_data):
    # The real bunny scans (100,000 of their points): reconstruct_mesh(cloud) and
    # reconstruct(cloud).mesh() are `reconstruct --mesh`'s mesh, byte for byte (trimmed to the
    # points the tree keeps).
    scans = tmp_path / "scans.ply"
    run(cli, "convert", "--subsample", "100000", shared_data("bunny/bunny_scans_aligned.ply"), scans)
    run(cli, "reconstruct", scans, "-o", tmp_path / "b.cstree", "--mesh", tmp_path / "cli.ply")
    cloud = clustersurf.read_points(scans)
    clustersurf.write_mesh(tmp_path / "one_call.ply", clustersurf.reconstruct_mesh(cloud))
    assert (tmp_path / "one_call.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    tree = clustersurf.reconstruct(cloud)
    clustersurf.write_mesh(tmp_path / "tree.ply", tree.mesh())
    assert (tmp_path / "tree.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    # A loaded tree does not hold its points: untrimmed, as `clustersurf mesh` without --points.
    assert len(clustersurf.load(tmp_path / "b.cstree").mesh().faces) > len(tree.mesh().faces)


def test_scan_colors_equal_the_cli(tmp_path, cli, shared_data):
    # The aerial LAS tile's RGB on the mesh (15,000 of its points), the same from both front
    # ends, in PLY and GLB.
    tile = tmp_path / "tile.ply"
    run(cli, "convert", "--subsample", "15000", shared_data("formats/las/autzen_trim.las"), tile)
    run(cli, "reconstruct", tile, "--mesh", tmp_path / "cli.ply")
    run(cli, "reconstruct", tile, "--mesh", tmp_path / "cli.glb")
    mesh = clustersurf.reconstruct_mesh(clustersurf.read_points(tile))
    assert mesh.colors is not None and mesh.colors.shape == mesh.vertices.shape
    clustersurf.write_mesh(tmp_path / "py.ply", mesh)
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    clustersurf.write_mesh(tmp_path / "py.glb", mesh)
    assert (tmp_path / "py.glb").read_bytes() == (tmp_path / "cli.glb").read_bytes()
    assert clustersurf.reconstruct_mesh(clustersurf.read_points(tile), color="none").colors is None


def test_both_front_ends_offer_the_schema(cli):
    """Every option of the library's schemas is a CLI flag with the schema's default and a keyword
    of reconstruct(), Tree.mesh() or Tree.render() documented with the same default."""
    helps = {command: " ".join(run(cli, command, "--help").stdout.split()) for command in ("reconstruct", "render")}
    docs = {"build": clustersurf.reconstruct.__doc__, "mesh": clustersurf.Tree.mesh.__doc__,
            "render": clustersurf.Tree.render.__doc__}
    for spec in clustersurf.option_schema():
        help_text = helps["render" if spec["stage"] == "render" else "reconstruct"]
        flag = "--" + spec["name"].replace("_", "-")
        if spec["alias"]:
            flag += ",--" + spec["alias"].replace("_", "-")
        assert flag in help_text, spec["name"]
        default = spec["default"]
        if default is not None and spec["kind"] != "flag":
            text = format(default, "g") if isinstance(default, float) else str(default)
            assert re.search(rf"{re.escape(flag)} \S+={re.escape(text)} ", help_text), spec["name"]
        assert f"``{spec['name']}``" in docs[spec["stage"]], spec["name"]


def test_an_unknown_option_is_refused_by_both_front_ends(tmp_path, cli, bunny_file):
    result = run(cli, "reconstruct", bunny_file, "-o", tmp_path / "t.cstree", "--smoothness", "2", check=False)
    assert result.returncode != 0 and "smoothness" in result.stderr
    with pytest.raises(clustersurf.OptionError, match="smoothness"):
        clustersurf.reconstruct(clustersurf.read_points(bunny_file).positions, smoothness=2)


def test_registration_equals_the_cli(tmp_path, cli, bunny_file):
    scans = tmp_path / "scans.ply"
    run(cli, "sample", bunny_file, "-o", scans, "-n", 20000, "--scanner", 6, "--registration", 0.002, "--seed", 3)
    report = json.loads(subprocess.run([cli, "--json", "reconstruct", str(scans), "-o", str(tmp_path / "t.cstree")],
                                       capture_output=True, text=True, check=True).stdout)["registration"]
    measured = clustersurf.measure_registration(clustersurf.read_points(scans))
    assert measured["scans"] == report["scans"] == 6
    assert measured["overlaps"] == report["overlaps"] > 0
    assert measured["median_offset"] == report["median_offset"] > 0
    assert measured["rms_offset"] == report["rms_offset"]
    assert clustersurf.measure_registration(clustersurf.read_points(bunny_file))["overlaps"] == 0
