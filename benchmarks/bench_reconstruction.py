"""Reconstruction benchmarks: marching cubes, mesh signed distance, screened Poisson, max-flow, graph cut.

Marching cubes of a capped gyroid on a 256³ grid (96³ quick) beside libigl's and scikit-image's;
the winding-number signed distance of 50k queries (10k quick) to the 70k-face bunny beside
libigl's signed_distance (exact winding number) and its fast winding number; screened Poisson on
pmp-bunny.xyz (35k points with normals) and armadillo_low.xyz (12k) at depth 8 (7 quick) beside
Open3D's create_from_point_cloud_poisson and pymeshlab's screened Poisson (both Kazhdan's code)
at the same depth (ours at its default screening 8, the peers at point weight 4, Open3D also at
8), ours and Open3D with all cores and on one thread, pymeshlab on one thread, with each
output's vertex count and mean and Hausdorff distance to the ground truth pmp-bunny.off ÷ its
bounding-box diagonal (armadillo: the samples' mean and max distance to the mesh); ours also with
adaptive=True (the locally adaptive octree, extracted on its leaves), with both modes' unknowns per
level; and the same on 120k noisy samples of armadillo.obj (40k quick) thinned to one in ten on
x < the median x (dense on one half, sparse on the other), against armadillo.obj.
Max-flow (Boykov–Kolmogorov, ours) on a 3D 6-connected grid graph of 64³ nodes (32³ quick) with
random capacities beside PyMaxflow (Kolmogorov's own maxflow-v3 code) and scipy's
csgraph.maximum_flow (Dinic, integer capacities); graph-cut reconstruction of pmp-bunny.xyz
(normals unused) at resolution 128 (64 quick) beside our Poisson at depth 7 (different work: the
oriented route), with the distance of each to pmp-bunny.off ÷ diagonal.

Result checks: the marching-cubes vertex set equals libigl's (count, and every vertex within 1e-12
of one of libigl's); |signed distance| equals libigl's to 1e-12, the sign agrees wherever the
exact winding number is 5e-3 away from 1/2 (on the first 5000 queries); Poisson's outputs (both modes) are closed oriented manifolds,
the same on one thread as on all, its mean distance ÷ diagonal no worse than each peer's, its vertex count within 1.5× of
each peer's (the ratios are the checks' values).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, check, optional, shared_data_dir, size  # noqa: E402

import meshsmith  # noqa: E402
from meshsmith import datasets, geometry, io, reconstruction as rc, topology  # noqa: E402

igl = optional("igl")
measure = optional("skimage.measure")
o3d = optional("open3d")
maxflow = optional("maxflow")
csgraph = optional("scipy.sparse.csgraph")
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


def pmp_bunny(case):
    """pmp-bunny.xyz (points, normals), its ground truth pmp-bunny.off and that mesh's diagonal, or
    None (with a message) when the shared data is missing."""
    data = shared_data_dir()
    if data is None:
        print(f"reconstruction: {case} skipped (shared data missing)")
        return None
    P, N = io.read_points(data / "pmp-bunny.xyz")
    V_true, F_true = io.read_mesh(data / "pmp-bunny.off")
    return P, N, V_true, F_true, float(np.linalg.norm(V_true.max(axis=0) - V_true.min(axis=0)))


POISSON_CLOUDS = (("pmp-bunny.xyz", "pmp-bunny.off"), ("armadillo_low.xyz", None))


def poisson_case() -> None:
    data = shared_data_dir()
    for cloud, truth in POISSON_CLOUDS:
        if data is None or not (data / cloud).exists():
            print(f"reconstruction: Poisson on {cloud} skipped (shared data missing)")
            continue
        P, N = io.read_points(data / cloud)
        poisson_cloud_case(cloud, P, N, io.read_mesh(data / truth) if truth else None, truth)
    if data is None or not (data / "armadillo.obj").exists():
        print("reconstruction: Poisson on non-uniform armadillo samples skipped (shared data missing)")
        return
    V, F = io.read_mesh(data / "armadillo.obj")
    P, N = half_dense_samples(V, F, size(120_000, 40_000))
    # The output size is not matched here (ours 1.5× the peers' vertex count, both modes): the
    # extraction depth is one for the whole cloud (the deepest level half the samples reach), so the
    # sparse half is meshed as finely as the dense one. Printed as a figure, not checked: a known gap.
    poisson_cloud_case("armadillo.obj samples, dense on x > 0, 10× sparser on x < 0, noise 0.1 edge", P, N,
                       (V, F), "armadillo.obj", size_checked=False)


def half_dense_samples(V, F, n, seed=0):
    """n samples of the mesh (V, F) with noise 0.1 × the mean edge length, of which those on x <
    the median x are thinned to one in ten: dense on one half of the surface, sparse on the other."""
    P, N = datasets.sample_points(V, F, n, seed=seed, noise=0.1)
    keep = (P[:, 0] > np.median(V[:, 0])) | (np.arange(n) % 10 == 0)
    return P[keep], N[keep]


def poisson_cloud_case(cloud: str, P, N, truth_mesh, truth: str | None, *, size_checked: bool = True) -> None:
    """Ours (default screening 8; the default adaptive=False, bands around every sample up to one
    extraction depth, and as a second row adaptive=True, the locally adaptive octree extracted on
    its leaves), Open3D and pymeshlab (point weight 4,
    PoissonRecon's default) on one point cloud at the same depth, ours and Open3D each with all
    cores and on one thread (ours: threads=1; Open3D: n_threads=1), pymeshlab on one thread
    (threads=1; its all-core run, threads=2, is left out: it took 367 s on the bunny beside 26.9 s
    on one thread in a run of this file at load average 11-15, 2026-12-01 23:23 UTC, and 114 s
    beside 13.5 s at load 19 in another, its OpenMP threads contending on the two crowded cores),
    and Open3D at point weight 8 (the nominal value of ours, its best in a sweep of 2, 4, 8, 16 on
    the bunny; shown, not checked). Distances ÷ diagonal to the ground-truth mesh, or for a cloud
    without one in the same frame (armadillo_low.xyz), from the samples to each mesh (one-sided:
    mean and max)."""
    depth = size(8, 7)
    bench = Benchmark("reconstruction", f"screened Poisson, {cloud} ({len(P) // 1000}k points), depth {depth}",
                      repeats=3)
    bench.time("meshsmith", lambda: rc.poisson(P, N, depth=depth))
    bench.time("meshsmith, 1 thread", lambda: rc.poisson(P, N, depth=depth, threads=1))
    bench.time("meshsmith adaptive=True", lambda: rc.poisson(P, N, depth=depth, adaptive=True))
    if o3d:
        points = o3d.geometry.PointCloud()
        points.points = o3d.utility.Vector3dVector(P)
        points.normals = o3d.utility.Vector3dVector(N)
        for threads, weight, label in ((-1, 4.0, ""), (1, 4.0, ", 1 thread"), (1, 8.0, ", point weight 8, 1 thread")):
            bench.time(f"Open3D create_from_point_cloud_poisson{label}",
                       lambda threads=threads, weight=weight: o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(
                           points, depth=depth, scale=1.1, point_weight=weight, n_threads=threads),
                       same_work=weight == 4.0)
    if pymeshlab:
        def meshlab(threads):
            meshes = pymeshlab.MeshSet()
            meshes.add_mesh(pymeshlab.Mesh(vertex_matrix=P, v_normals_matrix=N))
            meshes.generate_surface_reconstruction_screened_poisson(depth=depth, samplespernode=1.5, pointweight=4,
                                                                    threads=threads)
            return meshes.current_mesh().vertex_matrix(), meshes.current_mesh().face_matrix()
        bench.time("pymeshlab screened Poisson, 1 thread", lambda: meshlab(1))
    bench.report()
    ours = bench.output("meshsmith")
    adaptive = bench.output("meshsmith adaptive=True")
    for label, mesh in (("meshsmith", ours), ("meshsmith adaptive=True", adaptive)):
        closed = topology.is_manifold(mesh.F) and topology.is_oriented(mesh.F) and not topology.boundary_loops(mesh.F)
        bench.check(f"{label} output not a closed oriented manifold", 0 if closed else 1, 0)
    single = bench.output("meshsmith, 1 thread")
    bench.check("meshsmith vertices differing between all cores and 1 thread",
                0 if np.array_equal(ours.V, single.V) and np.array_equal(ours.F, single.F) else 1, 0)
    if truth_mesh is not None:
        V_true, F_true = truth_mesh
        diagonal = float(np.linalg.norm(V_true.max(axis=0) - V_true.min(axis=0)))
        errors = lambda V, F: surface_errors(V, F, V_true, F_true, diagonal)  # noqa: E731
        what = f"distance to {truth} ÷ diagonal"
    else:
        diagonal = float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))

        def errors(V, F):
            distance = geometry.SurfaceDistance(V, F).distances(P) / diagonal
            return float(distance.mean()), float(distance.max())
        what = "distance from the samples to the mesh ÷ diagonal (no ground truth in the same frame)"
    rows = [("meshsmith", len(ours.V), *errors(ours.V, ours.F))]
    peer_means = []
    if o3d:
        mesh = bench.output("Open3D create_from_point_cloud_poisson")[0]
        V, F = np.asarray(mesh.vertices), np.asarray(mesh.triangles)
        rows.append(("Open3D", len(V), *errors(V, F)))
    if pymeshlab:
        V, F = bench.output("pymeshlab screened Poisson, 1 thread")
        rows.append(("pymeshlab", len(V), *errors(V, F)))
    print(f"  {what}:")
    shown = rows[:1] + [("adaptive", len(adaptive.V), *errors(adaptive.V, adaptive.F))] + rows[1:]
    if o3d:
        mesh = bench.output("Open3D create_from_point_cloud_poisson, point weight 8, 1 thread")[0]
        V, F = np.asarray(mesh.vertices), np.asarray(mesh.triangles)
        shown = shown + [("Open3D pw 8", len(V), *errors(V, F))]
    for name, count, m, hd in shown:
        print(f"    {name:11s} {count:7d} vertices  mean {m:.2e}  {'Hausdorff' if truth else 'max'} {hd:.2e}")
    for label, mesh in (("uniform (default)", ours), ("adaptive", adaptive)):
        print(f"  meshsmith {label} levels: depths {mesh.level_depths.tolist()}, unknowns {mesh.level_unknowns.tolist()} "
              f"(total {int(mesh.level_unknowns.sum())}), iterations {mesh.level_iterations.tolist()}, "
              f"deepest extraction depth {mesh.extraction_depth}")
    for name, count, m, _ in rows[1:]:
        peer_means.append(m)
        bench.check(f"meshsmith mean distance ÷ {name}'s", rows[0][2] / m, 1.0)
        ratio = max(len(ours.V) / count, count / len(ours.V))
        if size_checked:
            bench.check(f"meshsmith vertex count ÷ {name}'s, or its inverse", ratio, 1.5)
        else:
            print(f"  not matched (printed, not checked): meshsmith vertex count ÷ {name}'s, or its inverse: {ratio:.2f}")
    if not peer_means:
        check("reconstruction", bench.case, "meshsmith mean distance ÷ diagonal", rows[0][2], 1e-3)


def grid_graph(n, seed=0):
    """The 6-connected n³ grid graph with integer capacities in [1, 100] on its edges (both directions
    independent) and source / sink capacities on the x = 0 and x = n - 1 faces."""
    rng = np.random.default_rng(seed)
    index = np.arange(n ** 3).reshape(n, n, n)
    edges = np.concatenate([np.c_[index[:-1].ravel(), index[1:].ravel()],
                            np.c_[index[:, :-1].ravel(), index[:, 1:].ravel()],
                            np.c_[index[:, :, :-1].ravel(), index[:, :, 1:].ravel()]])
    forward = rng.integers(1, 101, len(edges)).astype(float)
    backward = rng.integers(1, 101, len(edges)).astype(float)
    source, sink = np.zeros(n ** 3), np.zeros(n ** 3)
    source[index[0].ravel()] = 1000.0
    sink[index[-1].ravel()] = 1000.0
    return edges, forward, backward, source, sink


def max_flow_case() -> None:
    n = size(64, 32)
    edges, forward, backward, source, sink = grid_graph(n)
    bench = Benchmark("reconstruction", f"max-flow, {n}³ grid graph ({len(edges) // 1000}k edges)", repeats=3)
    bench.time("meshsmith", lambda: rc.max_flow(n ** 3, edges, forward, backward, source, sink))
    if maxflow:
        def pymaxflow():
            graph = maxflow.Graph[float](n ** 3, len(edges))
            graph.add_nodes(n ** 3)
            graph.add_edges(edges[:, 0], edges[:, 1], forward, backward)
            graph.add_grid_tedges(np.arange(n ** 3), source, sink)
            return graph.maxflow()
        bench.time("PyMaxflow (Kolmogorov's maxflow-v3)", pymaxflow)
    if csgraph:
        import scipy.sparse as sparse
        count = n ** 3 + 2
        rows = np.concatenate([edges[:, 0], edges[:, 1], np.full(n ** 3, n ** 3), np.arange(n ** 3)])
        cols = np.concatenate([edges[:, 1], edges[:, 0], np.arange(n ** 3), np.full(n ** 3, n ** 3 + 1)])
        data = np.concatenate([forward, backward, source, sink]).astype(np.int32)
        keep = data > 0
        matrix = sparse.csr_matrix((data[keep], (rows[keep], cols[keep])), shape=(count, count))
        bench.time("scipy csgraph.maximum_flow (dinic)",
                   lambda: csgraph.maximum_flow(matrix, n ** 3, n ** 3 + 1, method="dinic").flow_value)
    bench.report()
    ours = bench.output("meshsmith").flow
    print(f"  flow {ours:.1f}")
    if maxflow:
        bench.check("flow vs PyMaxflow (relative)", abs(ours - bench.output("PyMaxflow (Kolmogorov's maxflow-v3)")) / ours, 1e-9)
    if csgraph:
        bench.check("flow vs scipy (relative)", abs(ours - bench.output("scipy csgraph.maximum_flow (dinic)")) / ours, 1e-9)


def graph_cut_case() -> None:
    bunny = pmp_bunny("graph cut")
    if bunny is None:
        return
    P, N, V_true, F_true, diagonal = bunny
    resolution = size(128, 64)
    bench = Benchmark("reconstruction", f"graph cut, pmp-bunny.xyz ({len(P) // 1000}k points), resolution {resolution}",
                      repeats=3)
    bench.time("meshsmith", lambda: rc.graph_cut(P, resolution=resolution))
    bench.time("meshsmith Poisson depth 7 (oriented normals)", lambda: rc.poisson(P, N, depth=7), same_work=False)
    bench.report()
    ours = bench.output("meshsmith")
    closed = topology.is_manifold(ours.F) and not topology.boundary_loops(ours.F)
    bench.check("graph-cut output not a closed edge-manifold", 0 if closed else 1, 0)
    mean, hausdorff = surface_errors(ours.V, ours.F, V_true, F_true, diagonal)
    poisson = bench.output("meshsmith Poisson depth 7 (oriented normals)")
    p_mean, p_hausdorff = surface_errors(poisson.V, poisson.F, V_true, F_true, diagonal)
    print(f"  graph cut: {len(ours.V)} vertices, voxel {ours.voxel_size / diagonal:.2e} × diagonal, "
          f"{ours.free_voxels} graph nodes of {int(np.prod(ours.shape))} grid points, Euler characteristic "
          f"{topology.euler_characteristic(ours.F)}")
    print(f"  distance to pmp-bunny.off ÷ diagonal: graph cut mean {mean:.2e} Hausdorff {hausdorff:.2e}; "
          f"Poisson depth 7 mean {p_mean:.2e} Hausdorff {p_hausdorff:.2e}")
    bench.check("graph-cut mean distance ÷ diagonal", mean, 1e-3)


def main() -> None:
    marching_cubes_case()
    signed_distance_case()
    poisson_case()
    max_flow_case()
    graph_cut_case()


if __name__ == "__main__":
    main()
