"""Multiresolution editing (§3.1.2): smooth base + details in local frames; binding
cpp/python/deformation.cpp, C++ src/deformation/multiresolution.cpp."""
from __future__ import annotations

from typing import Callable

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import deformation as _core
from .._typing import ArrayLike, FloatArray
from .harmonic import harmonic

__all__ = ["multiresolution_edit"]


def multiresolution_edit(V: ArrayLike, F: ArrayLike, fixed: ArrayLike,
                         base_edit: Callable[[FloatArray], ArrayLike] | ArrayLike) -> FloatArray:
    """Edit the smooth base of a region and keep its details (classical multiresolution editing).

    The region is every vertex not in `fixed`. Its smooth base P̄ is the bi-Laplacian fairing
    (Δ²P̄ = 0 inside, `fixed` held: ``harmonic(V, F, fixed, V[fixed], order=2)``); the details
    P − P̄ are encoded in local frames of P̄ (its vertex normal and a tangent towards a neighbour).
    `base_edit` edits the base — a callable taking the (n, 3) base and returning the edited
    (n, 3) base, or the edited base itself — and the details are re-added in the frames of the
    edited base, so they follow its bending instead of keeping their world directions.

    V: (n, 3) float, F: (m, 3) int, fixed: (k,) distinct vertex indices (every connected part needs
    one). Returns (n, 3) float64: the edited base plus the details.
    Raises InputError for bad indices, a part without a fixed vertex, or an edited base of another
    shape or with NaN/Inf.
    """
    positions = _arguments.real_array(V, "V", 3)
    held = _arguments.index_array(fixed, "fixed")
    if held.size and (held.min() < 0 or held.max() >= len(positions)):
        raise InputError(f"fixed: vertex indices must be in [0, {len(positions)})")
    base = harmonic(positions, F, held, positions[held], order=2)
    unreferenced = ~np.isin(np.arange(len(positions)), np.asarray(_arguments.index_array(F, "F", 3)).ravel())
    base[unreferenced] = positions[unreferenced]   # used by no face: no detail, the vertex stays
    edited = base_edit(base.copy()) if callable(base_edit) else base_edit
    return _core.transfer_details(positions, base, F, edited)
