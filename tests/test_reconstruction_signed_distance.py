"""meshsmith.reconstruction: tangent_plane_sdf, winding_number, mesh_sdf, sample_grid (§2.2, §3.1).

The tangent-plane distance is the brute-force formula of Hoppe et al. on scipy's nearest samples;
mesh_sdf agrees with igl.signed_distance (winding-number sign) on closed meshes and on meshes with
holes; the hierarchical winding number is igl's exact one to 3e-3; a sampled mesh SDF contours
back (marching cubes) into the mesh.
"""
import numpy as np
import pytest
from scipy.spatial import cKDTree

import meshsmith
from meshsmith import datasets, geometry, io, reconstruction as rc, topology


def sphere_samples(n=4000, seed=0):
    P, N = datasets.sphere_points(n, seed=seed)
    return P, N


def test_tangent_plane_sdf_is_hoppes_formula_on_the_nearest_sample():
    P, N = sphere_samples()
    rng = np.random.default_rng(1)
    Q = rng.uniform(-1.5, 1.5, (3000, 3))
    nearest = cKDTree(P).query(Q)[1]
    unit = N / np.linalg.norm(N, axis=1, keepdims=True)
    expected = np.einsum("ij,ij->i", Q - P[nearest], unit[nearest])
    np.testing.assert_allclose(rc.tangent_plane_sdf(P, 3.0 * N, Q), expected, rtol=0, atol=1e-12)


def test_tangent_plane_sdf_approximates_the_sphere_distance_and_the_blend_is_convex():
    P, N = sphere_samples()
    rng = np.random.default_rng(2)
    directions = rng.standard_normal((2000, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    radii = rng.uniform(0.9, 1.1, len(directions))
    Q = directions * radii[:, None]
    truth = radii - 1.0
    one = rc.tangent_plane_sdf(P, N, Q)
    blended = rc.tangent_plane_sdf(P, N, Q, k=8)
    chord = cKDTree(P).query(directions)[0]   # to the nearest sample, from the query's direction
    np.testing.assert_allclose(truth - one, radii * chord ** 2 / 2, atol=1e-12)  # r (1 - cos θ): O(spacing²)
    noisy = P + 0.01 * rng.standard_normal((len(P), 1)) * N   # scan noise: blending planes averages it out
    errors = [np.abs(rc.tangent_plane_sdf(noisy, N, Q, k=k) - truth).mean() for k in (1, 8)]
    assert errors[1] < 0.5 * errors[0]   # measured: 0.0090 -> 0.0036
    idx = cKDTree(P).query(Q, k=8)[1]
    planes = np.einsum("qkj,qkj->qk", Q[:, None, :] - P[idx], N[idx])
    assert np.all(blended >= planes.min(axis=1) - 1e-12) and np.all(blended <= planes.max(axis=1) + 1e-12)


def test_winding_number_is_igls_to_3e_3_and_converges_with_accuracy():
    igl = pytest.importorskip("igl")
    V, F = datasets.torus(n_major=40, n_minor=20)
    rng = np.random.default_rng(3)
    Q = rng.uniform(-1.6, 1.6, (2000, 3))
    exact = igl.winding_number(V, F, Q)
    errors = [np.abs(rc.winding_number(V, F, Q, accuracy=a) - exact).max() for a in (2, 4, 8)]
    assert errors[1] < 3e-3 and errors[2] < errors[1] / 8 < errors[0] / 64  # about third order: 1.8e-2, 1.7e-3, 1e-4
    np.testing.assert_array_equal(rc.winding_number(V, F, Q), rc.winding_number(V, F, Q, accuracy=4))
    open_F = F[30:]                         # a hole: fractional values, still igl's
    np.testing.assert_allclose(rc.winding_number(V, open_F, Q), igl.winding_number(V, open_F, Q), atol=3e-3)


def signs_agree_with_igl(V, F, Q):
    igl = pytest.importorskip("igl")
    ours = rc.mesh_sdf(V, F, Q)
    S, I, C, _ = igl.signed_distance(Q, V, F.astype(np.int64), sign_type=igl.SIGNED_DISTANCE_TYPE_WINDING_NUMBER)
    # |distance|: igl's exact point-mesh distance (on the scanned bunny igl.signed_distance's own
    # distances differ from it by up to 0.5%, on the torus they agree to 1e-12)
    exact_distance = np.sqrt(igl.point_mesh_squared_distance(Q, V, F.astype(np.int64))[0])
    np.testing.assert_allclose(np.abs(ours.distance), exact_distance, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(ours.point - Q, axis=1), exact_distance, atol=1e-12)
    exact = igl.winding_number(V, F.astype(np.int64), Q)
    clear = np.abs(exact - 0.5) > 5e-3      # away from the sign's threshold (our winding is to 3e-3)
    np.testing.assert_array_equal(np.sign(ours.distance[clear]), np.sign(S[clear]))
    return clear.mean()


def test_mesh_sdf_agrees_with_igl_on_a_closed_mesh():
    V, F = datasets.torus(n_major=48, n_minor=24)
    Q = np.random.default_rng(4).uniform(-1.6, 1.6, (4000, 3))
    assert signs_agree_with_igl(V, F, Q) == 1.0
    igl = pytest.importorskip("igl")
    S = igl.signed_distance(Q, V, F.astype(np.int64), sign_type=igl.SIGNED_DISTANCE_TYPE_WINDING_NUMBER)[0]
    np.testing.assert_allclose(rc.mesh_sdf(V, F, Q).distance, S, rtol=0, atol=1e-11)  # values and signs


def test_mesh_sdf_agrees_with_igl_on_a_mesh_with_holes(data_dir):
    V, F = io.read_mesh(data_dir / "stanford-bunny.obj")
    assert topology.boundary_loops(F)
    lo, hi = V.min(axis=0), V.max(axis=0)
    Q = np.random.default_rng(5).uniform(lo - 0.1 * (hi - lo), hi + 0.1 * (hi - lo), (3000, 3))
    assert signs_agree_with_igl(V, F, Q) > 0.99
    inside = rc.mesh_sdf(V, F, (V.mean(axis=0) + 0.0 * V[:1]))  # the bunny's centroid: inside despite the holes
    assert inside.distance[0] < 0 and inside.winding[0] > 0.9


def test_sampled_mesh_sdf_contours_back_into_the_mesh():
    V, F = datasets.torus()
    grid = rc.sample_grid(np.array([V.min(axis=0) - 0.1, V.max(axis=0) + 0.1]), 48)
    values = rc.mesh_sdf(V, F, grid.points).distance.reshape(grid.shape)
    mesh = rc.marching_cubes(values, origin=grid.origin, spacing=grid.spacing)
    assert topology.is_manifold(mesh.F) and topology.euler_characteristic(mesh.F) == 0
    assert geometry.volume(mesh.V, mesh.F) == pytest.approx(geometry.volume(V, F), rel=0.01)
    assert geometry.hausdorff_distance(mesh.V, mesh.F, V, F) < grid.spacing[0]


def test_sample_grid_covers_the_box_with_equal_spacing():
    grid = rc.sample_grid([[0, 0, 0], [2, 1, 0.5]], 9)
    assert grid.shape == (9, 5, 3)
    np.testing.assert_allclose(grid.spacing, 0.25)
    np.testing.assert_array_equal(grid.origin, [0, 0, 0])
    P = grid.points.reshape(*grid.shape, 3)
    np.testing.assert_allclose(P[2, 3, 1], [0.5, 0.75, 0.25])
    np.testing.assert_allclose(P[-1, -1, -1], [2, 1, 0.5])
    uneven = rc.sample_grid([[0, 0, 0], [1, 0.3, 0.3]], 11)
    assert uneven.shape == (11, 4, 4)          # 0.3 / 0.1 = 3 steps (+1), robust to rounding


def test_bad_input_is_an_input_error():
    P, N = sphere_samples(100)
    bad = N.copy()
    bad[7] = 0
    with pytest.raises(meshsmith.InputError, match=r"N\[7\]"):
        rc.tangent_plane_sdf(P, bad, P)
    with pytest.raises(meshsmith.InputError, match="one normal per sample"):
        rc.tangent_plane_sdf(P, N[:50], P)
    with pytest.raises(meshsmith.InputError, match="k = 101"):
        rc.tangent_plane_sdf(P, N, P, k=101)
    Q = P.copy()
    Q[3, 1] = np.nan
    with pytest.raises(meshsmith.InputError, match="Q"):
        rc.tangent_plane_sdf(P, N, Q)
    V, F = datasets.icosphere(1)
    with pytest.raises(meshsmith.InputError, match="Q"):
        rc.mesh_sdf(V, F, Q)
    with pytest.raises(meshsmith.InputError):
        rc.mesh_sdf(V, F + 100, P)
    assert rc.mesh_sdf(V, F, np.zeros((0, 3))).distance.shape == (0,)
    with pytest.raises(meshsmith.InputError, match="bounds"):
        rc.sample_grid([[0, 0, 0], [1, 0, 1]], 10)
    with pytest.raises(meshsmith.InputError, match="resolution"):
        rc.sample_grid([[0, 0, 0], [1, 1, 1]], 1)
    with pytest.raises(meshsmith.InputError, match="2\\^26"):
        rc.sample_grid([[0, 0, 0], [1, 1, 1]], 1000)
