"""Topology and geometry measures on ~1.3M-face meshes: meshsmith vs libigl (and scipy, trimesh).

Inputs: datasets.icosphere(8) (1,310,720 faces, closed; icosphere(6), 81,920 faces, in quick mode)
for edges, components, χ, manifoldness and measures; datasets.grid(810, 810) (1,312,200 faces,
one boundary loop of 3,240 vertices; grid(200, 200) in quick mode) and the same grid with 400
square holes punched out for boundary loops.

Same work: components give face and vertex labels on every side (the peers' vertex labels are
indexed by a corner of each face for the face labels); libigl's facet_components is timed against
meshsmith's edge connectivity, the quantity it computes; libigl's split_nonmanifold returns faces
and origins, and its side also gathers the split positions V[origin], as meshsmith returns them.

Result checks (tolerances): edges, component labels (up to renumbering), χ, manifoldness,
boundary loops (as vertex sets) and split vertex counts equal to libigl's (0 differences); face
areas within 1e-12 of libigl's, area and volume within 1e-10 of trimesh's (relative).
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, differing_simplices, optional, relative_difference, size  # noqa: E402

from meshsmith import datasets, geometry, topology  # noqa: E402


def grid_with_holes(n, holes_per_side=20):
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
    count, vertex_labels = scipy.sparse.csgraph.connected_components(A, directed=False)
    return count, vertex_labels[F[:, 0]], vertex_labels


def same_partition(a, b) -> bool:
    """True when two labelings group the elements alike (equal up to renumbering)."""
    a, b = np.asarray(a), np.asarray(b)
    pairs = np.unique(np.column_stack([a, b]), axis=0)
    return len(pairs) == len(np.unique(a)) == len(np.unique(b))


def loop_sets(loops) -> set:
    return {frozenset(np.asarray(loop).tolist()) for loop in loops}


def main():
    igl = optional("igl")
    trimesh = optional("trimesh")
    V, F = datasets.icosphere(size(8, 6))
    label = f"icosphere({size(8, 6)}): {len(V):,} V, {len(F):,} F"

    bench = Benchmark("topology", f"unique edges, {label}", repeats=5)
    bench.time("meshsmith", lambda: topology.edges(F))
    if igl:
        bench.time("libigl edges", lambda: igl.edges(F))
    bench.time("numpy sort+unique", lambda: np.unique(np.sort(F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0))
    bench.report()
    if igl:
        bench.check("edges differing from libigl's", differing_simplices(topology.edges(F), igl.edges(F)), 0)

    bench = Benchmark("topology", f"vertex-connected components (face and vertex labels), {label}", repeats=5)
    bench.time("meshsmith", lambda: topology.connected_components(F))
    if igl:
        bench.time("libigl vertex_components", lambda: (lambda c: (c, c[F[:, 0]]))(igl.vertex_components(F)))
    bench.time("scipy csgraph", lambda: scipy_vertex_components(F, len(V)))
    bench.report()
    components = topology.connected_components(F)
    _, scipy_faces, scipy_vertices = scipy_vertex_components(F, len(V))
    bench.check("vertex components: labelings differing from scipy's",
                int(not same_partition(components.vertex_labels, scipy_vertices))
                + int(not same_partition(components.face_labels, scipy_faces)), 0)
    if igl:
        bench.check("vertex components: labeling differing from libigl's",
                    int(not same_partition(components.vertex_labels, igl.vertex_components(F))), 0)

    if igl:
        bench = Benchmark("topology", f"edge-connected components (face labels), {label}", repeats=5)
        bench.time("meshsmith", lambda: topology.connected_components(F, connectivity="edge"))
        bench.time("libigl facet_components", lambda: igl.facet_components(F))
        bench.report()
        bench.check("edge components: labeling differing from libigl's",
                    int(not same_partition(topology.connected_components(F, connectivity="edge").face_labels,
                                           igl.facet_components(F)[1])), 0)

    bench = Benchmark("topology", f"Euler characteristic, {label}", repeats=5)
    bench.time("meshsmith", lambda: topology.euler_characteristic(F))
    if igl:
        bench.time("libigl euler_characteristic", lambda: igl.euler_characteristic(F))
    bench.report()
    if igl:
        bench.check("|χ - libigl's χ|", abs(topology.euler_characteristic(F) - igl.euler_characteristic(F)), 0)

    bench = Benchmark("topology", f"manifold check (edges + vertices), {label}", repeats=5)
    bench.time("meshsmith", lambda: topology.is_manifold(F))
    if igl:
        bench.time("libigl is_edge_manifold+is_vertex_manifold",
                   lambda: (igl.is_edge_manifold(F), igl.is_vertex_manifold(F)))
    bench.report()
    if igl:
        igl_manifold = bool(igl.is_edge_manifold(F)[0]) and bool(np.all(igl.is_vertex_manifold(F)))
        bench.check("manifoldness differing from libigl's", int(topology.is_manifold(F) != igl_manifold), 0)

    bench = Benchmark("topology", f"info (all counts, area, volume), {label}", repeats=5)
    bench.time("meshsmith", lambda: topology.info(V, F))
    if trimesh:
        def trimesh_summary():
            mesh = trimesh.Trimesh(V, F, process=False)
            return (mesh.edges_unique, mesh.euler_number, mesh.is_watertight, mesh.is_winding_consistent,
                    mesh.bounds, mesh.area, mesh.volume, len(mesh.split(only_watertight=False)))
        bench.time("trimesh same properties", trimesh_summary)
    bench.report()
    if trimesh:
        summary, mesh = topology.info(V, F), trimesh.Trimesh(V, F, process=False)
        bench.check("info: counts (edges, χ, components) differing from trimesh's",
                    int(summary.n_edges != len(mesh.edges_unique)) + int(summary.euler_characteristic != mesh.euler_number)
                    + int(summary.n_components != len(mesh.split(only_watertight=False))), 0)
        bench.check("info: area and volume vs trimesh, max relative",
                    max(relative_difference(summary.surface_area, mesh.area),
                        relative_difference(summary.volume, mesh.volume)), 1e-10)

    bench = Benchmark("topology", f"face areas, {label}", repeats=5)
    bench.time("meshsmith", lambda: geometry.face_areas(V, F))
    if igl:
        bench.time("libigl doublearea/2", lambda: igl.doublearea(V, F) / 2)
    bench.report()
    if igl:
        bench.check("face areas vs libigl, max relative",
                    relative_difference(geometry.face_areas(V, F), igl.doublearea(V, F) / 2), 1e-12)

    bench = Benchmark("topology", f"signed volume, {label}", repeats=5)
    bench.time("meshsmith", lambda: geometry.volume(V, F))
    if trimesh:
        bench.time("trimesh Trimesh(V, F).volume", lambda: trimesh.Trimesh(V, F, process=False).volume)
    bench.report()
    if trimesh:
        bench.check("volume vs trimesh, relative",
                    relative_difference(geometry.volume(V, F), trimesh.Trimesh(V, F, process=False).volume), 1e-10)

    n = size(810, 200)
    for name, (Vg, Fg) in [(f"grid({n}, {n})", datasets.grid(n, n)),
                           (f"grid({n}, {n}) with 400 holes", grid_with_holes(n))]:
        bench = Benchmark("topology", f"boundary loops, {name}: {len(Fg):,} F", repeats=5)
        bench.time("meshsmith", lambda: topology.boundary_loops(Fg))
        if igl:
            bench.time("libigl boundary_loop_all", lambda: igl.boundary_loop_all(Fg))
            bench.time("libigl boundary_loop (longest only)", lambda: igl.boundary_loop(Fg), same_work=False)
        bench.report()
        if igl:
            ours, theirs = loop_sets(topology.boundary_loops(Fg)), loop_sets(igl.boundary_loop_all(Fg))
            bench.check("boundary loops differing from libigl's (as vertex sets)", len(ours ^ theirs), 0)

    bench = Benchmark("topology", f"split non-manifold vertices, {label}", repeats=5)
    bench.time("meshsmith", lambda: topology.split_non_manifold_vertices(V, F))
    if igl:
        def igl_split():  # the same outputs as meshsmith's: positions, faces, origin of each vertex
            faces, origin = igl.split_nonmanifold(F)
            return V[origin], faces, origin
        bench.time("libigl split_nonmanifold + V[origin]", igl_split)
    bench.report()
    if igl:
        bench.check("vertex count after splitting, |meshsmith - libigl|",
                    abs(len(topology.split_non_manifold_vertices(V, F)[0]) - len(igl_split()[0])), 0)


if __name__ == "__main__":
    main()
