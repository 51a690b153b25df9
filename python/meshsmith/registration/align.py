"""Absolute orientation by Horn's quaternion method (§2.3.1); binding cpp/python/registration.cpp."""
from __future__ import annotations

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import registration as _core
from .._typing import ArrayLike, FloatArray

__all__ = ["align", "apply_transform", "rotation_angle"]


def align(A: ArrayLike, B: ArrayLike, *, scale: bool = False, weights: ArrayLike | None = None) -> FloatArray:
    """The rigid (or, with ``scale=True``, similarity) transform that maps A onto B (§2.3.1;
    Horn 1987).

    A, B: (n, 3) float arrays of corresponding points (row i of A ↔ row i of B). weights: (n,)
    non-negative weights, or None for all 1. Minimises Σ w_i ‖T a_i − b_i‖² over rotations and
    translations: the rotation is the unit quaternion of the largest eigenvalue of Horn's
    symmetric 4×4 matrix, the translation maps the weighted centroid of A onto that of B, and the
    scale (``scale=True``) is the ratio of the spreads, sqrt(Σ w‖b − b̄‖² / Σ w‖a − ā‖²), so that
    ``align(B, A)`` is the inverse of ``align(A, B)``. Exact to round-off (about 1e-15) for
    noise-free correspondences.

    Returns the (4, 4) float64 transform. Raises InputError for empty input, NaN/Inf, shapes
    that differ, a negative weight, fewer than 3 points of positive weight, or points of A or B
    that are all identical or collinear (the rotation is then not determined).
    """
    return _core.align(A, B, weights, bool(scale))


def apply_transform(T: ArrayLike, P: ArrayLike) -> FloatArray:
    """The points P (n, 3) mapped by the 4×4 transform T: ``P @ T[:3, :3].T + T[:3, 3]``.
    Raises InputError if T is not a finite 4×4 array or P not a finite (n, 3) array."""
    M = _transform(T, "T")
    moved = _arguments.finite(_arguments.real_array(P, "P", 3), "P") @ M[:3, :3].T + M[:3, 3]
    if not np.isfinite(moved).all():
        raise InputError("apply_transform: a moved point leaves the double range")
    return moved


def rotation_angle(T: ArrayLike) -> float:
    """The rotation angle (radians, in [0, π]) of the rotation part of a 4×4 rigid or similarity
    transform T (its scale divided out)."""
    M = _transform(T, "T")[:3, :3]
    determinant = float(np.linalg.det(M))
    if not determinant > 0:
        raise InputError(f"T: the 3×3 part has determinant {determinant}: expected a rotation times a scale > 0")
    M = M / np.cbrt(determinant)
    skew = np.array([M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]])
    return float(np.arctan2(0.5 * np.linalg.norm(skew), (np.trace(M) - 1.0) / 2.0))


def _transform(T: ArrayLike, name: str) -> FloatArray:
    M = _arguments.finite(_arguments.real_array(T, name, 4), name)
    if M.shape != (4, 4):
        raise InputError(f"{name} has shape {M.shape}: expected a (4, 4) transform")
    return M
