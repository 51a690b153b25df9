"""meshsmith.smoothing.smooth_curve (§3.0.1 "Smoothing (2D)", issue 17 part 1): the Fourier modes of a
closed polygon scaled by the transfer function, open ends held, 2D and 3D, error bounds, bad input."""
import numpy as np
import pytest

import meshsmith
from meshsmith import curves, smoothing


def closed_polygon(n=64, modes=((2, 0.3), (5, 0.05), (17, 0.02)), seed=0):
    """A circle with a few added Fourier modes of the radius (in both coordinates)."""
    t = 2 * np.pi * np.arange(n) / n
    radius = 1.0 + sum(a * np.cos(j * t) for j, a in modes)
    return np.column_stack([radius * np.cos(t), radius * np.sin(t)])


@pytest.mark.parametrize("lam, mu, iterations", [(0.5, None, 7), (0.5, -0.53, 5), (0.33, -0.34, 12)])
def test_each_fourier_mode_is_scaled_by_the_transfer_function(lam, mu, iterations):
    P = closed_polygon()
    n = len(P)
    W = smoothing.smooth_curve(P, lam=lam, mu=mu, iterations=iterations, closed=True)
    # U is circulant: mode j has eigenvalue -(1 - cos(2 pi j / n)) of U.
    k = 1 - np.cos(2 * np.pi * np.fft.fftfreq(n) )
    expected = np.fft.ifft(np.fft.fft(P, axis=0) * smoothing.transfer_function(k, lam=lam, mu=mu,
                                                                                iterations=iterations)[:, None],
                           axis=0).real
    np.testing.assert_allclose(W, expected, atol=1e-13)


def test_taubin_keeps_the_low_modes_that_laplacian_shrinks():
    P = closed_polygon()
    area = lambda X: 0.5 * abs(np.sum(X[:, 0] * np.roll(X[:, 1], -1) - np.roll(X[:, 0], -1) * X[:, 1]))  # noqa: E731
    lap = smoothing.smooth_curve(P, iterations=50, closed=True)
    tau = smoothing.smooth_curve(P, mu=-0.53, iterations=50, closed=True)
    assert abs(area(tau) / area(P) - 1) < 0.02 < abs(area(lap) / area(P) - 1)


def test_open_curve_keeps_its_ends_and_a_straight_line_stays_straight():
    rng = np.random.default_rng(1)
    s = np.linspace(0, 1, 40)
    line = np.column_stack([s, 2 * s, -s]) + 0.01 * rng.standard_normal((40, 3))
    W = smoothing.smooth_curve(line, iterations=3000)
    np.testing.assert_array_equal(W[[0, -1]], line[[0, -1]])
    # The slowest mode decays as (1 - (1 - cos(pi / 39)) / 2)^3000 = 0.008: nearly the straight segment.
    direction = (line[-1] - line[0]) / np.linalg.norm(line[-1] - line[0])
    off_line = (W - line[0]) - ((W - line[0]) @ direction)[:, None] * direction
    assert np.linalg.norm(off_line, axis=1).max() < 0.1 * np.linalg.norm(
        ((line - line[0]) - ((line - line[0]) @ direction)[:, None] * direction), axis=1).max()
    fixed = smoothing.smooth_curve(line, iterations=5, fixed=[10, 20])
    np.testing.assert_array_equal(fixed[[0, 10, 20, 39]], line[[0, 10, 20, 39]])


def test_a_planar_curve_in_3d_stays_in_its_plane_and_2d_stays_2d():
    P = closed_polygon()
    assert smoothing.smooth_curve(P, closed=True).shape == P.shape
    P3 = np.column_stack([P, np.zeros(len(P))])
    np.testing.assert_array_equal(smoothing.smooth_curve(P3, closed=True)[:, 2], 0.0)
    np.testing.assert_allclose(smoothing.smooth_curve(P3, closed=True)[:, :2], smoothing.smooth_curve(P, closed=True),
                               atol=0)


@pytest.mark.parametrize("mu", [None, -0.53])
@pytest.mark.parametrize("dimension", [2, 3])
def test_error_bounds_are_never_violated(mu, dimension):
    rng = np.random.default_rng(2)
    P = closed_polygon(modes=((3, 0.2), (20, 0.05)))
    if dimension == 3:
        P = np.column_stack([P, 0.05 * rng.standard_normal(len(P))])
    epsilon = 0.01
    W = smoothing.smooth_curve(P, mu=mu, iterations=40, closed=True, epsilon_ball=epsilon)
    moved = np.linalg.norm(W - P, axis=1)
    assert moved.max() <= epsilon and moved.max() > 0.9 * epsilon
    T = curves.tangents(P, closed=True)
    W = smoothing.smooth_curve(P, mu=mu, iterations=40, closed=True, error_slab=epsilon)
    D = W - P
    across = np.linalg.norm(D - (D * T).sum(axis=1)[:, None] * T, axis=1)
    assert across.max() <= epsilon
    assert np.abs((D * T).sum(axis=1)).max() > epsilon        # free along the tangent


@pytest.mark.parametrize("call, message", [
    (lambda P: smoothing.smooth_curve(P[:2], closed=True), "P has 2 points: an closed curve needs at least 3"),
    (lambda P: smoothing.smooth_curve(P[:1]), "at least 2"),
    (lambda P: smoothing.smooth_curve(P, lam=-0.5), "lam = -0.5"),
    (lambda P: smoothing.smooth_curve(P, mu=0.5), "mu = 0.5"),
    (lambda P: smoothing.smooth_curve(P, iterations=-2), "iterations = -2"),
    (lambda P: smoothing.smooth_curve(P, fixed=[64]), r"fixed\[0\] = 64 is outside \[0, 64\)"),
    (lambda P: smoothing.smooth_curve(np.column_stack([P, P]), closed=True), r"P has shape \(64, 4\)"),
    (lambda P: smoothing.smooth_curve(np.where(np.arange(64)[:, None] == 3, np.nan, P)), r"P\[3"),
    (lambda P: smoothing.smooth_curve(P, epsilon_ball=1.0, error_slab=1.0), "at most one of"),
])
def test_bad_input_is_rejected(call, message):
    P = closed_polygon()
    P0 = P.copy()
    with pytest.raises(meshsmith.InputError, match=message):
        call(P)
    np.testing.assert_array_equal(P, P0)
