"""meshsmith.smoothing.laplacian and taubin (§3.0.1–3.0.2, issue 17 parts 1–2): low-pass behaviour
on noisy meshes (distance to the clean surface, volume), trimesh agreement, the transfer function on
eigenvectors, implicit stability, normal and tangential directions, fixed vertices, and the
epsilon-ball and error-slab bounds at every step."""
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
import trimesh

import meshsmith
from meshsmith import datasets, geometry, io, smoothing, topology

WEIGHTS = smoothing.WEIGHTS


def noisy_sphere(subdivisions=4, sigma=0.25, seed=0):
    V, F = datasets.icosphere(subdivisions)
    return V, datasets.noisy(V, F, sigma=sigma, seed=seed)[0], F


def distance_to(V_clean, F, W) -> float:
    """Mean distance of the vertices of W to the clean surface."""
    return float(geometry.SurfaceDistance(V_clean, F).distances(W).mean())


def tangential_part(D, N):
    return D - (D * N).sum(axis=1)[:, None] * N


# ---- low-pass behaviour ------------------------------------------------------------------------

@pytest.mark.parametrize("weights", WEIGHTS)
def test_noise_falls_and_taubin_keeps_the_volume_that_laplacian_loses_on_a_sphere(weights):
    V, Vn, F = noisy_sphere()
    clean_volume = geometry.volume(V, F)
    before = distance_to(V, F, Vn)
    lap = smoothing.laplacian(Vn, F, weights=weights, iterations=10)
    tau = smoothing.taubin(Vn, F, weights=weights, iterations=10)
    # On the unit sphere distance to the clean surface is | |p| - 1 |.
    lap_distance, tau_distance = (np.abs(np.linalg.norm(W, axis=1) - 1).mean() for W in (lap, tau))
    assert tau_distance < 0.5 * before
    assert tau_distance < 0.5 * lap_distance        # Laplacian's shrinking costs more than the noise
    lap_loss = abs(geometry.volume(lap, F) / clean_volume - 1)
    tau_loss = abs(geometry.volume(tau, F) / clean_volume - 1)
    assert tau_loss < 0.2 * lap_loss, (tau_loss, lap_loss)


@pytest.mark.parametrize("name", ["bunny.off", "spot.obj", "fandisk.obj", "fertility.off"])
def test_noise_falls_and_taubin_keeps_the_volume_on_shared_meshes(data_dir: Path, name):
    V, F = io.read_mesh(data_dir / name)
    Vn, _ = datasets.noisy(V, F, sigma=0.2, seed=1)
    clean_volume = geometry.volume(V, F)
    before = distance_to(V, F, Vn)
    lap = smoothing.laplacian(Vn, F, iterations=10)
    tau = smoothing.taubin(Vn, F, iterations=10)
    lap_distance, tau_distance = distance_to(V, F, lap), distance_to(V, F, tau)
    lap_loss = 1 - geometry.volume(lap, F) / clean_volume
    tau_loss = 1 - geometry.volume(tau, F) / clean_volume
    print(f"{name}: mean distance to the clean surface {before:.3g} -> Laplacian {lap_distance:.3g}, "
          f"Taubin {tau_distance:.3g}; volume lost: Laplacian {100 * lap_loss:.2f}%, Taubin {100 * tau_loss:.3f}%")
    assert tau_distance < 0.8 * before
    assert abs(tau_loss) < 0.2 * abs(lap_loss)


def test_taubin_scales_each_eigenvector_by_its_transfer_function():
    # Eigenvectors of U = D^-1 L: -L x = k D x (generalized, symmetric); x = its own mode.
    V, F = datasets.icosphere(1)
    L = geometry.uniform_laplacian(F, len(V)).toarray()
    D = np.diag(-np.diag(L))
    k, X = scipy.linalg.eigh(-L, D)
    for index in (1, 10, 30, len(V) - 1):
        x = X[:, index] / np.abs(X[:, index]).max()
        P = np.column_stack([x, 2 * x, -x])
        for lam, mu, iterations in ((0.5, -0.53, 7), (0.6, -0.6, 3)):
            expected = smoothing.transfer_function(k[index], lam=lam, mu=mu, iterations=iterations) * P
            np.testing.assert_allclose(smoothing.taubin(P, F, lam=lam, mu=mu, iterations=iterations), expected,
                                       atol=1e-12)
        expected = smoothing.transfer_function(k[index], lam=0.3, mu=None, iterations=5) * P
        np.testing.assert_allclose(smoothing.laplacian(P, F, lam=0.3, iterations=5), expected, atol=1e-12)
        implicit = (1 + 0.3 * k[index]) ** -5 * P
        np.testing.assert_allclose(smoothing.laplacian(P, F, lam=0.3, iterations=5, implicit=True), implicit,
                                   atol=1e-10)


def test_transfer_function_has_its_pass_band_at_one_over_lambda_plus_one_over_mu():
    lam, mu = 0.5, -0.53
    k_pb = 1 / lam + 1 / mu
    assert smoothing.transfer_function(0.0) == 1.0
    assert smoothing.transfer_function(k_pb, lam=lam, mu=mu) == pytest.approx(1.0, abs=1e-15)
    # Between 0 and k_PB it exceeds 1 slightly, above it it falls.
    assert smoothing.transfer_function(k_pb / 2, lam=lam, mu=mu) > 1.0
    assert smoothing.transfer_function(1.5, lam=lam, mu=mu, iterations=10) < 1e-3


# ---- agreement with trimesh --------------------------------------------------------------------

def test_uniform_explicit_and_implicit_laplacian_and_taubin_equal_trimesh():
    V, F = datasets.noisy(*datasets.icosphere(3), sigma=0.3, seed=3)
    mesh = lambda: trimesh.Trimesh(V.copy(), F.copy(), process=False)  # noqa: E731
    ours = smoothing.laplacian(V, F, lam=0.5, iterations=10)
    theirs = trimesh.smoothing.filter_laplacian(mesh(), lamb=0.5, iterations=10, volume_constraint=False).vertices
    np.testing.assert_allclose(ours, theirs, atol=1e-13)
    ours = smoothing.laplacian(V, F, lam=2.0, iterations=3, implicit=True)
    theirs = trimesh.smoothing.filter_laplacian(mesh(), lamb=2.0, iterations=3, implicit_time_integration=True,
                                                volume_constraint=False).vertices
    np.testing.assert_allclose(ours, theirs, atol=1e-12)
    # trimesh counts each half step as an iteration, and takes nu = -mu.
    ours = smoothing.taubin(V, F, lam=0.5, mu=-0.53, iterations=10)
    theirs = trimesh.smoothing.filter_taubin(mesh(), lamb=0.5, nu=0.53, iterations=20).vertices
    np.testing.assert_allclose(ours, theirs, atol=1e-13)


# ---- stability, directions, fixed vertices ---------------------------------------------------

@pytest.mark.parametrize("weights", WEIGHTS)
def test_implicit_steps_stay_stable_where_explicit_ones_diverge(weights):
    V, Vn, F = noisy_sphere(3)
    explicit = smoothing.laplacian(Vn, F, weights=weights, lam=5.0, iterations=20)
    implicit = smoothing.laplacian(Vn, F, weights=weights, lam=5.0, iterations=20, implicit=True)
    assert np.abs(explicit).max() > 1e6
    # Each implicit step is a convex combination for weights >= 0: inside the input's bounding box.
    assert np.all(implicit.max(axis=0) <= Vn.max(axis=0) + 1e-12)
    assert np.all(implicit.min(axis=0) >= Vn.min(axis=0) - 1e-12)
    assert np.isfinite(implicit).all()


@pytest.mark.parametrize("weights", WEIGHTS)
@pytest.mark.parametrize("method", ["laplacian", "laplacian implicit", "taubin"])
def test_normal_direction_moves_each_vertex_along_its_current_normal_only(weights, method):
    _, Vn, F = noisy_sphere(3)
    run = {"laplacian": lambda **o: smoothing.laplacian(Vn, F, weights=weights, **o),
           "laplacian implicit": lambda **o: smoothing.laplacian(Vn, F, weights=weights, implicit=True, **o),
           "taubin": lambda **o: smoothing.taubin(Vn, F, weights=weights, **o)}[method]
    if method == "taubin":
        # One λ step: the first half of a Taubin iteration moves like one Laplacian step.
        W = smoothing.taubin(Vn, F, weights=weights, iterations=1, direction="normal")
        full = smoothing.taubin(Vn, F, weights=weights, iterations=1)
        assert np.abs(W - Vn).max() > 1e-4 and not np.allclose(W, full)
        return
    W = run(iterations=1, direction="normal")
    N = geometry.vertex_normals(Vn, F)
    D = W - Vn
    assert np.abs(D).max() > 1e-3
    assert np.abs(tangential_part(D, N)).max() < 1e-15 * 8
    # Tangential: the other part, orthogonal to the normal.
    T = run(iterations=1, direction="tangential") - Vn
    assert np.abs(T).max() > 1e-3
    assert np.abs((T * N).sum(axis=1)).max() < 1e-15 * 8


def test_tangential_smoothing_keeps_a_planar_mesh_in_its_plane():
    V, F = datasets.grid(20, 20)
    rng = np.random.default_rng(5)
    V = V + np.column_stack([rng.uniform(-0.015, 0.015, (len(V), 2)), np.zeros(len(V))])
    rotation, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    P = V @ rotation.T + np.array([0.3, -2.0, 1.0])
    normal = rotation[:, 2]
    boundary = np.unique(np.concatenate(topology.boundary_loops(F)))
    for weights in WEIGHTS:
        W = smoothing.laplacian(P, F, weights=weights, iterations=20, direction="tangential", fixed=boundary)
        if weights == "uniform":
            assert np.abs(W - P).max() > 1e-3                  # the vertices did move
        else:
            assert np.abs(W - P).max() < 1e-13                 # linear precision: a plane is left alone
        height = (W - P[0]) @ normal
        assert np.abs(height).max() < 1e-14 * 8, weights       # ... within the plane, to round-off
        np.testing.assert_array_equal(W[boundary], P[boundary])


def test_fixed_vertices_do_not_move_at_all_and_unreferenced_ones_neither():
    V, Vn, F = noisy_sphere(2)
    V_extra = np.vstack([Vn, [[5.0, 5.0, 5.0]]])
    fixed = np.arange(0, len(Vn), 7)
    for run in (lambda: smoothing.laplacian(V_extra, F, fixed=fixed, iterations=5),
                lambda: smoothing.laplacian(V_extra, F, fixed=fixed, iterations=5, implicit=True, weights="cotan"),
                lambda: smoothing.laplacian(V_extra, F, fixed=fixed, iterations=5, implicit=True, weights="mean_value"),
                lambda: smoothing.taubin(V_extra, F, fixed=fixed, iterations=5, weights="cotan_delaunay")):
        W = run()
        np.testing.assert_array_equal(W[fixed], V_extra[fixed])
        np.testing.assert_array_equal(W[-1], V_extra[-1])
        assert np.abs(W - V_extra).max() > 1e-3


def test_results_scale_exactly_with_the_input():
    _, Vn, F = noisy_sphere(2)
    for run in (lambda X: smoothing.laplacian(X, F, weights="cotan", iterations=3),
                lambda X: smoothing.laplacian(X, F, iterations=3, implicit=True, epsilon_ball=np.ldexp(0.01, k)),
                lambda X: smoothing.taubin(X, F, iterations=3, error_slab=np.ldexp(0.005, k))):
        k = 0
        reference = run(Vn)
        for k in (-997, 997):
            np.testing.assert_array_equal(run(np.ldexp(Vn, k)), np.ldexp(reference, k))


# ---- error control ---------------------------------------------------------------------------

CALLS = {
    "laplacian": lambda V, F, w, **o: smoothing.laplacian(V, F, weights=w, iterations=30, **o),
    "laplacian lam=1": lambda V, F, w, **o: smoothing.laplacian(V, F, weights=w, lam=1.0, iterations=30, **o),
    "laplacian implicit": lambda V, F, w, **o: smoothing.laplacian(V, F, weights=w, lam=3.0, iterations=10,
                                                                  implicit=True, **o),
    "laplacian normal": lambda V, F, w, **o: smoothing.laplacian(V, F, weights=w, iterations=30, direction="normal", **o),
    "laplacian tangential": lambda V, F, w, **o: smoothing.laplacian(V, F, weights=w, iterations=30,
                                                                    direction="tangential", **o),
    "taubin": lambda V, F, w, **o: smoothing.taubin(V, F, weights=w, iterations=30, **o),
}


@pytest.mark.parametrize("weights", WEIGHTS)
@pytest.mark.parametrize("method", sorted(CALLS))
def test_epsilon_ball_is_never_violated(method, weights):
    V, Vn, F = noisy_sphere(3, sigma=0.4, seed=7)
    epsilon = 0.3 * float(np.linalg.norm(Vn[F[:, 0]] - Vn[F[:, 1]], axis=1).mean())
    W = CALLS[method](Vn, F, weights, epsilon_ball=epsilon)
    moved = np.linalg.norm(W - Vn, axis=1)
    assert moved.max() <= epsilon                       # exactly, as the floats stand
    assert moved.max() > 0.5 * epsilon                  # and the bound was active
    assert np.isfinite(W).all()


@pytest.mark.parametrize("weights", WEIGHTS)
@pytest.mark.parametrize("method", sorted(CALLS))
def test_error_slab_is_never_violated_and_leaves_tangential_motion_free(method, weights):
    V, Vn, F = noisy_sphere(3, sigma=0.4, seed=8)
    epsilon = 0.1 * float(np.linalg.norm(Vn[F[:, 0]] - Vn[F[:, 1]], axis=1).mean())
    N0 = geometry.vertex_normals(Vn, F)
    W = CALLS[method](Vn, F, weights, error_slab=epsilon)
    along = np.abs(((W - Vn) * N0).sum(axis=1))
    assert along.max() <= epsilon
    if method != "laplacian normal":
        assert np.linalg.norm(tangential_part(W - Vn, N0), axis=1).max() > epsilon


def test_the_bound_holds_after_every_step_not_only_at_the_end():
    # Projected after every step, the result is not the unconstrained result projected once.
    _, Vn, F = noisy_sphere(2, sigma=0.5)
    epsilon = 0.01
    W = smoothing.laplacian(Vn, F, iterations=4, epsilon_ball=epsilon)
    free = smoothing.laplacian(Vn, F, iterations=4)
    D = free - Vn
    length = np.linalg.norm(D, axis=1)
    once = Vn + D * np.minimum(1, epsilon / np.maximum(length, 1e-300))[:, None]
    assert np.linalg.norm(W - Vn, axis=1).max() <= epsilon
    assert np.abs(W - once).max() > 1e-4


# ---- bad input ---------------------------------------------------------------------------------

@pytest.mark.parametrize("call, message", [
    (lambda V, F: smoothing.laplacian(V, F, lam=0.0), "lam = 0: expected a finite number > 0"),
    (lambda V, F: smoothing.laplacian(V, F, lam=float("nan")), "lam = nan"),
    (lambda V, F: smoothing.taubin(V, F, mu=0.1), "mu = 0.1: expected a finite number < 0"),
    (lambda V, F: smoothing.laplacian(V, F, iterations=-1), "iterations = -1"),
    (lambda V, F: smoothing.laplacian(V, F, weights="cot"), "weights = 'cot': expected 'uniform'"),
    (lambda V, F: smoothing.laplacian(V, F, direction="up"), "direction = 'up'"),
    (lambda V, F: smoothing.laplacian(V, F, fixed=[0, 99999]), r"fixed\[1\] = 99999 is outside \[0, 162\)"),
    (lambda V, F: smoothing.laplacian(V, F, fixed=[0.5]), "fixed has dtype float64"),
    (lambda V, F: smoothing.laplacian(V, F, epsilon_ball=-1.0), "epsilon_ball = -1: expected a finite distance > 0"),
    (lambda V, F: smoothing.taubin(V, F, error_slab=0.0), "error_slab = 0"),
    (lambda V, F: smoothing.laplacian(V, F, epsilon_ball=0.1, error_slab=0.1), "at most one of"),
])
def test_bad_options_are_rejected_and_nothing_is_modified(call, message):
    V, F = datasets.icosphere(2)
    V0, F0 = V.copy(), F.copy()
    with pytest.raises(meshsmith.InputError, match=message):
        call(V, F)
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(F, F0)


def test_non_manifold_input_for_intrinsic_weights_is_rejected():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], dtype=float)
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    with pytest.raises(meshsmith.InputError, match="edge-manifold"):
        smoothing.taubin(V, F, weights="cotan_delaunay")


def test_progress_is_reported_and_cancel_stops():
    _, Vn, F = noisy_sphere(2)
    seen = []
    smoothing.laplacian(Vn, F, iterations=5, implicit=True, progress=lambda f, s: seen.append((f, s)) or True)
    assert seen[-1][0] == 1.0 and {"factorizing", "smoothing"} <= {s for _, s in seen}
    with pytest.raises(meshsmith.Cancelled):
        smoothing.taubin(Vn, F, iterations=5, progress=lambda f, s: False)


def test_zero_iterations_return_a_copy_of_the_input():
    V, F = datasets.icosphere(1)
    W = smoothing.taubin(V, F, iterations=0)
    np.testing.assert_array_equal(W, V)
    assert W is not V and not np.shares_memory(W, V)
