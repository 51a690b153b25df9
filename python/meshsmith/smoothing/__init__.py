"""Smoothing chapter (§3.0.1–3.0.2): Laplacian and Taubin smoothing of meshes and polylines, with
error control.

Every method moves vertices by the umbrella operator U (uniform, cotangent, intrinsic-Delaunay
cotangent or mean-value weights), explicitly or implicitly, optionally only along the normal or
only tangentially, with vertices held fixed and each vertex kept inside an epsilon-ball or an
error slab around its input position at every step. Bad input raises
:class:`meshsmith.InputError`.

Modules, one per algorithm family: ``laplacian`` (laplacian, taubin), ``curve`` (smooth_curve), ``fairing``
(bilaplacian).
"""
from .curve import smooth_curve
from .fairing import bilaplacian
from .laplacian import DIRECTIONS, WEIGHTS, laplacian, taubin, transfer_function

__all__ = ["WEIGHTS", "DIRECTIONS", "laplacian", "taubin", "transfer_function", "smooth_curve", "bilaplacian"]
