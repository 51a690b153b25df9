"""Discrete curves (§1.1) against analytic truth: circles, ellipses, lines, helices; the observed
order of convergence of each curvature method; bad input and repeated points."""
import numpy as np
import pytest

import meshsmith
import meshsmith.curves as mc

METHODS = ("turning_angle", "osculating_circle", "second_difference")


def circle(n, radius=2.0, jitter=0.0, seed=0, clockwise=False):
    """n points on a circle, uniform in angle or jittered by up to jitter × the spacing."""
    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    if jitter:
        t = t + np.random.default_rng(seed).uniform(-jitter, jitter, n) * 2 * np.pi / n
    if clockwise:
        t = -t
    return radius * np.stack([np.cos(t), np.sin(t)], axis=1), t


def helix(n, a=2.0, b=0.5, turns=2.0):
    t = np.linspace(0.0, 2 * np.pi * turns, n)
    return np.stack([a * np.cos(t), a * np.sin(t), b * t], axis=1), t


def observed_orders(errors):
    """Orders between successive doublings of the number of samples."""
    errors = np.asarray(errors)
    return np.log2(errors[:-1] / errors[1:])


def fitted_order(errors, sizes=None):
    """Least-squares slope of log(error) against log(1/n) (robust to random jitter)."""
    sizes = np.asarray(sizes or SIZES[:len(errors)], dtype=float)
    return -np.polyfit(np.log(sizes), np.log(np.asarray(errors)), 1)[0]


SIZES = [32, 64, 128, 256, 512]


# --- curvature: circle, ellipse, line, helix ------------------------------------------------

@pytest.mark.parametrize("jitter", [0.0, 0.3])
def test_circle_curvature_converges_to_inverse_radius(jitter):
    # measured (max error, r = 2): turning angle order 2.0 (uniform and jittered);
    # osculating circle exact (1e-12); second difference exact uniform, order 1.8 jittered
    # (fitted over n = 32..512).
    errors = {method: [] for method in METHODS}
    for n in SIZES:
        P, _ = circle(n, jitter=jitter, seed=n)
        for method in METHODS:
            kappa = mc.curvature(P, closed=True, method=method)
            errors[method].append(np.abs(kappa - 0.5).max())
    assert fitted_order(errors["turning_angle"]) > 1.9
    assert max(errors["osculating_circle"]) < 1e-11  # every 3 points lie on the circle
    if jitter:
        assert fitted_order(errors["second_difference"]) > 1.7
    else:
        assert max(errors["second_difference"]) < 1e-11
    assert errors["turning_angle"][-1] < 1e-5


def test_ellipse_curvature_at_the_vertices():
    a, b = 3.0, 1.0
    errors = {method: [] for method in METHODS}
    for n in SIZES:  # multiples of 4: the vertices t = 0, π/2 are samples
        t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        P = np.stack([a * np.cos(t), b * np.sin(t)], axis=1)
        for method in METHODS:
            kappa = mc.curvature(P, closed=True, method=method)
            errors[method].append(max(abs(kappa[0] - a / b**2), abs(kappa[n // 4] - b / a**2)))
    for method in METHODS:  # measured: order 2.0 for all three
        assert np.all(observed_orders(errors[method])[1:] > 1.9), (method, errors[method])
        assert errors[method][-1] < 1e-3


def test_ellipse_curvature_everywhere_is_second_order():
    a, b = 3.0, 1.0
    errors = {method: [] for method in METHODS}
    for n in SIZES:
        t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        P = np.stack([a * np.cos(t), b * np.sin(t)], axis=1)
        truth = a * b / (a**2 * np.sin(t) ** 2 + b**2 * np.cos(t) ** 2) ** 1.5
        for method in METHODS:
            errors[method].append(np.abs(mc.curvature(P, closed=True, method=method) - truth).max())
    for method in METHODS:
        assert np.all(observed_orders(errors[method])[1:] > 1.9), (method, errors[method])


def test_irregular_samples_converge_at_first_order():
    # Three-point stencils on irregularly spaced samples of a generic curve (an ellipse, spacing
    # jittered by +-30%) are first order: the error term (h+ - h-) times the third derivative
    # does not cancel. Measured fitted orders over n = 64..2048: 0.95, 0.96, 0.96.
    a, b = 3.0, 1.0
    sizes = [64, 128, 256, 512, 1024, 2048]
    errors = {method: [] for method in METHODS}
    for n in sizes:
        t = np.linspace(0, 2 * np.pi, n, endpoint=False)
        t += np.random.default_rng(n).uniform(-0.3, 0.3, n) * 2 * np.pi / n
        P = np.stack([a * np.cos(t), b * np.sin(t)], axis=1)
        truth = a * b / (a**2 * np.sin(t) ** 2 + b**2 * np.cos(t) ** 2) ** 1.5
        for method in METHODS:
            errors[method].append(np.abs(mc.curvature(P, closed=True, method=method) - truth).max())
    for method in METHODS:
        assert fitted_order(errors[method], sizes) > 0.8, (method, errors[method])
        assert errors[method][-1] < 0.02


@pytest.mark.parametrize("dimension", [2, 3])
def test_straight_line_has_zero_curvature(dimension):
    s = np.sort(np.random.default_rng(1).random(40))  # non-uniform spacing
    direction = np.array([1.0, -2.0, 0.5])[:dimension]
    P = np.outer(s, direction) + np.array([0.3, 0.1, -1.0])[:dimension]
    for method in METHODS:
        np.testing.assert_allclose(mc.curvature(P, method=method), 0.0, atol=1e-9)
    T = mc.tangents(P)
    np.testing.assert_allclose(T, np.tile(direction / np.linalg.norm(direction), (40, 1)), atol=1e-12)
    N = mc.normals(P)  # 3D: documented fallback, a fixed unit vector orthogonal to the line
    np.testing.assert_allclose(np.linalg.norm(N, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose((N * T).sum(axis=1), 0.0, atol=1e-12)


def test_helix_curvature_tangents_and_frenet_normals():
    a, b = 2.0, 0.5
    truth = a / (a**2 + b**2)
    errors = {method: [] for method in METHODS}
    for n in [100, 200, 400, 800]:
        P, t = helix(n, a, b)
        for method in METHODS:
            errors[method].append(np.abs(mc.curvature(P, method=method)[1:-1] - truth).max())
    for method in METHODS:  # measured: order 2.0 for all three
        assert np.all(observed_orders(errors[method]) > 1.9), (method, errors[method])
        assert errors[method][-1] < 1e-4
    P, t = helix(800, a, b)
    T = mc.tangents(P)
    exact_T = np.stack([-a * np.sin(t), a * np.cos(t), np.full_like(t, b)], axis=1) / np.hypot(a, b)
    assert np.abs(T[1:-1] - exact_T[1:-1]).max() < 1e-4
    N = mc.normals(P)
    exact_N = np.stack([-np.cos(t), -np.sin(t), np.zeros_like(t)], axis=1)  # towards the axis
    assert np.abs(N[1:-1] - exact_N[1:-1]).max() < 1e-3
    np.testing.assert_allclose((N * T).sum(axis=1), 0.0, atol=1e-12)


def test_planar_normals_tangents_and_signed_curvature():
    P, t = circle(200, radius=2.0)
    T = mc.tangents(P, closed=True)
    np.testing.assert_allclose(T, np.stack([-np.sin(t), np.cos(t)], axis=1), atol=1e-12)
    N = mc.normals(P, closed=True)  # counter-clockwise circle: inward
    np.testing.assert_allclose(N, -P / 2.0, atol=1e-12)
    assert np.all(mc.curvature(P, closed=True, signed=True) > 0)
    Q, _ = circle(200, radius=2.0, clockwise=True)
    np.testing.assert_allclose(mc.curvature(Q, closed=True, signed=True), -0.5, atol=1e-4)


def test_nonuniform_tangents_are_second_order():
    # circle: the chord-length quadratic's tangent is the circle's tangent, exactly
    P, t = circle(100, jitter=0.3, seed=1)
    np.testing.assert_allclose(mc.tangents(P, closed=True),
                               np.stack([-np.sin(t), np.cos(t)], axis=1), atol=1e-13)
    # ellipse, jittered samples: measured fitted order 1.9
    a, b = 3.0, 1.0
    errors = []
    for n in SIZES:
        t = np.linspace(0, 2 * np.pi, n, endpoint=False)
        t += np.random.default_rng(n).uniform(-0.3, 0.3, n) * 2 * np.pi / n
        P = np.stack([a * np.cos(t), b * np.sin(t)], axis=1)
        exact = np.stack([-a * np.sin(t), b * np.cos(t)], axis=1)
        exact /= np.linalg.norm(exact, axis=1)[:, None]
        errors.append(np.abs(mc.tangents(P, closed=True) - exact).max())
    assert fitted_order(errors) > 1.8


# --- arc length -----------------------------------------------------------------------------

def test_arc_length_of_a_circle_converges_to_its_circumference():
    errors = []
    for n in SIZES:
        P, _ = circle(n, radius=2.0)
        s = mc.arc_length(P, closed=True)
        assert s.shape == (n + 1,) and s[0] == 0.0 and np.all(np.diff(s) > 0)
        errors.append(abs(s[-1] - 4 * np.pi))
    orders = observed_orders(errors)  # measured: 2.00
    assert np.all(np.abs(orders - 2.0) < 0.05)
    # open polyline: exact cumulative lengths
    np.testing.assert_allclose(mc.arc_length([[0, 0], [3, 4], [3, 5]]), [0.0, 5.0, 6.0])


def test_arc_length_parametrization():
    # uneven samples of a straight segment → equal steps exactly
    s = np.sort(np.concatenate([[0.0, 1.0], np.random.default_rng(2).random(30)]))
    P = np.outer(s, [2.0, 1.0, -1.0])
    R = mc.arc_length_parametrization(P, 11)
    np.testing.assert_allclose(R, np.outer(np.linspace(0, 1, 11), [2.0, 1.0, -1.0]), atol=1e-12)
    # closed: a finely sampled, unevenly spaced circle → n points at equal arc-length steps
    C, _ = circle(4000, jitter=0.45, seed=3)
    R = mc.arc_length_parametrization(C, 100, closed=True)
    assert R.shape == (100, 2)
    np.testing.assert_allclose(R[0], C[0])
    steps = np.linalg.norm(np.roll(R, -1, axis=0) - R, axis=1)
    assert steps.std() / steps.mean() < 1e-4
    np.testing.assert_allclose(np.linalg.norm(R, axis=1), 2.0, atol=1e-5)
    # default n keeps the number of points
    assert mc.arc_length_parametrization(C, closed=True).shape == C.shape


# --- repeated points and bad input ------------------------------------------------------------

def test_repeated_consecutive_points_are_skipped():
    P, _ = helix(60)
    repeated = np.insert(P, [5, 5, 20, 59], P[[4, 4, 19, 58]], axis=0)  # copies next to originals
    stands_for = np.insert(np.arange(60), [5, 5, 20, 59], [4, 4, 19, 58])
    for method in METHODS:
        np.testing.assert_allclose(mc.curvature(repeated, method=method),
                                   mc.curvature(P, method=method)[stands_for])
    np.testing.assert_allclose(mc.tangents(repeated), mc.tangents(P)[stands_for])
    np.testing.assert_allclose(mc.normals(repeated), mc.normals(P)[stands_for])
    assert mc.arc_length(repeated)[-1] == pytest.approx(mc.arc_length(P)[-1])
    # a closed curve whose last point repeats the first
    C, _ = circle(50)
    closed_twice = np.vstack([C, C[:1]])
    np.testing.assert_allclose(mc.curvature(closed_twice, closed=True)[:-1],
                               mc.curvature(C, closed=True))
    assert np.all(np.isfinite(mc.curvature(closed_twice, closed=True)))


def test_doubling_back_gives_finite_values():
    P = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.0], [0.0, 1.0]])
    for method in METHODS:
        assert np.all(np.isfinite(mc.curvature(P, method=method)))
    assert np.all(np.isfinite(mc.tangents(P)))


@pytest.mark.parametrize("call", [
    lambda: mc.arc_length([[0.0, 0.0]]),
    lambda: mc.tangents([[0.0, 0.0], [0.0, 0.0]]),                       # one distinct point
    lambda: mc.curvature([[0.0, 0.0], [1.0, 0.0]]),                      # fewer than 3
    lambda: mc.normals([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
    lambda: mc.tangents([[0.0, 0.0], [1.0, 0.0]], closed=True),
    lambda: mc.curvature([[0.0, 0.0], [1.0, np.nan], [2.0, 0.0]]),
    lambda: mc.arc_length(np.zeros((5, 4))),
    lambda: mc.arc_length(np.zeros(5)),
    lambda: mc.arc_length([["a", "b"], ["c", "d"]]),
    lambda: mc.arc_length(np.ones((3, 2), dtype=bool)),
    lambda: mc.curvature(np.random.rand(5, 2), method="menger"),
    lambda: mc.curvature(np.random.rand(5, 3), signed=True),
    lambda: mc.arc_length_parametrization(np.random.rand(5, 2), n=1),
    lambda: mc.arc_length_parametrization(np.random.rand(5, 2), n=2, closed=True),
    lambda: mc.arc_length_parametrization(np.random.rand(5, 2), n=7.5),
])
def test_bad_input(call):
    with pytest.raises(meshsmith.InputError):
        call()


def test_input_is_not_modified():
    P, _ = helix(30)
    before = P.copy()
    for function in (mc.tangents, mc.normals, mc.curvature, mc.arc_length,
                     mc.arc_length_parametrization):
        function(P)
    np.testing.assert_array_equal(P, before)


def test_rigid_motion_and_scale_invariance():
    P, _ = helix(200)
    rotation, _ = np.linalg.qr(np.random.default_rng(11).normal(size=(3, 3)))
    moved = 2.5 * P @ rotation.T + [3.0, -1.0, 7.0]
    for method in METHODS:
        np.testing.assert_allclose(mc.curvature(moved, method=method),
                                   mc.curvature(P, method=method) / 2.5, rtol=1e-9)
    np.testing.assert_allclose(mc.tangents(moved), mc.tangents(P) @ rotation.T, atol=1e-9)
    np.testing.assert_allclose(mc.normals(moved), mc.normals(P) @ rotation.T, atol=1e-9)
    np.testing.assert_allclose(mc.arc_length(moved), 2.5 * mc.arc_length(P), rtol=1e-12)
