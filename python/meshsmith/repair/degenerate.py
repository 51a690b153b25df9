"""Needles and caps (§2.4): almost-degenerate triangles removed by edge collapses and flips that
keep the topology; binding cpp/python/repair_degenerate.cpp, C++ src/repair/degenerate_triangles.cpp."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _arguments
from .._core import repair as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray

__all__ = ["NeedlesAndCaps", "remove_needles_and_caps"]


@dataclass(frozen=True)
class NeedlesAndCaps(Unpackable):
    """The result of :func:`remove_needles_and_caps`; unpacks as ``V, F``.

    V: (n', 3) float64, the kept input vertices, unmoved (``V == V_in[vertex_map]``); F: (m', 3)
    int64; vertex_map (n',) and face_map (m',) int64: the input vertex / face each output one was
    (a face's corners change where a collapse or a flip passed); collapses: needles removed (each
    collapse removes one vertex and two faces, one next to a boundary); flips: caps removed;
    remaining_needles, remaining_caps: those no admissible operation removed.
    """

    V: FloatArray
    F: IndexArray
    vertex_map: IndexArray
    face_map: IndexArray
    collapses: int
    flips: int
    remaining_needles: int
    remaining_caps: int

    unpacks = ("V", "F")


@_arguments.real_options
def remove_needles_and_caps(V: ArrayLike, F: ArrayLike, *, needle_ratio: float = 10.0, cap_angle: float = 160.0,
                            max_passes: int = 10) -> NeedlesAndCaps:
    """Remove needles and caps (§2.4) without changing the topology.

    A needle: a triangle whose longest edge exceeds ``needle_ratio`` (> 1) times its shortest; its
    shortest edge is collapsed onto one of its ends, which does not move (a halfedge collapse,
    taken only when the link condition holds, no face around turns by more than 90° and no
    boundary vertex leaves the boundary). A cap: a triangle with an angle above ``cap_angle``
    degrees (in (90, 180)); the edge opposite is flipped, when it is inside, the flip keeps both
    new faces on the side of the old ones and lowers the largest angle. Passes over every face
    repeat until nothing changes or ``max_passes``; genus, boundary loops and components are kept.

    V: (n, 3) float array, F: (m, 3) integer array, manifold and oriented (as
    :func:`meshsmith.repair.clean` returns it). Returns a :class:`NeedlesAndCaps`. Raises
    InputError for bad input, a non-manifold mesh or an option out of range.
    """
    raw = _core.remove_needles_and_caps(V, F, needle_ratio=float(needle_ratio), cap_angle=float(cap_angle),
                                        max_passes=max_passes)
    return NeedlesAndCaps(V=raw["V"], F=raw["F"], vertex_map=np.asarray(raw["vertex_map"], dtype=np.int64),
                          face_map=np.asarray(raw["face_map"], dtype=np.int64), collapses=int(raw["collapses"]),
                          flips=int(raw["flips"]), remaining_needles=int(raw["remaining_needles"]),
                          remaining_caps=int(raw["remaining_caps"]))
