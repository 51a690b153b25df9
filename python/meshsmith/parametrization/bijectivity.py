"""Is a parametrization one-to-one? Flipped and degenerate triangles, self-crossing boundaries (§5.1); C++ src/parametrization/bijectivity_cgal.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass

from .._core import parametrization as _core
from .._results import Unpackable
from .._typing import ArrayLike, IndexArray

__all__ = ["BijectivityReport", "check_bijectivity", "is_bijective"]


@dataclass(frozen=True)
class BijectivityReport(Unpackable):
    """The verdict of :func:`check_bijectivity`; unpacks in field order.

    bijective: bool; orientation: +1 (all triangles counter-clockwise), -1 (all clockwise) or 0;
    degenerate_faces: (k,) int64 faces with collinear UV corners; flipped_faces: (k,) int64 faces
    oriented against the majority; crossing_boundary_sides: (k, 2) int64 pairs of boundary sides
    (3 * face + corner, the side from corner to the next) whose UV segments intersect (at most 100).
    """

    bijective: bool
    orientation: int
    degenerate_faces: IndexArray
    flipped_faces: IndexArray
    crossing_boundary_sides: IndexArray


def check_bijectivity(UV: ArrayLike, F: ArrayLike) -> BijectivityReport:
    """Check that the parametrization UV of F is one-to-one, and say why not.

    A disk map is bijective iff every UV triangle keeps one orientation (none flipped, none
    degenerate) and the boundary polygon is simple (no two boundary edges meet except
    consecutive ones at their shared vertex, without folding back). Exact orientation predicates
    decide every case; boundary edges are paired by a box-intersection sweep. With several
    boundary loops each must be simple and no two may meet.

    UV: (n, 2) float array, F: (m, 3) integer array. Returns a :class:`BijectivityReport`.
    Raises InputError for an empty F, an index outside UV or a NaN/Inf in UV.
    """
    return BijectivityReport(**_core.check_bijectivity(UV, F))


def is_bijective(UV: ArrayLike, F: ArrayLike) -> bool:
    """True when the parametrization UV of F is one-to-one (see :func:`check_bijectivity`)."""
    return check_bijectivity(UV, F).bijective
