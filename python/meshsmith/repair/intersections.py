"""Self-intersecting face pairs (§2.4) with CGAL's exact predicates; binding
cpp/python/repair_intersections.cpp, C++ src/repair/self_intersections_cgal.cpp."""
from __future__ import annotations

from .._core import repair as _core
from .._typing import ArrayLike, IndexArray, ProgressCallback

__all__ = ["self_intersections"]


def self_intersections(V: ArrayLike, F: ArrayLike, *, progress: ProgressCallback = None) -> IndexArray:
    """The pairs of faces that intersect other than along what they share (§2.4).

    Two faces with no common vertex that touch or cross; two faces with one common vertex that
    meet elsewhere; two faces with a common edge folded onto each other (coplanar, on the same
    side of it); two faces on the same three vertices. Candidates are the pairs whose bounding
    boxes meet (CGAL's box intersection), decided with CGAL's exact predicates, so the answer
    does not depend on rounding or on the thread count. Degenerate faces (collinear or repeated
    corners, which :func:`meshsmith.repair.clean` removes) take no part.

    V: (n, 3) float array, F: (m, 3) integer array. Returns (k, 2) int64 face pairs, f < g in each
    row, rows sorted. O(m log m + candidates). Raises InputError for bad input; Cancelled from
    ``progress``.
    """
    return _core.self_intersections(V, F, progress=progress)
