"""Bi-Laplacian fairing (§3.0.2, the thin plate Δ²f = 0); binding cpp/python/smoothing_fairing.cpp,
C++ src/smoothing/fairing.cpp (on the deformation chapter's k-harmonic solver)."""
from __future__ import annotations

import numpy as np

from .._core import smoothing as _core
from .._typing import ArrayLike, FloatArray

__all__ = ["bilaplacian"]


def bilaplacian(V: ArrayLike, F: ArrayLike, *, fixed: ArrayLike | None = None) -> FloatArray:
    """Fair a mesh by the bi-Laplace equation Δ²x = 0 (the thin-plate surface of §3.0.2).

    Held in place: every boundary vertex and every neighbour of one (the boundary ring: holding
    both makes the faired surface meet the rest C¹, tangents included), and the `fixed` vertices.
    Every other vertex used by a face solves (L M⁻¹ L x)_i = 0 (cotan Laplacian L, Voronoi mass
    matrix M): one sparse Cholesky factorization and solve. Vertices used by no face stay.

    V: (n, 3) float, F: (m, 3) int, fixed: (k,) distinct vertex indices or None. Returns (n, 3)
    float64. Raises InputError for bad shapes or indices, NaN/Inf, or a connected part with nothing
    held (a closed mesh needs `fixed` vertices).
    """
    held = np.zeros(0, dtype=np.int64) if fixed is None else fixed
    return _core.bilaplacian(V, F, held)
