#!/usr/bin/env python3
"""Reconstruct a mesh from a point cloud with Open3D, as a peer in bench/compare.

    open3d_reconstruct.py --version
    open3d_reconstruct.py poisson IN OUT --depth D [--trim Q] [--estimate-normals]
    open3d_reconstruct.py bpa IN OUT [--estimate-normals]

poisson: screened Poisson (Kazhdan & Hoppe 2013) as packaged by Open3D; --trim Q removes the
vertices whose density is in the lowest quantile Q (Open3D's documented way to cut the
surface Poisson invents away from the data). bpa: ball pivoting with radii 1, 2 and 4 times
the mean nearest-neighbour spacing. --estimate-normals (or an input without normals)
estimates normals from 30 neighbours and orients them consistently (tangent-plane MST), the
pipeline Open3D documents for clouds without normals.
"""
import argparse
import sys

import numpy as np
import open3d as o3d


def main() -> int:
    if "--version" in sys.argv:
        print(f"open3d {o3d.__version__}")
        return 0
    p = argparse.ArgumentParser()
    p.add_argument("method", choices=["poisson", "bpa"])
    p.add_argument("input")
    p.add_argument("output")
    p.add_argument("--depth", type=int, default=8)
    p.add_argument("--trim", type=float, default=0.0)
    p.add_argument("--estimate-normals", action="store_true")
    a = p.parse_args()
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
    cloud = o3d.io.read_point_cloud(a.input)
    if len(cloud.points) == 0:
        print(f"error: {a.input}: no points", file=sys.stderr)
        return 3
    if a.estimate_normals or not cloud.has_normals():
        cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(30))
        cloud.orient_normals_consistent_tangent_plane(30)
    if a.method == "poisson":
        mesh, density = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(cloud, depth=a.depth)
        if a.trim > 0:
            d = np.asarray(density)
            mesh.remove_vertices_by_mask(d < np.quantile(d, a.trim))
    else:
        spacing = float(np.mean(cloud.compute_nearest_neighbor_distance()))
        radii = o3d.utility.DoubleVector([spacing, 2 * spacing, 4 * spacing])
        mesh = o3d.geometry.TriangleMesh.create_from_point_cloud_ball_pivoting(cloud, radii)
    mesh.compute_vertex_normals()
    if not cloud.has_colors():  # Poisson gives every vertex a color, black without the input's
        mesh.vertex_colors = o3d.utility.Vector3dVector()
    if not o3d.io.write_triangle_mesh(a.output, mesh):
        print(f"error: {a.output}: cannot write", file=sys.stderr)
        return 4
    return 0


if __name__ == "__main__":
    sys.exit(main())
