"""meshsmith.reconstruction.marching_cubes and marching_cubes_sparse (§2.2, §3.1).

Analytic fields (sphere, torus, a capped gyroid) give closed, manifold, outward-oriented meshes
of the right Euler characteristic; vertices converge to the true surface as O(h²); the vertex set
is libigl's (to 1e-12) and scikit-image's (float32 inside: to 1e-6); random fields, full of
ambiguous faces, still give closed manifolds; the sparse variant gives the dense arrays exactly
and contours a 512³ grid from a few million evaluations.
"""
import numpy as np
import pytest
from scipy.spatial import cKDTree

import meshsmith
from meshsmith import geometry, reconstruction as rc, topology


def grid(n, lo=-1.0, hi=1.0):
    h = (hi - lo) / (n - 1)
    x = np.linspace(lo, hi, n)
    return np.meshgrid(x, x, x, indexing="ij"), h


def sphere(X, Y, Z, r=0.7):
    return np.sqrt(X ** 2 + Y ** 2 + Z ** 2) - r


def torus(X, Y, Z, R=0.6, r=0.25):
    return np.sqrt((np.sqrt(X ** 2 + Y ** 2) - R) ** 2 + Z ** 2) - r


def capped_gyroid(X, Y, Z):
    """The gyroid inside radius 0.55, pushed smoothly above its range (> 1.5) beyond radius 0.9:
    a closed, smooth level set of genus 2."""
    s = np.clip((np.sqrt(X ** 2 + Y ** 2 + Z ** 2) - 0.55) / 0.35, 0, 1)
    return (np.sin(6 * X) * np.cos(6 * Y) + np.sin(6 * Y) * np.cos(6 * Z) + np.sin(6 * Z) * np.cos(6 * X)
            + 3 * s * s * (3 - 2 * s))


def contour(field, n):
    (X, Y, Z), h = grid(n)
    return rc.marching_cubes(field(X, Y, Z), origin=(-1, -1, -1), spacing=(h, h, h))


def assert_closed_manifold(V, F, chi):
    assert F.dtype == np.int64 and V.dtype == np.float64
    assert topology.is_manifold(F) and topology.is_oriented(F)
    assert topology.boundary_loops(F) == []
    assert topology.euler_characteristic(F) == chi
    np.testing.assert_array_equal(np.unique(F), np.arange(len(V)))


@pytest.mark.parametrize("field, chi, volume", [(sphere, 2, 4 / 3 * np.pi * 0.7 ** 3),
                                                (torus, 0, 2 * np.pi ** 2 * 0.6 * 0.25 ** 2)])
def test_analytic_fields_give_closed_outward_manifolds(field, chi, volume):
    V, F, centres, *_ = contour(field, 64)
    assert_closed_manifold(V, F, chi)
    assert centres == 0
    assert geometry.volume(V, F) == pytest.approx(volume, rel=5e-3)  # positive: normals outward


@pytest.mark.parametrize("n", [48, 64, 96, 128])
def test_gyroid_has_the_same_topology_at_every_resolution(n):
    V, F, *_ = contour(capped_gyroid, n)
    assert_closed_manifold(V, F, -2)
    assert topology.connected_components(F).count == 1
    assert geometry.volume(V, F) > 0


def test_vertex_distance_to_the_sphere_falls_as_h_squared():
    errors, steps = [], []
    for n in (17, 33, 65, 129):
        (X, Y, Z), h = grid(n)
        V = rc.marching_cubes(sphere(X, Y, Z), origin=(-1, -1, -1), spacing=(h, h, h)).V
        errors.append(np.abs(np.linalg.norm(V, axis=1) - 0.7).max())
        steps.append(h)
    orders = np.diff(np.log(errors)) / np.diff(np.log(steps))
    assert np.all(orders > 1.8), orders  # observed: 1.95 to 2.0 (the README quotes it)


@pytest.mark.parametrize("field", [sphere, torus, capped_gyroid])
def test_vertex_set_is_libigls_and_scikit_images(field):
    igl = pytest.importorskip("igl")
    n = 40
    (X, Y, Z), h = grid(n)
    values = field(X, Y, Z)
    ours = rc.marching_cubes(values, origin=(-1, -1, -1), spacing=(h, h, h))
    corners = np.c_[X.ravel(order="F"), Y.ravel(order="F"), Z.ravel(order="F")]
    V_igl, F_igl, _ = igl.marching_cubes(values.ravel(order="F"), corners, n, n, n, 0.0)
    assert len(ours.V) == len(V_igl) + ours.centre_vertices
    for a, b in ((ours.V, V_igl), (V_igl, ours.V)):
        assert cKDTree(b).query(a)[0].max() < 1e-12
    measure = pytest.importorskip("skimage.measure")
    V_sk, *_ = measure.marching_cubes(values, 0.0, spacing=(h, h, h))
    V_sk = V_sk - 1.0
    assert len(V_sk) == len(ours.V)
    for a, b in ((ours.V, V_sk), (V_sk, ours.V)):
        assert cKDTree(b).query(a)[0].max() < 1e-6  # scikit-image interpolates in float32


@pytest.mark.parametrize("seed", range(4))
def test_random_fields_full_of_ambiguous_faces_give_closed_manifolds(seed):
    rng = np.random.default_rng(seed)
    values = rng.standard_normal((14, 15, 16))
    values[[0, -1], :, :] = values[:, [0, -1], :] = values[:, :, [0, -1]] = 1.0  # level set closed in the grid
    mesh = rc.marching_cubes(values, iso=0.1)
    assert topology.is_manifold(mesh.F) and topology.is_oriented(mesh.F)
    assert topology.boundary_loops(mesh.F) == []
    # outward: the enclosed volume (bubbles of outside within the inside count negative) is positive
    assert geometry.volume(mesh.V, mesh.F) > 0
    expected = sum(int((np.diff((values - 0.1) < 0, axis=a)).sum()) for a in range(3))
    assert len(mesh.V) - mesh.centre_vertices == expected  # one vertex per crossed grid edge
    assert expected > 100


def test_values_at_the_iso_value_count_as_outside_and_the_result_is_deterministic():
    (X, Y, Z), h = grid(33)
    values = np.round(sphere(X, Y, Z) / h) * h  # many grid values exactly on the iso-value
    a = rc.marching_cubes(values, spacing=(h, h, h))
    b = rc.marching_cubes(values.copy(), spacing=(h, h, h))
    np.testing.assert_array_equal(a.V, b.V)
    np.testing.assert_array_equal(a.F, b.F)
    assert topology.is_manifold(a.F) and topology.boundary_loops(a.F) == []


def test_sparse_variant_gives_the_dense_arrays():
    (X, Y, Z), h = grid(61)
    values = torus(X, Y, Z)
    dense = rc.marching_cubes(values, origin=(-1, -1, -1), spacing=(h, h, h))

    def field(P):
        return torus(P[:, 0], P[:, 1], P[:, 2])

    seeds = np.array([[0.6, 0.0, 0.25]])  # one point on the surface: the rest is followed
    sparse = rc.marching_cubes_sparse(field, shape=values.shape, seeds=seeds, origin=(-1, -1, -1), spacing=(h, h, h))
    np.testing.assert_allclose(sparse.V, dense.V, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(sparse.F, dense.F)
    assert sparse.blocks < dense.blocks and sparse.evaluations < values.size


def test_sparse_variant_contours_a_512_cubed_grid_without_the_full_grid():
    n = 512
    h = 2.0 / (n - 1)
    calls = []

    def field(P):
        calls.append(len(P))
        return np.sqrt((P ** 2).sum(axis=1)) - 0.7

    mesh = rc.marching_cubes_sparse(field, shape=(n, n, n), seeds=[[0.7, 0.0, 0.0]], origin=(-1, -1, -1),
                                    spacing=(h, h, h))
    assert_closed_manifold(mesh.V, mesh.F, 2)
    assert mesh.evaluations == sum(calls) < 0.06 * n ** 3  # 6.9M, 5% of the grid (corners repeat), in waves
    assert max(calls) <= 2048 * 9 ** 3
    assert np.abs(np.linalg.norm(mesh.V, axis=1) - 0.7).max() < h * h


def test_sparse_variant_finds_only_the_pieces_it_reaches():
    def field(P):  # two balls
        return np.minimum(np.linalg.norm(P - [0.5, 0, 0], axis=1), np.linalg.norm(P + [0.5, 0, 0], axis=1)) - 0.3

    h = 2.0 / 40
    one = rc.marching_cubes_sparse(field, shape=(41, 41, 41), seeds=[[0.8, 0, 0]], origin=(-1, -1, -1), spacing=(h,) * 3)
    both = rc.marching_cubes_sparse(field, shape=(41, 41, 41), seeds=[[0.8, 0, 0], [-0.8, 0, 0]],
                                    origin=(-1, -1, -1), spacing=(h,) * 3)
    assert topology.connected_components(one.F).count == 1
    assert topology.connected_components(both.F).count == 2
    assert topology.euler_characteristic(both.F) == 4


def test_progress_is_reported_and_cancels():
    (X, Y, Z), h = grid(64)
    seen = []
    rc.marching_cubes(sphere(X, Y, Z), progress=lambda f, s: seen.append(f))
    assert seen[-1] == 1.0
    with pytest.raises(meshsmith.Cancelled):
        rc.marching_cubes(sphere(X, Y, Z), progress=lambda f, s: False)
    with pytest.raises(meshsmith.Cancelled):
        rc.marching_cubes_sparse(lambda P: np.linalg.norm(P, axis=1) - 20, shape=(64, 64, 64), seeds=[[20, 0, 0]],
                                 progress=lambda f, s: False)


def test_bad_input_is_an_input_error():
    good = np.ones((3, 3, 3))
    bad = good.copy()
    bad[1, 2, 0] = np.nan
    with pytest.raises(meshsmith.InputError, match=r"values\[1, 2, 0\] is nan"):
        rc.marching_cubes(bad)
    with pytest.raises(meshsmith.InputError, match="3-D"):
        rc.marching_cubes(np.ones((4, 4)))
    with pytest.raises(meshsmith.InputError, match="at least 2"):
        rc.marching_cubes(np.ones((1, 4, 4)))
    with pytest.raises(meshsmith.InputError, match="spacing"):
        rc.marching_cubes(good, spacing=(1, 0, 1))
    with pytest.raises(meshsmith.InputError, match="origin"):
        rc.marching_cubes(good, origin=(1, 2))
    with pytest.raises(meshsmith.InputError, match="iso"):
        rc.marching_cubes(good, iso=np.inf)
    field = lambda P: np.linalg.norm(P, axis=1) - 2  # noqa: E731
    with pytest.raises(meshsmith.InputError, match="no seed"):
        rc.marching_cubes_sparse(field, shape=(8, 8, 8), seeds=[[100.0, 0, 0]])
    with pytest.raises(meshsmith.InputError, match="one per point"):
        rc.marching_cubes_sparse(lambda P: np.zeros(3), shape=(8, 8, 8), seeds=[[1.0, 1, 1]])
    with pytest.raises(meshsmith.InputError, match="finite"):
        rc.marching_cubes_sparse(lambda P: np.full(len(P), np.nan), shape=(8, 8, 8), seeds=[[1.0, 1, 1]])
    with pytest.raises(meshsmith.InputError, match="callable"):
        rc.marching_cubes_sparse(None, shape=(8, 8, 8), seeds=[[1.0, 1, 1]])
    with pytest.raises(meshsmith.InputError, match="block_size"):
        rc.marching_cubes_sparse(field, shape=(8, 8, 8), seeds=[[1.0, 1, 1]], block_size=0)
    with pytest.raises(ZeroDivisionError):  # what the field raises reaches the caller as itself
        rc.marching_cubes_sparse(lambda P: 1 / 0, shape=(8, 8, 8), seeds=[[1.0, 1, 1]])
