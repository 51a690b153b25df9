"""Laplacian and Taubin smoothing of triangle meshes (§3.0.1–3.0.2); binding cpp/python/smoothing.cpp
(C++ cpp/src/smoothing/laplacian_smoothing.cpp).
"""
from __future__ import annotations

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import smoothing as _core
from .._typing import ArrayLike, FloatArray, ProgressCallback

__all__ = ["WEIGHTS", "DIRECTIONS", "laplacian", "taubin", "transfer_function"]

#: The umbrella operator's edge weights (§3.0.2).
WEIGHTS = ("uniform", "cotan", "cotan_delaunay", "mean_value")
#: Which part of each step's displacement is applied (§3.0.1).
DIRECTIONS = ("full", "normal", "tangential")


@_arguments.real_options
def error_bound(epsilon_ball: float | None, error_slab: float | None, function: str) -> tuple[str, float]:
    """The (bound, epsilon) pair the bindings take, from the two keyword options. Raises
    InputError when both are given (the bindings check epsilon itself: finite and > 0)."""
    if epsilon_ball is not None and error_slab is not None:
        raise InputError(f"{function}: give at most one of epsilon_ball and error_slab")
    if epsilon_ball is not None:
        return "epsilon_ball", float(epsilon_ball)
    if error_slab is not None:
        return "error_slab", float(error_slab)
    return "none", 0.0


@_arguments.real_options
def laplacian(V: ArrayLike, F: ArrayLike, *, weights: str = "uniform", lam: float = 0.5, iterations: int = 10,
              direction: str = "full", implicit: bool = False, fixed: ArrayLike | None = None,
              epsilon_ball: float | None = None, error_slab: float | None = None,
              progress: ProgressCallback = None) -> FloatArray:
    """Laplacian smoothing (§3.0.2): ``iterations`` steps of the umbrella operator U.

    ``(U p)_i = sum_j w_ij (p_j - p_i) / sum_j w_ij`` moves each vertex towards the weighted
    centre of its one-ring; the weights are computed once, on the input, so k explicit steps
    apply the linear filter ``(I + lam U)^k``. Explicit steps (``p <- p + lam U p``) are stable for
    ``0 < lam <= 1`` with non-negative weights and diverge beyond (for uniform weights the
    eigenvalues of -U reach 2: a mode grows as ``|1 - 2 lam|^k``). Implicit steps (``implicit=True``,
    backward Euler, Desbrun et al. 1999) solve ``(I - lam U) p' = p``, which damps every mode for
    any ``lam > 0``: the system ``(D - lam L) p' = D p`` is factorized once (CHOLMOD; sparse LU for
    the non-symmetric mean-value weights) and each iteration is one solve.

    V: (n, 3) float array. F: (m, 3) int array. weights: ``"uniform"`` (default), ``"cotan"``
    (cot alpha + cot beta: linear precision, may be negative), ``"cotan_delaunay"`` (the cot
    weights of the intrinsic Delaunay triangulation, :func:`meshsmith.geometry.cotan_laplacian`
    with ``intrinsic_delaunay=True``: non-negative on every edge) or ``"mean_value"``. lam: the
    step size, > 0. iterations: >= 0. direction: ``"full"``, ``"normal"`` (each step's
    displacement projected onto the current angle-weighted vertex normal: noise removal without
    moving vertices along the surface) or ``"tangential"`` (its tangential part: vertex
    redistribution without changing the shape). fixed: indices of vertices held at their input
    position (a boundary, say). epsilon_ball: each vertex stays within this distance of its
    input position; error_slab: its displacement along its input vertex normal
    (``geometry.vertex_normals(V, F)``) stays within this distance, tangential motion is free
    (a vertex without a normal, all its faces degenerate, gets the ball) (§3.0.2 "Error Control";
    give at most one). The bound is enforced after every step by
    projection onto the ball or slab, and holds exactly for the returned floats. progress:
    optional ``(fraction, stage) -> bool``; False cancels.

    Returns the smoothed (n, 3) float array. Vertices used by no face (or only by degenerate
    ones) do not move.

    Raises InputError for bad (V, F), an unknown option, lam <= 0, iterations < 0, a fixed index
    outside ``[0, n)``, a bound that is not > 0, both bounds, or (``"cotan_delaunay"``) a
    non-manifold or inconsistently oriented mesh; SolverError if the factorization fails.
    """
    bound, epsilon = error_bound(epsilon_ball, error_slab, "laplacian")
    return _core.laplacian_smoothing(V, F, weights, float(lam), iterations, direction, bool(implicit), fixed,
                                     bound, epsilon, progress)


@_arguments.real_options
def taubin(V: ArrayLike, F: ArrayLike, *, lam: float = 0.5, mu: float = -0.53, iterations: int = 10,
           weights: str = "uniform", direction: str = "full", fixed: ArrayLike | None = None,
           epsilon_ball: float | None = None, error_slab: float | None = None,
           progress: ProgressCallback = None) -> FloatArray:
    """Taubin's lambda|mu smoothing (§3.0.1 "Design a smoothing operator"; Taubin 1995).

    Each of the ``iterations`` applies ``p <- (I + mu U)(I + lam U) p``: a shrinking step and an
    inflating one, with the umbrella operator U of :func:`laplacian`. For a mode of -U with
    eigenvalue k (the frequency, in [0, 2] for non-negative weights) the filter's transfer
    function is ``f(k) = ((1 - lam k)(1 - mu k))**iterations`` (:func:`transfer_function`): f(0) = 1,
    ``f(k) ~ 1`` below the pass-band frequency ``k_PB = 1/lam + 1/mu`` (0.113 for the defaults),
    and f falls to 0 above it, so noise is removed while the shape and its volume are kept —
    unlike plain Laplacian smoothing, whose ``(1 - lam k)**iterations`` shrinks every mode.
    ``mu = -lam`` gives §3.0.1's ``(I - lam U)(I + lam U) = I - lam**2 U**2``.

    V: (n, 3) float array. F: (m, 3) int array. lam > 0, mu < 0 (``mu < -lam`` for a pass band);
    weights, direction, fixed, epsilon_ball, error_slab and progress as :func:`laplacian` (the
    bound is enforced after each of the two steps). Returns the smoothed (n, 3) float array.

    Raises InputError as :func:`laplacian`, and for mu >= 0.
    """
    bound, epsilon = error_bound(epsilon_ball, error_slab, "taubin")
    return _core.taubin_smoothing(V, F, weights, float(lam), float(mu), iterations, direction, fixed, bound, epsilon,
                                  progress)


@_arguments.real_options
def transfer_function(k: ArrayLike, *, lam: float = 0.5, mu: float | None = -0.53, iterations: int = 1) -> FloatArray:
    """The factor by which smoothing scales a mode of -U of frequency k (§3.0.1).

    ``((1 - lam k)(1 - mu k))**iterations`` for :func:`taubin`, ``(1 - lam k)**iterations`` for
    explicit :func:`laplacian` steps (``mu=None``). k: array of eigenvalues of -U (>= 0; at most 2
    for non-negative weights). Returns a float array of k's shape.

    Raises InputError for k that is not an array of finite numbers, non-finite lam or mu, or
    iterations that is not an integer >= 0.
    """
    k = np.asarray(_arguments.numbers(k, "k"), dtype=float)
    steps = _arguments.integer(iterations, "iterations", 0, 2**31 - 1)
    if not np.all(np.isfinite(k)):
        raise InputError("transfer_function: k holds NaN or Inf: expected finite frequencies")
    for name, value in (("lam", lam), ("mu", mu)):
        if value is not None and not np.isfinite(value):
            raise InputError(f"transfer_function: {name} = {value}: expected a finite number")
    factor = 1.0 - float(lam) * k
    if mu is not None:
        factor = factor * (1.0 - float(mu) * k)
    with np.errstate(over="ignore"):  # |factor| > 1 (an unstable step) grows to inf: that is the answer
        return np.asarray(factor ** steps, dtype=float)
