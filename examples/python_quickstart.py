"""clustersurf from Python, step by step (run it as a script or paste the cells into a notebook).

    PYTHONPATH=build/python /usr/bin/python3 examples/python_quickstart.py [CLOUD] [OUTPUT_DIR]

Defaults: data/bunny.ply (from scripts/setup) and out/python/. The last cell converts to and
from an Open3D TriangleMesh when Open3D is installed (Debian: python3-open3d).
"""

# %% Read a point cloud (PLY, XYZ, OBJ) into numpy arrays.
import pathlib
import sys

import numpy as np

import clustersurf

root = pathlib.Path(__file__).resolve().parent.parent
cloud_file = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else root / "data" / "bunny.ply"
out = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else root / "out" / "python"
out.mkdir(parents=True, exist_ok=True)

cloud = clustersurf.read_points(cloud_file)
print(f"{cloud_file.name}: {len(cloud)} points, normals: {cloud.normals is not None}")

# %% Build and orient the cluster tree; options are the CLI's (`clustersurf reconstruct --help`).
# Pass the cloud itself: its positions are relative to its origin (a georeferenced LAS or E57
# scan is moved next to zero when read), which the tree and its meshes keep.
tree = clustersurf.reconstruct(cloud, proxy="poly", max_error="auto")
info = tree.info()
print(tree)
print(f"leaf proxies {info['leaf_proxies']}, error threshold {info['error_threshold']:.4g}")
tree.save(out / "tree.cstree")  # the same bytes as `clustersurf reconstruct CLOUD -o tree.cstree`

# %% Walk the tree: every node has its cluster's proxy, errors and support sphere.
root_node = tree.root
print(f"root: {root_node.point_count} points, children {[c.index for c in root_node.children]}")
leaf = tree.node(int(tree.leaves[0]))
center, radius = leaf.support
print(f"first leaf: {leaf.proxy_type}, rms error {leaf.rms_error:.3g}, support radius {radius:.3g}")
leaf_of_point = tree.leaf_of_points()  # -1: an outlier, left out of every cluster
counts = np.bincount(leaf_of_point[leaf_of_point >= 0], minlength=len(tree))[tree.leaves]
print(f"points per leaf: min {counts.min()}, median {int(np.median(counts))}, max {counts.max()}")

# %% Evaluate the implicit function f (≈ signed distance, > 0 outside; NaN where undefined).
lo, hi = tree.bbox
probe = np.array([(lo + hi) / 2, hi + (hi - lo)])
print("f at the box center and far outside:", tree.evaluate(probe))
print("f at the input points (≈ 0): max |f| =", np.nanmax(np.abs(tree.evaluate(cloud.positions))))

# %% Mesh it, at full and at a coarse level of detail, and write PLY/OBJ files.
mesh = tree.mesh(resolution=128, points=cloud)  # trimmed to the points, as `reconstruct --mesh`
clustersurf.write_mesh(out / "mesh.ply", mesh)  # written back at the cloud's origin
coarse = tree.mesh(resolution=128, lod_depth=6, color="leaf")
clustersurf.write_mesh(out / "coarse.ply", *coarse.astuple())
vertices, faces, normals = mesh.vertices, mesh.faces, mesh.normals
print(f"mesh: {len(vertices)} vertices, {len(faces)} triangles; coarse: {len(coarse.faces)} triangles")

# %% Render pictures: an (h, w, 4) uint8 array (matplotlib's imshow takes it as is).
picture = tree.render(width=320, height=240, show="clusters", samples=2)
print(f"picture {picture.shape}, {np.count_nonzero(picture[..., :3].min(axis=2) < 255)} non-white pixels")

# %% How close is the mesh to the input? (distances as fractions of the diagonal)
scores = clustersurf.compare_surfaces(mesh, cloud, samples=20000)
print(f"chamfer {scores['chamfer']:.5f}, F-score@1% {scores['fscore'][1]['fscore']:.3f}")

# %% Open3D: numpy arrays in and out of an Open3D TriangleMesh / PointCloud.
try:
    import open3d as o3d
except ImportError:
    print("Open3D is not installed: skipping the Open3D part")
else:
    o3d_mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(vertices), o3d.utility.Vector3iVector(faces))
    o3d_mesh.vertex_normals = o3d.utility.Vector3dVector(normals)
    print(f"Open3D mesh: {o3d_mesh}, edge manifold: {o3d_mesh.is_edge_manifold()}")
    # ... and back: an Open3D mesh (say, from o3d.io.read_triangle_mesh) into clustersurf.
    v, f = np.asarray(o3d_mesh.vertices), np.asarray(o3d_mesh.triangles)
    samples = clustersurf.sample_surface(v, f, n=5000, seed=2)
    pcd = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(samples.positions))
    pcd.normals = o3d.utility.Vector3dVector(samples.normals)
    again = clustersurf.reconstruct(np.asarray(pcd.points), np.asarray(pcd.normals))
    print(f"Open3D points -> {again}")
