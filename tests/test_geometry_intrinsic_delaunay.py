"""geometry.cotan_laplacian(V, F, intrinsic_delaunay=True): the intrinsic Delaunay cotangent Laplacian
(§3.0.2 "Delaunay cot-weights", issue 17): agreement with libigl's intrinsic_delaunay_cotmatrix, the
Delaunay triangulation of planar points in convex position as ground truth, equality with the plain
Laplacian on Delaunay meshes, non-negative weights (interior and boundary: obtuse angles opposite
boundary edges are refined away and lumped back) with linear precision inside, on every shared mesh,
bad input."""
from pathlib import Path

import igl
import numpy as np
import pytest
import scipy.sparse
import scipy.spatial

import meshsmith
from meshsmith import datasets, geometry, io, topology

SHARED_MESHES = ["armadillo.obj", "bob_tri.obj", "bumpy-cube.obj", "bunny.off", "camelhead.off", "cheburashka.off",
                 "decimated-knight.off", "decimated-max.obj", "fandisk.obj", "fertility.off", "hand_lowres.obj",
                 "kitten.off", "nefertiti-lowres.obj", "plane_holes.obj", "pmp-bunny.off", "rocker-arm.obj",
                 "spot.obj", "stanford-bunny.obj", "torus.obj"]


def relative(A, B) -> float:
    return float(abs(A - B).max() / abs(B).max())


def edge_weights(L):
    """(i, j, w) of every stored entry above the diagonal."""
    upper = scipy.sparse.triu(L, 1).tocoo()
    return upper.row, upper.col, upper.data


def boundary_edges(F) -> set:
    sides = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(sides, axis=0, return_counts=True)
    return set(map(tuple, unique[counts == 1].tolist()))


def test_a_fan_of_points_in_convex_position_becomes_their_delaunay_triangulation():
    # Points on an ellipse at random angles: no four co-circular, so the Delaunay triangulation is
    # unique; the fan from point 0 is a valid but far-from-Delaunay triangulation of the same disk.
    rng = np.random.default_rng(4)
    t = np.sort(rng.uniform(0, 2 * np.pi, 30))
    V = np.column_stack([2.0 * np.cos(t), np.sin(t), np.zeros_like(t)])
    fan = np.array([[0, i, i + 1] for i in range(1, len(V) - 1)])
    plain = geometry.cotan_laplacian(V, fan)
    assert (edge_weights(plain)[2] < -1e-3).sum() > 5            # the fan is far from Delaunay
    delaunay = scipy.spatial.Delaunay(V[:, :2]).simplices
    u, v = V[delaunay[:, 1]] - V[delaunay[:, 0]], V[delaunay[:, 2]] - V[delaunay[:, 0]]
    counter_clockwise = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0] > 0
    delaunay = np.where(counter_clockwise[:, None], delaunay, delaunay[:, [0, 2, 1]])
    truth = geometry.cotan_laplacian(V, delaunay)
    assert edge_weights(truth)[2].min() > 0.0  # no obtuse angle opposite a hull edge: nothing to split
    assert relative(geometry.cotan_laplacian(V, fan, intrinsic_delaunay=True), truth) < 1e-10


def test_an_obtuse_boundary_triangle_is_split_at_its_altitude_and_lumped_back():
    # One triangle, obtuse at c: the foot h of c's altitude (a quarter of the way from a to b)
    # splits ab into two right triangles; h is lumped back with f_h = (3 f_a + f_b) / 4: the
    # weight w of ch goes to ca and cb as 3w/4 and w/4, those of ah and hb to ab as t² and (1 − t)².
    a, b, c = np.array([0.0, 0, 0]), np.array([4.0, 0, 0]), np.array([1.0, 0.5, 0])
    V, F = np.array([a, b, c]), np.array([[0, 1, 2]])
    h, t = np.array([1.0, 0, 0]), 0.25

    def half_cot(p, q, r):  # ½ cot of the angle at p in triangle (p, q, r)
        u, v = q - p, r - p
        return 0.5 * u.dot(v) / np.linalg.norm(np.cross(u, v))

    w_ah, w_hb = half_cot(c, a, h), half_cot(c, h, b)
    w_ch = half_cot(a, c, h) + half_cot(b, h, c)
    expected = {(0, 1): t * t * w_ah + (1 - t) ** 2 * w_hb, (0, 2): (1 - t) * w_ch, (1, 2): t * w_ch}
    L = geometry.cotan_laplacian(V, F, intrinsic_delaunay=True).toarray()
    assert geometry.cotan_laplacian(V, F).toarray()[0, 1] < 0       # the plain weight of ab is negative
    for (i, j), w in expected.items():
        assert L[i, j] == pytest.approx(w, rel=1e-12, abs=1e-15) and L[j, i] == L[i, j]
    np.testing.assert_allclose(L.sum(axis=1), 0.0, atol=1e-14)


def test_linear_precision_inside_a_planar_mesh_with_split_boundary_edges():
    # A grid whose second row is pushed (and jittered) towards the boundary row: the strip's
    # triangles are flat, with obtuse angles opposite boundary edges that no flip removes.
    V, F = datasets.grid(12, 12)
    rows_y = np.unique(V[:, 1])
    second = np.isclose(V[:, 1], rows_y[1])
    V = V.copy()
    V[second, 1] = rows_y[0] + 0.15 * (rows_y[1] - rows_y[0])
    V[second, 0] += np.random.default_rng(3).uniform(-0.3, 0.3, second.sum()) * (rows_y[1] - rows_y[0])
    theirs = igl.intrinsic_delaunay_cotmatrix(V, F.astype(np.int64))
    theirs = theirs[0] if isinstance(theirs, tuple) else theirs
    boundary = boundary_edges(F)
    rows, cols, weights = edge_weights(theirs)
    assert sum((int(i), int(j)) in boundary for i, j in zip(rows[weights < 0], cols[weights < 0])) >= 3
    L = geometry.cotan_laplacian(V, F, intrinsic_delaunay=True)
    assert edge_weights(L)[2].min() >= 0.0
    interior = np.setdiff1d(np.arange(len(V)), np.unique(np.concatenate(topology.boundary_loops(F))))
    linear = V @ np.array([0.7, -1.3, 0.0]) + 0.2
    assert abs(L @ linear)[interior].max() < 1e-12 * abs(L).max()
    assert np.linalg.eigvalsh(L.toarray()).max() < 1e-10 * abs(L).max()


@pytest.mark.parametrize("V, F", [datasets.icosphere(3), datasets.torus(n_major=48, n_minor=24), datasets.grid(8, 8)],
                         ids=["icosphere", "torus", "grid (co-circular quads)"])
def test_equals_the_plain_cotan_laplacian_on_an_already_delaunay_mesh(V, F):
    plain = geometry.cotan_laplacian(V, F)
    assert edge_weights(plain)[2].min() > -1e-12          # Delaunay already: nothing to flip
    assert relative(geometry.cotan_laplacian(V, F, intrinsic_delaunay=True), plain) < 1e-13


def test_agrees_with_libigl_on_a_noisy_mesh_and_is_negative_semidefinite():
    V, F = datasets.noisy(*datasets.icosphere(3), sigma=0.3, seed=1, direction="isotropic")
    ours = geometry.cotan_laplacian(V, F, intrinsic_delaunay=True)
    theirs = igl.intrinsic_delaunay_cotmatrix(V, F.astype(np.int64))
    theirs = theirs[0] if isinstance(theirs, tuple) else theirs
    assert (edge_weights(geometry.cotan_laplacian(V, F))[2] < 0).sum() > 20
    assert relative(ours, theirs) < 1e-12
    assert edge_weights(ours)[2].min() >= 0.0
    assert abs(ours - ours.T).max() == 0.0
    np.testing.assert_allclose(np.asarray(ours.sum(axis=1)).ravel(), 0.0, atol=1e-12 * abs(ours).max())
    assert np.linalg.eigvalsh(ours.toarray()).max() < 1e-10 * abs(ours).max()


@pytest.mark.parametrize("name", SHARED_MESHES)
def test_weights_are_non_negative_on_every_shared_mesh_and_match_libigl_away_from_split_edges(data_dir: Path, name):
    V, F = io.read_mesh(data_dir / name)
    ours = geometry.cotan_laplacian(V, F, intrinsic_delaunay=True)
    theirs = igl.intrinsic_delaunay_cotmatrix(V, F.astype(np.int64))
    theirs = theirs[0] if isinstance(theirs, tuple) else theirs
    rows, cols, weights = edge_weights(theirs)
    boundary = boundary_edges(F)
    # libigl's negative weights beyond round-off (it keeps co-circular quads' ±1e-16) are on the
    # boundary only (one cotangent, of an obtuse angle; no flip changes it); ours are split there,
    # so every weight is non-negative.
    significant = weights < -1e-12 * abs(theirs).max()
    negative = [(int(i), int(j)) for i, j in zip(rows[significant], cols[significant])]
    assert all((min(e), max(e)) in boundary for e in negative), negative[:5]
    assert edge_weights(ours)[2].min() >= 0.0
    assert abs(ours - ours.T).max() == 0.0
    np.testing.assert_allclose(np.asarray(ours.sum(axis=1)).ravel(), 0.0, atol=1e-11 * abs(ours).max())
    # Away from the split edges (two rings around their endpoints) libigl's matrix to round-off;
    # camelhead's slivers carry cotangents of 1e5, whose round-off is larger than the others'.
    near = np.zeros(len(V), bool)
    near[[v for e in negative for v in e]] = True
    near[np.unique(np.concatenate([rows[weights < 0], cols[weights < 0]]))] = True
    adjacency = (abs(theirs) + abs(ours)) > 0
    for _ in range(2):
        near = near | (adjacency @ near)
    keep = np.flatnonzero(~near)
    assert relative(ours[keep][:, keep], theirs[keep][:, keep]) < 1e-9
    plain_negative = (edge_weights(geometry.cotan_laplacian(V, F))[2] < 0).mean()
    print(f"{name}: plain cot weights negative on {100 * plain_negative:.1f}% of the edges; libigl's intrinsic "
          f"Delaunay weights negative on {len(negative)} boundary edges; ours on none")


def test_scaling_by_a_power_of_two_changes_nothing():
    V, F = datasets.noisy(*datasets.icosphere(2), sigma=0.3, seed=2, direction="isotropic")
    L = geometry.cotan_laplacian(V, F, intrinsic_delaunay=True)
    for k in (-997, 997):
        scaled = geometry.cotan_laplacian(np.ldexp(V, k), F, intrinsic_delaunay=True)
        assert relative(scaled, L) < 1e-13


def test_degenerate_faces_contribute_nothing():
    V, F = datasets.grid(4, 4)
    F_repeated = np.vstack([F, [[0, 0, 1]]])
    L = geometry.cotan_laplacian(V, F, intrinsic_delaunay=True)
    assert relative(geometry.cotan_laplacian(V, F_repeated, intrinsic_delaunay=True), L) == 0.0


def test_non_manifold_and_misoriented_meshes_are_rejected():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], dtype=float)
    three_faces = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    with pytest.raises(meshsmith.InputError, match=r"edge \(0, 1\) has 3 faces"):
        geometry.cotan_laplacian(V, three_faces, intrinsic_delaunay=True)
    misoriented = np.array([[0, 1, 2], [0, 1, 3]])
    with pytest.raises(meshsmith.InputError, match="same direction"):
        geometry.cotan_laplacian(V, misoriented, intrinsic_delaunay=True)
    geometry.cotan_laplacian(V, misoriented)  # the plain Laplacian does not care
