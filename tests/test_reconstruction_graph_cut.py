"""Graph-cut reconstruction (§2.2, §3.2): Boykov–Kolmogorov max-flow against networkx's minimum_cut
on random graphs, PyMaxflow on grid graphs, and a graph with a known cut; unoriented samples of a sphere and a torus give
closed, outward manifolds of the right Euler characteristic, their vertices within a fraction of
a voxel of the true surface; a cloud with a wide gap needs an inside seed; bad input is an
InputError."""
import sys
from pathlib import Path

import networkx as nx
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, geometry, reconstruction as rc, topology


def assert_closed_manifold(V, F, chi):
    assert F.dtype == np.int64 and V.dtype == np.float64
    assert topology.is_manifold(F) and topology.is_oriented(F)
    assert topology.boundary_loops(F) == []
    assert topology.euler_characteristic(F) == chi
    assert geometry.volume(V, F) > 0  # outward


@pytest.mark.parametrize("n, seed", [(12, 0), (20, 1), (24, 2)])
def test_max_flow_equals_pymaxflow_on_grid_graphs(n, seed):
    """The benchmark's graph (benchmarks/bench_reconstruction.py: random integer capacities on a
    6-connected n³ grid, source and sink on opposite faces, where the search trees and orphans get
    a workout): the same flow as Kolmogorov's own code (PyMaxflow), exactly, and our side is a cut
    of that capacity."""
    maxflow = pytest.importorskip("maxflow")
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from bench_reconstruction import grid_graph
    edges, forward, backward, source, sink = grid_graph(n, seed)
    flow, side = rc.max_flow(n ** 3, edges, forward, backward, source, sink)
    graph = maxflow.Graph[float](n ** 3, len(edges))
    graph.add_nodes(n ** 3)
    graph.add_edges(edges[:, 0], edges[:, 1], forward, backward)
    graph.add_grid_tedges(np.arange(n ** 3), source, sink)
    assert flow == graph.maxflow()
    u, v = edges[:, 0], edges[:, 1]
    cut = (forward[side[u] & ~side[v]].sum() + backward[side[v] & ~side[u]].sum()
           + source[~side].sum() + sink[side].sum())
    assert cut == flow


def test_max_flow_known_cut():
    # s→0 (3), s→1 (2); 0→1 (1), 0→2 (2), 1→3 (2), 2→3 (4); 2→t (2), 3→t (3): the cut
    # {s, 0, 1} | {2, 3, t} costs 0→2 + 1→3 = 4, every other cut at least 5.
    edges = np.array([[0, 1], [0, 2], [1, 3], [2, 3]])
    forward = np.array([1.0, 2.0, 2.0, 4.0])
    backward = np.zeros(4)
    flow, side = rc.max_flow(4, edges, forward, backward, [3.0, 2.0, 0.0, 0.0], [0.0, 0.0, 2.0, 3.0])
    assert flow == pytest.approx(4.0, abs=1e-12)
    np.testing.assert_array_equal(side, [True, True, False, False])


@pytest.mark.parametrize("seed", range(8))
def test_max_flow_matches_networkx(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 60))
    m = int(rng.integers(n, 5 * n))
    edges = rng.integers(0, n, size=(m, 2))
    edges = edges[edges[:, 0] != edges[:, 1]]
    forward = rng.uniform(0, 1, len(edges)) * (rng.uniform(size=len(edges)) < 0.8)
    backward = rng.uniform(0, 1, len(edges)) * (rng.uniform(size=len(edges)) < 0.5)
    source = rng.uniform(0, 2, n) * (rng.uniform(size=n) < 0.3)
    sink = rng.uniform(0, 2, n) * (rng.uniform(size=n) < 0.3)
    flow, side = rc.max_flow(n, edges, forward, backward, source, sink)

    G = nx.DiGraph()
    G.add_nodes_from(["s", "t", *range(n)])
    def add(u, v, c):
        if c > 0:
            G.add_edge(u, v, capacity=G.get_edge_data(u, v, {"capacity": 0.0})["capacity"] + c)
    for (u, v), f, b in zip(edges.tolist(), forward, backward):
        add(u, v, f), add(v, u, b)
    for u in range(n):
        add("s", u, source[u]), add(u, "t", sink[u])
    expected, _ = nx.minimum_cut(G, "s", "t")
    assert flow == pytest.approx(expected, rel=1e-9, abs=1e-12)
    # Our partition is a cut of that capacity.
    S = {"s", *np.flatnonzero(side).tolist()}
    capacity = sum(d["capacity"] for u, v, d in G.edges(data=True) if u in S and v not in S)
    assert capacity == pytest.approx(expected, rel=1e-9, abs=1e-12)


def test_sphere_samples_give_a_closed_sphere():
    P, _ = datasets.sphere_points(4000, seed=1)
    mesh = rc.graph_cut(P, resolution=32)
    assert_closed_manifold(mesh.V, mesh.F, 2)
    error = np.abs(np.linalg.norm(mesh.V, axis=1) - 1.0)
    assert mesh.voxel_size == pytest.approx(2 / 32, rel=0.01)
    assert error.mean() < 0.2 * mesh.voxel_size, error.mean() / mesh.voxel_size   # measured 0.11
    assert error.max() < 0.75 * mesh.voxel_size
    assert geometry.volume(mesh.V, mesh.F) == pytest.approx(4 / 3 * np.pi, rel=0.03)
    assert 0 < mesh.free_voxels < np.prod(mesh.shape) and mesh.cut > 0


def test_torus_samples_give_a_closed_torus():
    R, r = 1.0, 0.35
    V, F = datasets.torus(R, r, 96, 48)
    P, _ = datasets.sample_points(V, F, 12000, seed=2)
    mesh = rc.graph_cut(P, resolution=48)
    assert_closed_manifold(mesh.V, mesh.F, 0)
    X = mesh.V
    error = np.abs(np.hypot(np.hypot(X[:, 0], X[:, 1]) - R, X[:, 2]) - r)
    assert error.mean() < 0.15 * mesh.voxel_size, error.mean() / mesh.voxel_size   # measured 0.087


def test_a_wide_gap_needs_an_inside_seed():
    P, _ = datasets.sphere_points(3000, seed=3)
    P = P[P[:, 2] < 0.8]  # a hole of radius 0.6 at the top
    with pytest.raises(meshsmith.InputError, match="inside seeds"):
        rc.graph_cut(P, resolution=24)
    mesh = rc.graph_cut(P, resolution=24, inside=[[0.0, 0.0, 0.0]])
    assert_closed_manifold(mesh.V, mesh.F, 2)
    # The cut closes the gap near the samples' rim, not through the ball.
    assert mesh.V[:, 2].max() < 1.0 and mesh.V[:, 2].max() > 0.7
    assert geometry.volume(mesh.V, mesh.F) > 0.8 * 4 / 3 * np.pi


def test_progress_reaches_one():
    seen = []
    rc.graph_cut(datasets.sphere_points(500)[0], resolution=12, progress=lambda f, s: seen.append(f) or True)
    assert seen[-1] == 1.0 and seen == sorted(seen)


@pytest.mark.parametrize("P, options, message", [
    (np.zeros((3, 3)), {}, "at least 4"),
    (np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0.0]]), {}, "one line"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.nan]]), {}, "P"),
    (None, {"resolution": 1}, "resolution"),
    (None, {"crust": 0.1}, "crust"),
    (None, {"exponent": np.nan}, "exponent"),
    (None, {"inside": [[5.0, 0, 0]]}, "inside"),
    (None, {"inside": [[np.nan, 0, 0]]}, "inside"),
    (None, {"resolution": 1024}, "2\\^26"),
])
def test_bad_input(P, options, message):
    if P is None:
        P = datasets.sphere_points(200)[0]
    with pytest.raises(meshsmith.InputError, match=message):
        rc.graph_cut(P, **options)


@pytest.mark.parametrize("args, message", [
    ((2, [[0, 0]], [1.0], [0.0], [1, 0], [0, 1]), "different nodes"),
    ((2, [[0, 2]], [1.0], [0.0], [1, 0], [0, 1]), "different nodes"),
    ((2, [[0, 1]], [-1.0], [0.0], [1, 0], [0, 1]), "capacity"),
    ((2, [[0, 1]], [np.inf], [0.0], [1, 0], [0, 1]), "capacity"),
    ((2, [[0, 1]], [1.0, 2.0], [0.0], [1, 0], [0, 1]), "one value per edge"),
    ((3, [[0, 1]], [1.0], [0.0], [1, 0], [0, 1]), "one value per node"),
])
def test_max_flow_bad_input(args, message):
    with pytest.raises(meshsmith.InputError, match=message):
        rc.max_flow(*args)
