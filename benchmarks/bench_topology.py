"""Topology and geometry measures on ~1.3M-face meshes: meshsmith vs libigl (and scipy, trimesh).

Inputs: datasets.icosphere(8) (1,310,720 faces, closed) for edges, components, χ, manifoldness
and measures; datasets.grid(810, 810) (1,312,200 faces, one boundary loop of 3,240 vertices)
and the same grid with 400 square holes punched out for boundary loops.
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark  # noqa: E402

from meshsmith import datasets, geometry, topology  # noqa: E402


def _optional(module_name):
    try:
        return __import__(module_name)
    except ImportError:
        return None


def grid_with_holes(n=810, holes_per_side=20):
    """The n × n grid without the two triangles of one cell in every block of n/holes cells."""
    V, F = datasets.grid(n, n)
    step = n // holes_per_side
    cells = np.arange(n * n).reshape(n, n)[step // 2::step, step // 2::step].ravel()
    keep = np.ones(len(F), dtype=bool)
    keep[cells] = keep[n * n + cells] = False   # grid(): first all lower, then all upper triangles
    return V, F[keep]


def scipy_vertex_components(F, n):
    import scipy.sparse
    import scipy.sparse.csgraph

    rows = np.concatenate([F[:, 0], F[:, 1], F[:, 2]])
    cols = np.concatenate([F[:, 1], F[:, 2], F[:, 0]])
    A = scipy.sparse.coo_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(n, n))
    return scipy.sparse.csgraph.connected_components(A, directed=False)


def main():
    igl = _optional("igl")
    trimesh = _optional("trimesh")
    V, F = datasets.icosphere(8)
    size = f"icosphere(8): {len(V):,} V, {len(F):,} F"

    bench = Benchmark("topology", f"unique edges, {size}", repeats=3)
    bench.time("meshsmith", lambda: topology.edges(F))
    if igl:
        bench.time("libigl edges", lambda: igl.edges(F))
    bench.time("numpy sort+unique", lambda: np.unique(np.sort(F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0))
    bench.report()

    bench = Benchmark("topology", f"vertex-connected components, {size}", repeats=3)
    bench.time("meshsmith", lambda: topology.connected_components(F))
    if igl:
        bench.time("libigl vertex_components", lambda: igl.vertex_components(F))
        bench.time("libigl facet_components", lambda: igl.facet_components(F))
    bench.time("scipy csgraph", lambda: scipy_vertex_components(F, len(V)))
    bench.report()

    bench = Benchmark("topology", f"Euler characteristic, {size}", repeats=3)
    bench.time("meshsmith", lambda: topology.euler_characteristic(F))
    if igl:
        bench.time("libigl euler_characteristic", lambda: igl.euler_characteristic(F))
    bench.report()

    bench = Benchmark("topology", f"manifold check (edges + vertices), {size}", repeats=3)
    bench.time("meshsmith", lambda: topology.is_manifold(F))
    if igl:
        bench.time("libigl is_edge_manifold+is_vertex_manifold",
                   lambda: (igl.is_edge_manifold(F), igl.is_vertex_manifold(F)))
    bench.report()

    bench = Benchmark("topology", f"info (all counts, area, volume), {size}", repeats=3)
    bench.time("meshsmith", lambda: topology.info(V, F))
    if trimesh:
        def trimesh_summary():
            mesh = trimesh.Trimesh(V, F, process=False)
            return (mesh.edges_unique, mesh.euler_number, mesh.is_watertight, mesh.is_winding_consistent,
                    mesh.area, mesh.volume, len(mesh.split(only_watertight=False)))
        bench.time("trimesh same properties", trimesh_summary)
    bench.report()

    bench = Benchmark("topology", f"face areas, {size}", repeats=3)
    bench.time("meshsmith", lambda: geometry.face_areas(V, F))
    if igl:
        bench.time("libigl doublearea/2", lambda: igl.doublearea(V, F) / 2)
    bench.report()

    bench = Benchmark("topology", f"signed volume, {size}", repeats=3)
    bench.time("meshsmith", lambda: geometry.volume(V, F))
    if trimesh:
        bench.time("trimesh Trimesh(V, F).volume", lambda: trimesh.Trimesh(V, F, process=False).volume)
    bench.report()

    for name, (Vg, Fg) in [("grid(810, 810)", datasets.grid(810, 810)),
                           ("grid(810, 810) with 400 holes", grid_with_holes())]:
        bench = Benchmark("topology", f"boundary loops, {name}: {len(Fg):,} F", repeats=3)
        bench.time("meshsmith", lambda: topology.boundary_loops(Fg))
        if igl:
            bench.time("libigl boundary_loop_all", lambda: igl.boundary_loop_all(Fg))
            bench.time("libigl boundary_loop (longest)", lambda: igl.boundary_loop(Fg))
        bench.report()

    Vs, Fs = datasets.icosphere(8)
    bench = Benchmark("topology", f"split non-manifold vertices, {size}", repeats=3)
    bench.time("meshsmith", lambda: topology.split_non_manifold_vertices(Vs, Fs))
    if igl:
        bench.time("libigl split_nonmanifold", lambda: igl.split_nonmanifold(Vs, Fs))
    bench.report()


if __name__ == "__main__":
    main()
