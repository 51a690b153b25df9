"""Coordinates near the ends of the float range (issue 14, part 1): scale-invariant algorithms give
the unscaled answer, scaled exactly, for inputs scaled by a power of two (2^±997 ≈ 1e±300,
2^±498 ≈ 1e±150), and within rounding for decimal factors (1e±300); quantities that cannot fit a
double say so with InputError; degenerate point sets and small input angles terminate.

Scale factors are powers of two where the comparison is exact: the normalization
(core/normalization.h) makes the computation bit-identical, so outputs of unit length^p must equal
the unscaled ones times 2^(p·k) exactly.
"""
import math
import multiprocessing
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import meshsmith
from meshsmith import datasets

POWERS = [-997, -498, 498, 997]  # 2^-997 ≈ 1.5e-300, 2^997 ≈ 1.3e300
DECIMAL = [1e-300, 1e-150, 1e150, 1e300]


def scaled(X, k):
    return np.ldexp(np.asarray(X, dtype=float), k)


def assert_scaled_exactly(result, reference, k, power):
    """result == reference · 2^(power·k), bit for bit."""
    np.testing.assert_array_equal(result, np.ldexp(reference, power * k))


def run_child(code: str, timeout: float):
    """Runs `code` in a fresh interpreter; returns (exit code, stdout) or fails on a timeout (a hang)."""
    try:
        done = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        pytest.fail(f"did not finish within {timeout} s (a hang)")
    return done.returncode, done.stdout + done.stderr


# --- points: kd-tree ---------------------------------------------------------------------------

@pytest.mark.parametrize("k", POWERS + [1020])
def test_knn_is_exactly_scale_covariant(k):
    P, _ = datasets.sphere_points(400, seed=2)
    indices, distances = meshsmith.points.knn(P, 8)
    scaled_indices, scaled_distances = meshsmith.points.knn(scaled(P, k), 8)
    assert scaled_indices.max() < len(P)
    np.testing.assert_array_equal(scaled_indices, indices)
    assert_scaled_exactly(scaled_distances, distances, k, 1)


@pytest.mark.parametrize("factor", [1e200, 1e300, 1e-300])
def test_knn_at_decimal_scales_returns_valid_neighbours(factor):
    P, _ = datasets.sphere_points(400, seed=2)
    indices, distances = meshsmith.points.knn(P, 8)
    scaled_indices, scaled_distances = meshsmith.points.knn(P * factor, 8)
    assert scaled_indices.min() >= 0 and scaled_indices.max() < len(P)
    assert np.all(np.isfinite(scaled_distances))
    np.testing.assert_allclose(scaled_distances / factor, distances, rtol=1e-12)
    if factor < 1:
        return  # a far query of tiny points: test_knn_query_far_outside_tiny_points
    # A query given explicitly, at 1e308, far from the points.
    Q = np.array([[1e308, 0.0, 0.0]])
    far_indices, far_distances = meshsmith.points.knn(P * factor, 3, Q)
    assert far_indices.max() < len(P) and np.all(np.isfinite(far_distances))
    np.testing.assert_allclose(far_distances[0], np.linalg.norm(Q[0] / 1e300 - P[far_indices[0]] * (factor / 1e300), axis=1) * 1e300,
                               rtol=1e-12)


def test_knn_query_far_outside_tiny_points():
    """A query 1e300 away from points of size 1e-300: the neighbours are those furthest along it."""
    P, _ = datasets.sphere_points(200, seed=4)
    Q = np.array([[1e300, 0.0, 0.0]])
    indices, distances = meshsmith.points.knn(P * 1e-300, 5, Q)
    assert set(indices[0]) == set(np.argsort(-P[:, 0])[:5])
    np.testing.assert_allclose(distances[0], 1e300, rtol=1e-12)


@pytest.mark.parametrize("kind", ["zero", "one", "ulps"])
def test_a_million_coincident_points_do_not_hang_the_kd_tree(kind):
    code = f"""
        import numpy as np, meshsmith
        n = 1_000_000
        if "{kind}" == "zero":
            P = np.zeros((n, 3))
        elif "{kind}" == "one":
            P = np.full((n, 3), 1e300)
        else:  # nearly coincident: within two units in the last place of 1
            P = 1 + np.random.default_rng(0).integers(-2, 3, (n, 3)) * np.spacing(1.0)
        indices, distances = meshsmith.points.knn(P, 8)
        assert indices.min() >= 0 and indices.max() < n
        assert not np.any(indices == np.arange(n)[:, None])
        assert np.all(distances <= 8 * np.spacing(1.0) * (1e300 if "{kind}" == "one" else 1))
        N = meshsmith.points.estimate_normals(P, 8)
        assert np.all(np.isfinite(N))
        print("ok")
    """
    code_returned, output = run_child(code, timeout=120)
    assert code_returned == 0 and "ok" in output, output


def test_radius_query_at_extreme_scales():
    P, _ = datasets.sphere_points(300, seed=5)
    tree = meshsmith.points.KdTree(P)
    offsets, indices, distances = tree.query_radius(P[:20], 0.3)
    for k in (-997, 997):
        big = meshsmith.points.KdTree(scaled(P, k))
        o, i, d = big.query_radius(scaled(P[:20], k), math.ldexp(0.3, k))
        np.testing.assert_array_equal(o, offsets)
        np.testing.assert_array_equal(i, indices)
        assert_scaled_exactly(d, distances, k, 1)
