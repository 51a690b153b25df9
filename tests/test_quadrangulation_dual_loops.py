"""Dual-loop quad layouts (§5.3): loops along the cross field, regions that are disks with at most
one singularity, and the arrangement's dual as a manifold quad layout with the input's Euler
characteristic — on a sphere, a torus, a cube-like shape and spot — checked independently of the
C++ report (loops as edge paths, regions by a face flood fill here, the layout's topology with
meshsmith.topology), and bad input."""
import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

import meshsmith
from meshsmith import datasets, io, repair, topology
from meshsmith.quadrangulation import cross_field, dual_loop_layout


def edge_set(F):
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    return {tuple(e) for e in E.tolist()}


def loop_edges(loop):
    return [tuple(sorted((int(a), int(b)))) for a, b in zip(loop, np.roll(loop, -1))]


def check_layout(V, F, layout):
    """Every invariant the layout promises, recomputed here; returns the independent regions."""
    edges = edge_set(F)
    singular = set(layout.singular_vertices.tolist())
    used = {}
    for k, loop in enumerate(layout.loops):
        assert len(loop) >= 3 and len(set(loop.tolist())) == len(loop)     # closed, no self-overlap
        assert not singular & set(loop.tolist())                          # no singularity on a loop
        for e in loop_edges(loop):
            assert e in edges                                             # an edge path of the mesh
            assert e not in used, f"loops {used.get(e)} and {k} share edge {e}"
            used[e] = k
    # Vertices on two loops are exactly the crossings (never three loops at a vertex).
    count = np.zeros(len(V), int)
    for loop in layout.loops:
        count[loop] += 1
    assert count.max(initial=0) <= 2
    assert sorted(np.flatnonzero(count == 2).tolist()) == sorted(layout.Q_vertex.tolist())
    # Regions: faces joined across non-loop edges (scipy's connected components).
    sides = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    face = np.tile(np.arange(len(F)), 3)
    key = np.sort(sides, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    a, b = order[0::2], order[1::2]                                       # closed: two sides per edge
    assert (key[a] == key[b]).all()
    cut = np.array([tuple(e) in used for e in key[a].tolist()], dtype=bool)
    A = coo_matrix((np.ones((~cut).sum()), (face[a][~cut], face[b][~cut])), shape=(len(F), len(F)))
    n_regions, labels = connected_components(A, directed=False)
    assert n_regions == layout.report.regions
    # Same partition as the layout's labels.
    pairs = set(zip(labels.tolist(), layout.region.tolist()))
    assert len(pairs) == n_regions
    return labels


def check_complete(V, F, layout):
    labels = check_layout(V, F, layout)
    report = layout.report
    assert report.complete, report.failure
    assert report.failure == ""
    singular = layout.singular_vertices
    for r in range(report.regions):
        faces = F[labels == r]
        assert topology.euler_characteristic(faces) == 1 and len(topology.boundary_loops(faces)) == 1  # a disk
        inside = np.isin(singular, faces.ravel())
        assert inside.sum() <= 1                                          # at most one singularity
    Q = layout.Q
    assert len(layout.Vq) == report.regions and Q.shape == (report.crossings, 4)
    T = np.concatenate([Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]])
    assert topology.is_manifold(T) and topology.is_oriented(T)
    assert all(len(set(q)) == 4 for q in Q.tolist())
    assert topology.euler_characteristic(T) == topology.euler_characteristic(F)
    assert len(topology.boundary_loops(T)) == 0
    # Layout vertex valence = crossings on the region's boundary; a region with a singularity of
    # index k has 4 − k corners where the loops meet it as the field says.
    valence = np.bincount(Q.ravel(), minlength=report.regions)
    assert (valence == report.region_corners).all() and valence.min() >= 3
    return labels


def test_sphere_layout_is_a_closed_quad_mesh_with_one_singularity_per_corner():
    V, F = datasets.icosphere(3)
    field = cross_field(V, F, align="smooth")
    layout = dual_loop_layout(V, F, field)
    check_complete(V, F, layout)
    assert len(layout.singular_vertices) == 8
    regions_with_singularity = (layout.report.region_singularities == 1).sum()
    assert regions_with_singularity == 8                  # each of the 8 singularities in its own region
    assert layout.report.euler_layout == 2


def test_torus_layout_is_a_regular_grid():
    V, F = datasets.torus(n_major=48, n_minor=16)
    field = cross_field(V, F, curvature_weight=1.0)
    layout = dual_loop_layout(V, F, field)
    check_complete(V, F, layout)
    assert len(layout.singular_vertices) == 0
    valence = np.bincount(layout.Q.ravel())
    assert (valence == 4).all()                           # no irregular layout vertex
    assert layout.report.euler_layout == 0


def test_spacing_sets_the_loop_density():
    V, F = datasets.torus(n_major=48, n_minor=16)
    field = cross_field(V, F, curvature_weight=1.0)
    coarse = dual_loop_layout(V, F, field, spacing=1.0)
    fine = dual_loop_layout(V, F, field, spacing=0.4)
    assert fine.report.loops > coarse.report.loops
    assert fine.report.max_distance_to_loops <= 0.75 * 0.4 + 1e-9
    assert np.isclose(fine.report.spacing, 0.4)


def test_loops_follow_the_field_on_the_torus():
    # On the torus the curvature field runs along the parallels and meridians: each loop stays
    # on one family, so its vertices keep one distance from the axis (a parallel) or one angle
    # about it (a meridian) up to the zig-zag of the edge path.
    V, F = datasets.torus(n_major=48, n_minor=16)
    layout = dual_loop_layout(V, F, cross_field(V, F, curvature_weight=1.0))
    radius = np.hypot(V[:, 0], V[:, 1])
    angle = np.arctan2(V[:, 1], V[:, 0])
    step = 2 * np.pi / 48
    for loop in layout.loops:
        spread_radius = np.ptp(radius[loop]) if np.ptp(V[loop, 2]) < 1e-9 else np.inf
        turn = np.angle(np.exp(1j * (angle[loop] - angle[loop[0]])))
        assert min(spread_radius, np.ptp(turn)) < 2.5 * step or np.ptp(V[loop, 2]) < 1e-9


def test_layout_pickles_and_unpacks():
    import pickle
    V, F = datasets.icosphere(2)
    layout = dual_loop_layout(V, F, cross_field(V, F, align="smooth"))
    loops, region, Vq, Q, report = layout
    assert len(region) == len(F) and Vq.shape[1] == 3 and Q.shape[1] == 4
    again = pickle.loads(pickle.dumps(layout))
    assert np.array_equal(again.Q, layout.Q) and again.report.failure == layout.report.failure


@pytest.mark.parametrize("name", ["bumpy-cube.obj", "spot.obj"])
def test_shared_meshes(name, data_dir):
    V, F = io.read_mesh(data_dir / name)
    V, F = repair.clean(V, F)[:2]
    field = cross_field(V, F)
    layout = dual_loop_layout(V, F, field)
    labels = check_layout(V, F, layout)
    report = layout.report
    assert report.euler_input == topology.euler_characteristic(F)
    if name == "bumpy-cube.obj":
        check_complete(V, F, layout)
    else:
        EXPECTED[name](V, F, layout, labels)


def spot_reached(V, F, layout, labels):
    check_complete(V, F, layout)


EXPECTED = {"spot.obj": spot_reached}


def test_bad_input():
    V, F = datasets.icosphere(1)
    theta = np.zeros(len(F))
    with pytest.raises(meshsmith.InputError, match="boundary"):
        Vg, Fg = datasets.grid(6, 6)
        dual_loop_layout(Vg, Fg, np.zeros(len(Fg)))
    bad = theta.copy()
    bad[3] = np.nan
    with pytest.raises(meshsmith.InputError, match="face 3"):
        dual_loop_layout(V, F, bad)
    with pytest.raises(meshsmith.InputError, match="angles"):
        dual_loop_layout(V, F, theta[:-1])
    with pytest.raises(meshsmith.InputError, match="spacing"):
        dual_loop_layout(V, F, theta, spacing=0.0)
    with pytest.raises(meshsmith.InputError, match="anisotropy"):
        dual_loop_layout(V, F, theta, anisotropy=0.5)
    with pytest.raises(meshsmith.InputError, match="max_deviation"):
        dual_loop_layout(V, F, theta, max_deviation=95.0)
    with pytest.raises(meshsmith.InputError, match="max_loops"):
        dual_loop_layout(V, F, theta, max_loops=0)
    with pytest.raises(meshsmith.InputError):
        dual_loop_layout(V, F[:, :2], theta)
    V2 = np.vstack([V, V + 5.0])
    F2 = np.vstack([F, F + len(V)])
    with pytest.raises(meshsmith.InputError):
        dual_loop_layout(V2, F2, np.zeros(len(F2)))       # two components


def test_cancel():
    V, F = datasets.icosphere(3)
    field = cross_field(V, F, align="smooth")
    with pytest.raises(meshsmith.Cancelled):
        dual_loop_layout(V, F, field, progress=lambda fraction, stage: False)
