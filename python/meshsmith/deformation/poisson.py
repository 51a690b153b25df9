"""Poisson (gradient-domain) editing (§3.1.2); binding cpp/python/deformation.cpp, C++
src/deformation/poisson_edit.cpp."""
from __future__ import annotations

import numpy as np

from .._core import deformation as _core
from .._typing import ArrayLike, FloatArray

__all__ = ["poisson_edit"]


def poisson_edit(V: ArrayLike, F: ArrayLike, handle: ArrayLike, handle_positions: ArrayLike, *,
                 fixed: ArrayLike | None = None, rotate: bool = True) -> FloatArray:
    """Poisson editing: keep the surface's Laplacian coordinates, turned, under the constraints.

    Minimizes ‖ΔQ − R ΔP‖² (mass-matrix norm) over the edited surface Q with the `handle`
    vertices at `handle_positions` and the `fixed` ones in place; the normal equations are
    L M⁻¹ L Q = L R ΔP (cotan Laplacian L, Voronoi mass matrix M). rotate=False takes R = I, which
    is Δ²Q = Δ²P: the bi-Laplacian deformation (:class:`Deformer`). rotate=True turns each
    vertex's Laplacian coordinate by R_i, the handle's best-fit rotation scaled in angle by the
    bi-harmonic weight w_i (1 on the handle, 0 on the fixed vertices), so a twisted or bent handle
    carries the surface's details round with it.

    V: (n, 3) float, F: (m, 3) int, handle: (h,) distinct indices (non-empty), handle_positions:
    (h, 3), fixed: (f,) distinct indices not in `handle` (or None). Returns (n, 3) float64.
    Raises InputError as :class:`Deformer`, or for handle_positions of the wrong shape or NaN/Inf.
    """
    empty = np.zeros(0, dtype=np.int64)
    return _core.poisson_edit(V, F, handle, empty if fixed is None else fixed, handle_positions, bool(rotate))
