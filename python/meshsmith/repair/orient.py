"""Consistent orientation, closed components outward (§2.4); binding cpp/python/repair.cpp,
C++ src/repair/orient.cpp."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core import repair as _core
from .._results import Unpackable
from .._typing import ArrayLike

__all__ = ["OrientedFaces", "orient_faces"]


@dataclass(frozen=True)
class OrientedFaces(Unpackable):
    """The result of :func:`orient_faces`; unpacks as ``F, flipped``.

    F: (m, 3) int64, the input faces with those in `flipped` reversed; flipped: (k,) int64 faces
    reversed, ascending; components: edge-connected components; closed_components: those without
    a boundary or non-manifold edge; non_orientable_components: those that admit no consistent
    orientation (a Möbius strip): they keep some edges used twice in one direction.
    """

    F: np.ndarray
    flipped: np.ndarray
    components: int
    closed_components: int
    non_orientable_components: int

    unpacks = ("F", "flipped")


def orient_faces(V: ArrayLike, F: ArrayLike) -> OrientedFaces:
    """Orient every component of a mesh consistently, closed components outward.

    Faces are joined across edges with exactly two faces; a breadth-first walk from each
    component's first face makes every face agree with the one it was reached from. A closed
    component with negative signed volume is then reversed as a whole (outward: counter-clockwise
    seen from outside); an open one is reversed if that flips fewer faces, so a consistently
    oriented open mesh is returned unchanged. Non-manifold edges join nothing: split them first
    (:func:`meshsmith.topology.split_non_manifold_vertices`, or use :func:`clean`).

    V: (n, 3) float array, F: (m, 3) integer array. Returns an :class:`OrientedFaces`.
    Raises InputError if (V, F) fails :func:`meshsmith.core.validate_mesh`. O(m).
    """
    return OrientedFaces(**_core.orient_faces(V, F))
