"""geometry.cotan_laplacian(V, F, intrinsic_delaunay=True): the intrinsic Delaunay cotangent Laplacian
(§3.0.2 "Delaunay cot-weights", issue 17): agreement with libigl's intrinsic_delaunay_cotmatrix, the
Delaunay triangulation of planar points in convex position as ground truth, equality with the plain
Laplacian on Delaunay meshes, non-negative interior weights on every shared mesh, bad input."""
from pathlib import Path

import igl
import numpy as np
import pytest
import scipy.sparse
import scipy.spatial

import meshsmith
from meshsmith import datasets, geometry, io

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
    assert relative(geometry.cotan_laplacian(V, fan, intrinsic_delaunay=True), truth) < 1e-10


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
def test_interior_weights_are_non_negative_on_every_shared_mesh_and_match_libigl(data_dir: Path, name):
    V, F = io.read_mesh(data_dir / name)
    ours = geometry.cotan_laplacian(V, F, intrinsic_delaunay=True)
    theirs = igl.intrinsic_delaunay_cotmatrix(V, F.astype(np.int64))
    theirs = theirs[0] if isinstance(theirs, tuple) else theirs
    # camelhead's slivers carry cotangents of 1e5, whose round-off is larger than the others'.
    assert relative(ours, theirs) < 1e-9
    rows, cols, weights = edge_weights(ours)
    boundary = boundary_edges(F)
    negative = [(int(i), int(j)) for i, j in zip(rows[weights < 0], cols[weights < 0])]
    # A boundary edge has one cotangent, negative when its opposite angle is obtuse; no flip changes it.
    assert all((min(e), max(e)) in boundary for e in negative), negative[:5]
    plain_negative = (edge_weights(geometry.cotan_laplacian(V, F))[2] < 0).mean()
    print(f"{name}: plain cot weights negative on {100 * plain_negative:.1f}% of the edges; intrinsic Delaunay: "
          f"{len(negative)} negative, all on the boundary")


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
