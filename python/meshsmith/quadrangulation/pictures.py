"""Pictures of the quadrangulation chapter (§5.2.2, §5.3) through meshsmith's own renderer
(:func:`meshsmith.render.render`): a cross field as crosses drawn on the faces with its
singularities as coloured cones, and a dual-loop layout's regions. The parametrization's grid
texture and quad meshes with their edges are :func:`meshsmith.render.render` itself (``uv=`` with
``checker_size=1``; (k, 4) faces).

Glyphs are geometry added to the surface and drawn by the same z-buffer, so what the surface
hides they hide too; their colours are per-vertex values through the ``magma`` colormap, fixed
by the constants below (tests read them back from the pixels).
"""
from __future__ import annotations

import numpy as np

from .. import _arguments
from .. import render as _render
from .._core import InputError
from .._typing import ArrayLike, FloatArray, IndexArray, PathLike
from ..repair.unreferenced import on_referenced_vertices
from .cross_field import FieldLike, field_angles, singularities
from .dual_loops import _face_directions

__all__ = ["FIELD_COLORMAP", "SURFACE_VALUE", "CROSS_VALUE", "CONE_VALUES", "field_glyphs", "field_picture",
           "regions_picture"]

#: Colormap and per-vertex values of the field picture: the surface, the crosses, and the cones by
#: index in quarter turns (+1: a valence-3 corner, −1: valence 5; the others share the last entry).
FIELD_COLORMAP = "magma"
SURFACE_VALUE = 0.92
CROSS_VALUE = 0.0
CONE_VALUES = {1: 0.62, -1: 0.30, "other": 0.45}


def _cone_value(index: int) -> float:
    return CONE_VALUES.get(index, CONE_VALUES["other"])


_AXES = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
_OCTAHEDRON = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])


def _octahedra(points: np.ndarray, radius: float, first: int) -> tuple[np.ndarray, np.ndarray]:
    """Octahedra of `radius` at (k, 3) points: (6k, 3) vertices and (8k, 3) faces numbered from `first`."""
    vertices = (points[:, None, :] + radius * _AXES[None]).reshape(-1, 3)
    faces = first + (np.arange(len(points))[:, None, None] * 6 + _OCTAHEDRON[None]).reshape(-1, 3)
    return vertices, faces


def _spread_faces(centroids: np.ndarray, cell: float) -> np.ndarray:
    """One face per cube of side `cell` (the one nearest the cube's centre): crosses that do not overlap."""
    key = np.floor(centroids / cell).astype(np.int64)
    offset = np.linalg.norm(centroids - (key + 0.5) * cell, axis=1)
    order = np.lexsort((offset, key[:, 2], key[:, 1], key[:, 0]))
    first = np.ones(len(order), dtype=bool)
    first[1:] = (np.diff(key[order], axis=0) != 0).any(axis=1)
    return np.sort(order[first])


def field_glyphs(V: ArrayLike, F: ArrayLike, field: FieldLike, *, glyph_size: float | None = None,
                 max_crosses: int = 1500) -> tuple[FloatArray, IndexArray, FloatArray]:
    """The glyph geometry of :func:`field_picture`: (Vg, Fg, value).

    Crosses: on faces spread one per cube of side `glyph_size` (default: the bounding diagonal ÷
    40, grown up to a quarter of it until at most `max_crosses` remain, then
    evenly thinned), two perpendicular bars along the field's
    directions, `glyph_size`·0.8 long and 0.12 of that wide, lifted off the face by 2% of their
    length; cones: an octahedron of radius 0.45·`glyph_size` at each singular vertex. Vg: (g, 3)
    float64, Fg: (h, 3) int64 (own numbering, counter-clockwise seen from outside), value: (g,)
    float64 per glyph vertex (CROSS_VALUE, CONE_VALUES by index). Raises InputError as
    :func:`meshsmith.quadrangulation.singularities`, for glyph_size ≤ 0 and max_crosses < 1.
    """
    max_crosses = _arguments.integer(max_crosses, "max_crosses", 1, 10 ** 7)
    if glyph_size is not None and not (np.isfinite(_arguments.real(glyph_size, "glyph_size")) and glyph_size > 0):
        raise InputError(f"field_glyphs: glyph_size must be None or a finite number > 0, got {glyph_size}")
    theta = field_angles(V, F, field)
    mesh = on_referenced_vertices(V, F)
    P, T = np.asarray(mesh.V, dtype=np.float64), np.asarray(mesh.F, dtype=np.int64)
    cones = singularities(P, T, theta)
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    diagonal = float(np.linalg.norm(P.max(0) - P.min(0)))
    size = diagonal / 40 if glyph_size is None else float(glyph_size)
    centroids = (a + b + c) / 3
    chosen = _spread_faces(centroids, size)
    while len(chosen) > max_crosses and size < diagonal / 4:
        size *= 1.25
        chosen = _spread_faces(centroids, size)
    if len(chosen) > max_crosses:  # (cubes straddle the shape: a few remain) evenly spaced among them
        chosen = chosen[np.linspace(0, len(chosen) - 1, max_crosses).round().astype(np.int64)]
    n = normal[chosen]
    u = _face_directions(P, T[chosen], theta[chosen])  # the cross's first direction
    w = np.cross(n, u)                                # and its second
    half, thick = 0.4 * size, 0.06 * size
    lift = centroids[chosen] + 0.02 * size * n
    corners = []
    for along, across in ((u, w), (w, u)):
        for s, r in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            corners.append(lift + s * half * along + r * thick * across)
    k = len(chosen)
    Vc = np.stack(corners, axis=1).reshape(-1, 3)                         # 8 per cross
    bar = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    Fc = (np.arange(k)[:, None, None] * 8 + bar[None]).reshape(-1, 3)
    values = [np.full(len(Vc), CROSS_VALUE)]
    # Octahedra at the cones.
    Vo, Fo = _octahedra(P[cones.vertices], 0.45 * size, len(Vc))
    values.append(np.repeat([_cone_value(int(i)) for i in cones.indices], 6).astype(np.float64))
    return np.vstack([Vc, Vo]), np.vstack([Fc, Fo]).astype(np.int64), np.concatenate(values)


def field_picture(V: ArrayLike, F: ArrayLike, field: FieldLike, path: PathLike | None = None, *,
                  size: tuple[int, int] = (480, 420), view: _render.View = "three-quarter",
                  camera: _render.Camera | None = None, up: str = "y", title: str | None = None,
                  glyph_size: float | None = None) -> np.ndarray:
    """A picture of a cross field: crosses drawn on the faces, the singularities as cones coloured
    by index (magma: CONE_VALUES; crosses CROSS_VALUE, the surface SURFACE_VALUE).

    V: (n, 3), F: (m, 3); field: a :class:`CrossField`, (m,) angles or (m, 3) directions. camera:
    as :func:`meshsmith.render.render` (default: framed on V from `view`, so the glyphs do not move
    the framing). Writes a PNG at `path` if given; returns the (height, width, 3) uint8 image.
    Raises InputError as :func:`field_glyphs` and :func:`meshsmith.render.render`.
    """
    mesh = on_referenced_vertices(V, F)
    P, T = np.asarray(mesh.V, dtype=np.float64), np.asarray(mesh.F, dtype=np.int64)
    Vg, Fg, value = field_glyphs(P, T, field_angles(V, F, field), glyph_size=glyph_size)
    if camera is None:
        camera = _render.frame_camera(P, view=view, size=size, up=up)
    scalar = np.concatenate([np.full(len(P), SURFACE_VALUE), value])
    return _render.render(np.vstack([P, Vg]), np.vstack([T, Fg + len(P)]), path, size=size, camera=camera, up=up,
                          scalar=scalar, cmap=FIELD_COLORMAP, scalar_range=(0.0, 1.0), colorbar=False,
                          wireframe=False, title=title)


def regions_picture(V: ArrayLike, F: ArrayLike, region: ArrayLike, path: PathLike | None = None, *,
                    size: tuple[int, int] = (480, 420), view: _render.View = "three-quarter",
                    camera: _render.Camera | None = None, up: str = "y", title: str | None = None,
                    marked: ArrayLike | None = None) -> np.ndarray:
    """A picture of a partition of the faces (e.g. a dual-loop layout's regions): each region one
    flat colour (a scrambled walk through viridis, so neighbours differ), `marked` input vertices
    (e.g. the layout's corners) as small dark octahedra. region: (m,) integers ≥ 0.
    Returns the (height, width, 3) uint8 image (and writes `path` if given). Raises InputError for
    a region array of the wrong length or with negative entries, marked vertices out of range, and
    as :func:`meshsmith.render.render`."""
    mesh = on_referenced_vertices(V, F)
    P, T = np.asarray(mesh.V, dtype=np.float64), np.asarray(mesh.F, dtype=np.int64)
    label = np.asarray(_arguments.index_array(region, "region"), dtype=np.int64)
    if len(label) != len(T) or (len(label) and label.min() < 0):
        raise InputError(f"regions_picture: region must be {len(T)} integers >= 0, one per face")
    # Faces drawn apart (three vertices each) so a region's colour does not bleed into the next.
    corners = P[T].reshape(-1, 3)
    faces = np.arange(3 * len(T)).reshape(-1, 3)
    golden = 0.6180339887498949
    scalar = np.repeat(0.15 + 0.8 * ((label * golden) % 1.0), 3)
    points = np.zeros(0, dtype=np.int64) if marked is None else mesh.from_input_indices(marked, "marked")
    if points.ndim != 1 or (len(points) and (points.min() < 0 or points.max() >= len(P))):
        raise InputError(f"regions_picture: marked must be a list of vertex indices in [0, {len(P)})")
    if len(points):
        radius = 0.012 * float(np.linalg.norm(P.max(0) - P.min(0)))
        Vo, Fo = _octahedra(P[points], radius, len(corners))
        corners, faces = np.vstack([corners, Vo]), np.vstack([faces, Fo])
        scalar = np.concatenate([scalar, np.zeros(len(Vo))])
    if camera is None:
        camera = _render.frame_camera(P, view=view, size=size, up=up)
    return _render.render(corners, faces, path, size=size, camera=camera, up=up, scalar=scalar, cmap="viridis",
                          scalar_range=(0.0, 1.0), colorbar=False, wireframe=False, title=title, flat=True)
