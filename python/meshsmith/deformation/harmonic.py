"""k-harmonic interpolation and handle-based deformation (§3.1.1); binding
cpp/python/deformation.cpp, C++ src/deformation/harmonic_deformer.cpp."""
from __future__ import annotations

import numpy as np

from .._core import deformation as _core
from .._typing import ArrayLike, FloatArray, IndexArray

__all__ = ["harmonic", "Deformer"]


def harmonic(V: ArrayLike, F: ArrayLike, b: ArrayLike, bc: ArrayLike, *, order: int = 2) -> FloatArray:
    """The k-harmonic interpolant of the values `bc` at the vertices `b` (libigl's
    ``igl.harmonic(V, F, b, bc, k)``, equal to it to round-off).

    Solves Q X = 0 at every vertex not in `b` with X[b] = bc, where Q = (−L M⁻¹)^(k−1) (−L), L the
    cotan Laplacian and M the Voronoi mass matrix: order 1 is ΔX = 0, order 2 the bi-Laplace
    (thin plate) equation Δ²X = 0, order 3 Δ³X = 0.

    V: (n, 3) float, F: (m, 3) int, b: (k,) distinct vertex indices, bc: (k, c) values.
    Returns (n, c) float64 (rows of vertices used by no face are 0).
    Raises InputError for bad shapes or indices, NaN/Inf, order not in {1, 2, 3}, or a connected
    part of the mesh without a vertex of `b` (the system would be singular there).
    """
    return _core.harmonic(V, F, b, bc, order)


class Deformer:
    """Handle-based deformation with a precomputed k-harmonic system (§3.1.1).

    ``Deformer(V, F, handle, fixed=None, *, order=2, details=False)``: the `handle` vertices are moved
    by the user, the `fixed` ones stay, and the displacement of every other vertex solves
    Q d = 0 (order 2: Δ²d = 0, so the result equals ``V + igl.harmonic(V, F, b, D_b, 2)`` with
    D_b the handle and fixed displacements). The constructor factorizes the system once;
    :meth:`deform` then costs one back-substitution and :meth:`transform` (an affine map of the
    handle, through its four control points) one small dense product.

    details=True is the detail-preserving variant: the surface is split into a smooth base (the
    free region faired by the same system, handle and fixed held) and details stored in local
    frames (normal and tangent) of the base; a deformation moves the base and re-adds the details
    in the moved frames, so bumps on a bent region turn with it instead of shearing.

    V: (n, 3) float, F: (m, 3) int, handle: (h,) distinct indices (non-empty), fixed: (f,)
    distinct indices, none in `handle` (None or empty: only the handle holds the mesh).
    Raises InputError for an empty handle, an index out of range or repeated, a vertex both in
    `handle` and `fixed`, order not in {1, 2, 3}, or a connected part of the mesh with no handle
    or fixed vertex.
    """

    def __init__(self, V: ArrayLike, F: ArrayLike, handle: ArrayLike, fixed: ArrayLike | None = None, *, order: int = 2,
                 details: bool = False) -> None:
        empty = np.zeros(0, dtype=np.int64)
        self._deformer = _core.HarmonicDeformer(V, F, handle, empty if fixed is None else fixed, order,
                                                bool(details))

    @property
    def handle(self) -> IndexArray:
        """(h,) int64 handle vertices, in the order handle positions are given."""
        return self._deformer.handle

    @property
    def fixed(self) -> IndexArray:
        """(f,) int64 fixed vertices."""
        return self._deformer.fixed

    @property
    def order(self) -> int:
        """k of the k-harmonic system (1, 2 or 3)."""
        return int(self._deformer.order)

    def deform(self, handle_positions: ArrayLike) -> FloatArray:
        """The deformed vertices (n, 3) with the handle vertices at `handle_positions` ((h, 3),
        in the order of :attr:`handle`). Raises InputError for a wrong shape or NaN/Inf."""
        return self._deformer.deform(handle_positions)

    def transform(self, T: ArrayLike) -> FloatArray:
        """The deformed vertices (n, 3) when the handle undergoes the affine map `T` (4×4, acting
        on column vectors (x, y, z, 1); last row (0, 0, 0, 1)). Raises InputError for NaN/Inf,
        a wrong shape or a projective last row."""
        return self._deformer.transform(T)
