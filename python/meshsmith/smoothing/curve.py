"""Smoothing of polylines (§3.0.1 "Smoothing (2D)"); binding cpp/python/smoothing.cpp (C++
cpp/src/smoothing/curve_smoothing.cpp).
"""
from __future__ import annotations

from .. import _arguments, curves
from .._core import smoothing as _core
from .._typing import ArrayLike, FloatArray, ProgressCallback
from .laplacian import error_bound

__all__ = ["smooth_curve"]


@_arguments.real_options
def smooth_curve(P: ArrayLike, *, lam: float = 0.5, mu: float | None = None, iterations: int = 10,
                 closed: bool = False, fixed: ArrayLike | None = None, epsilon_ball: float | None = None,
                 error_slab: float | None = None, progress: ProgressCallback = None) -> FloatArray:
    """Smooths a polyline by §3.0.1's update ``dp_i = (p_(i+1) - p_i) / 2 + (p_(i-1) - p_i) / 2``.

    ``[p] <- (I + lam U)[p]`` per step, U the polygon's second-difference matrix (the umbrella
    operator of the curve), or with ``mu`` Taubin's pair ``(I + mu U)(I + lam U)`` per iteration
    (:func:`meshsmith.smoothing.taubin` documents the transfer function; for a closed polygon of n
    points the frequencies are ``k_j = 1 - cos(2 pi j / n)``, the Fourier modes).

    P: (n, 2) or (n, 3) float array, n >= 2 (3 if closed); a closed curve does not repeat its
    first point at the end. lam > 0; mu: None (Laplacian steps) or < 0; iterations >= 0.
    The two ends of an open curve are held in place, and so are the indices in ``fixed``.
    epsilon_ball: each point stays within this distance of its input position; error_slab: the
    part of its displacement orthogonal to its input tangent (:func:`meshsmith.curves.tangents`)
    stays within this distance, motion along the tangent is free (give at most one; enforced
    after every step, exactly for the returned floats). progress: optional ``(fraction, stage)
    -> bool``. Returns the smoothed (n, d) float array.

    Raises InputError for a bad P, lam <= 0, mu >= 0, iterations < 0, a fixed index outside
    ``[0, n)``, a bound that is not > 0, or both bounds.
    """
    bound, epsilon = error_bound(epsilon_ball, error_slab, "smooth_curve")
    tangents = curves.tangents(P, closed=bool(closed)) if bound == "error_slab" else None
    return _core.smooth_curve(P, float(lam), 0.0 if mu is None else float(mu), iterations, bool(closed), fixed,
                              bound, epsilon, tangents, progress)
