"""Areas and volume (§1.2); binding cpp/python/geometry.cpp.
"""
from __future__ import annotations

from .._core import geometry as _geometry
from .._typing import ArrayLike, FloatArray

__all__ = ["face_areas", "surface_area", "volume"]


def face_areas(V: ArrayLike, F: ArrayLike) -> FloatArray:
    """Area of each triangle, ``|(v1 - v0) x (v2 - v0)| / 2`` (libigl's ``doublearea / 2``).

    V: (n, 3) float array of positions, F: (m, 3) integer array of triangles.
    Returns an (m,) float64 array (0 for degenerate faces).
    Raises InputError for bad input (empty, out-of-range index, NaN/Inf).
    """
    return _geometry.face_areas(V, F)


def surface_area(V: ArrayLike, F: ArrayLike) -> float:
    """Total area of the triangles of (V, F), summed in a fixed order (deterministic).

    Raises InputError as :func:`face_areas`.
    """
    return float(_geometry.surface_area(V, F))


def volume(V: ArrayLike, F: ArrayLike) -> float:
    """Signed volume enclosed by a closed surface (divergence theorem).

    Sum over faces of ``v0 . (v1 x v2) / 6``: positive when the faces are counter-clockwise seen
    from outside (outward normals), negative when inward. For an open or inconsistently oriented
    mesh the value depends on the origin and is not a volume.
    V: (n, 3) float array, F: (m, 3) integer array. Raises InputError as :func:`face_areas`.
    """
    return float(_geometry.volume(V, F))
