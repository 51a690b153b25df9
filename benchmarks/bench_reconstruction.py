"""Reconstruction benchmarks: marching cubes, mesh signed distance, screened Poisson.

Marching cubes of a capped gyroid on a 256³ grid (96³ quick) beside libigl's and scikit-image's;
the winding-number signed distance of 50k queries (10k quick) to the 70k-face bunny beside
libigl's signed_distance (exact winding number) and its fast winding number; screened Poisson on
pmp-bunny.xyz (35k points with normals) at depth 8 (7 quick) beside Open3D's
create_from_point_cloud_poisson and pymeshlab's screened Poisson (Kazhdan's code) at the same
depth, with each output's mean and Hausdorff distance to the ground truth pmp-bunny.off ÷ its
bounding-box diagonal.

Result checks: the marching-cubes vertex set equals libigl's (count, and every vertex within 1e-12
of one of libigl's); |signed distance| equals libigl's to 1e-12, the sign agrees wherever the
exact winding number is 5e-3 away from 1/2 (on the first 5000 queries); Poisson's output is closed and edge-manifold, its mean
distance ÷ diagonal no worse than 1.25 × the better peer's (the ratio is the check's value).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, check, optional, shared_data_dir, size  # noqa: E402

import meshsmith  # noqa: E402
from meshsmith import geometry, io, reconstruction as rc, topology  # noqa: E402

igl = optional("igl")
measure = optional("skimage.measure")
o3d = optional("open3d")
pymeshlab = optional("pymeshlab")


def capped_gyroid(n):
    x = np.linspace(-1, 1, n)
    X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    s = np.clip((np.sqrt(X ** 2 + Y ** 2 + Z ** 2) - 0.55) / 0.35, 0, 1)
    values = (np.sin(6 * X) * np.cos(6 * Y) + np.sin(6 * Y) * np.cos(6 * Z) + np.sin(6 * Z) * np.cos(6 * X)
              + 3 * s * s * (3 - 2 * s))
    return values, np.c_[X.ravel(order="F"), Y.ravel(order="F"), Z.ravel(order="F")], 2.0 / (n - 1)


def marching_cubes_case() -> None:
    n = size(256, 96)
    values, corners, h = capped_gyroid(n)
    column = values.ravel(order="F")
    bench = Benchmark("reconstruction", f"marching cubes, capped gyroid on a {n}³ grid", repeats=3)
    bench.time("meshsmith", lambda: rc.marching_cubes(values, origin=(-1, -1, -1), spacing=(h, h, h)))
    if igl:
        bench.time("libigl marching_cubes", lambda: igl.marching_cubes(column, corners, n, n, n, 0.0))
    if measure:
        bench.time("scikit-image marching_cubes (lewiner)", lambda: measure.marching_cubes(values, 0.0, spacing=(h, h, h)))
    bench.report()
    ours = bench.output("meshsmith")
    print(f"  meshsmith: {len(ours.V)} vertices, {len(ours.F)} triangles, closed manifold "
          f"{topology.is_manifold(ours.F) and not topology.boundary_loops(ours.F)}, "
          f"Euler characteristic {topology.euler_characteristic(ours.F)}, centre vertices {ours.centre_vertices}")
    if igl:
        V_igl = bench.output("libigl marching_cubes")[0]
        bench.check("vertex count minus libigl's (without centre vertices)", abs(len(ours.V) - ours.centre_vertices - len(V_igl)), 0)
        bench.check("max distance from a libigl vertex to ours", cKDTree(ours.V).query(V_igl)[0].max(), 1e-12)
        print(f"  libigl: closed manifold {topology.is_manifold(bench.output('libigl marching_cubes')[1])}")


def signed_distance_case() -> None:
    data = shared_data_dir()
    if data is None or not igl:
        print("reconstruction: mesh signed distance skipped (shared data or libigl missing)")
        return
    V, F = io.read_mesh(data / "pmp-bunny.off")
    lo, hi = V.min(axis=0), V.max(axis=0)
    q = size(50_000, 10_000)
    Q = np.random.default_rng(0).uniform(lo - 0.1 * (hi - lo), hi + 0.1 * (hi - lo), (q, 3))
    F64 = F.astype(np.int64)
    bench = Benchmark("reconstruction", f"signed distance (winding-number sign), {q // 1000}k queries to a 70k-face mesh",
                      repeats=3)
    bench.time("meshsmith", lambda: rc.mesh_sdf(V, F, Q))
    bench.time("libigl signed_distance (winding number)",
               lambda: igl.signed_distance(Q, V, F64, sign_type=igl.SIGNED_DISTANCE_TYPE_WINDING_NUMBER))
    bench.time("libigl signed_distance (fast winding number)",
               lambda: igl.signed_distance(Q, V, F64, sign_type=igl.SIGNED_DISTANCE_TYPE_FAST_WINDING_NUMBER))
    bench.report()
    ours = bench.output("meshsmith")
    S = bench.output("libigl signed_distance (winding number)")[0]
    bench.check("max | |d| - |d_igl| |", np.abs(np.abs(ours.distance) - np.abs(S)).max(), 1e-12)
    few = slice(0, 5000)  # igl's exact winding number is O(#F) per query: the first 5000 queries
    clear = np.abs(igl.winding_number(V, F64, Q[few]) - 0.5) > 5e-3
    bench.check("of the first 5000 queries, those of the other sign (away from w = 1/2)",
                int((np.sign(ours.distance[few]) != np.sign(S[few]))[clear].sum()), 0)


def surface_errors(V, F, V_true, F_true, diagonal):
    mean = geometry.mean_surface_distance(V, F, V_true, F_true) / diagonal
    hausdorff = geometry.hausdorff_distance(V, F, V_true, F_true) / diagonal
    return mean, hausdorff


def poisson_case() -> None:
    data = shared_data_dir()
    if data is None:
        print("reconstruction: Poisson skipped (shared data missing)")
        return
    P, N = io.read_points(data / "pmp-bunny.xyz")
    V_true, F_true = io.read_mesh(data / "pmp-bunny.off")
    diagonal = float(np.linalg.norm(V_true.max(axis=0) - V_true.min(axis=0)))
    depth = size(8, 7)
    bench = Benchmark("reconstruction", f"screened Poisson, pmp-bunny.xyz ({len(P) // 1000}k points), depth {depth}",
                      repeats=3)
    bench.time("meshsmith", lambda: rc.poisson(P, N, depth=depth))
    if o3d:
        cloud = o3d.geometry.PointCloud()
        cloud.points = o3d.utility.Vector3dVector(P)
        cloud.normals = o3d.utility.Vector3dVector(N)
        bench.time("Open3D create_from_point_cloud_poisson",
                   lambda: o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(cloud, depth=depth, scale=1.1))
    if pymeshlab:
        def meshlab():
            meshes = pymeshlab.MeshSet()
            meshes.add_mesh(pymeshlab.Mesh(vertex_matrix=P, v_normals_matrix=N))
            meshes.generate_surface_reconstruction_screened_poisson(depth=depth, samplespernode=1.5, pointweight=4)
            return meshes.current_mesh().vertex_matrix(), meshes.current_mesh().face_matrix()
        bench.time("pymeshlab screened Poisson", meshlab)
    bench.report()
    ours = bench.output("meshsmith")
    closed = topology.is_manifold(ours.F) and not topology.boundary_loops(ours.F)
    bench.check("meshsmith output not a closed edge-manifold", 0 if closed else 1, 0)
    mean, hausdorff = surface_errors(ours.V, ours.F, V_true, F_true, diagonal)
    rows = [("meshsmith", len(ours.V), mean, hausdorff)]
    peer_means = []
    if o3d:
        mesh = bench.output("Open3D create_from_point_cloud_poisson")[0]
        V, F = np.asarray(mesh.vertices), np.asarray(mesh.triangles)
        rows.append(("Open3D", len(V), *surface_errors(V, F, V_true, F_true, diagonal)))
        peer_means.append(rows[-1][2])
    if pymeshlab:
        V, F = bench.output("pymeshlab screened Poisson")
        rows.append(("pymeshlab", len(V), *surface_errors(V, F, V_true, F_true, diagonal)))
        peer_means.append(rows[-1][2])
    print("  distance to pmp-bunny.off ÷ diagonal:")
    for name, count, m, hd in rows:
        print(f"    {name:10s} {count:7d} vertices  mean {m:.2e}  Hausdorff {hd:.2e}")
    print(f"  meshsmith levels: depths {ours.level_depths.tolist()}, unknowns {ours.level_unknowns.tolist()}, "
          f"iterations {ours.level_iterations.tolist()}")
    if peer_means:
        bench.check("meshsmith mean distance ÷ the better peer's", mean / min(peer_means), 1.25)
    else:
        check("reconstruction", bench.case, "meshsmith mean distance ÷ diagonal", mean, 1e-3)


def main() -> None:
    marching_cubes_case()
    signed_distance_case()
    poisson_case()


if __name__ == "__main__":
    main()
