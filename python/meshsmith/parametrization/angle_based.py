"""Angle-based flattening, ABF and ABF++ (§5.1.3), and UV from angles; binding cpp/python/parametrization_abf.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass as _dataclass

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import parametrization as _core
from .._deprecation import positional_options
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, ProgressCallback
from ..repair.unreferenced import on_referenced_vertices, referenced_indices

__all__ = ["AbfResult", "abf", "uv_from_angles"]


@_dataclass(frozen=True)
class AbfResult(Unpackable):
    """Result of :func:`abf` (m = number of faces, n = number of vertices); unpacks in field order.

    uv (n, 2) float: the flattened vertex positions (NaN rows for vertices no face uses); every
      triangle is counter-clockwise (positive signed area) when the map is bijective.
    angles (m, 3) float: the optimized angles (radians), column k at corner k (vertex F[f, k]).
    optimal_angles (m, 3) float: the target angles beta (the 3D angles, rescaled to sum 2 pi
      around interior vertices, clamped to [minimum_angle, pi - minimum_angle]).
    iterations: Newton iterations taken (0 when beta already satisfies every condition).
    residual: final constraint residual, the infinity-norm over |sum of a triangle's angles - pi|,
      |sum of the angles around an interior vertex - 2 pi| and |sum log sin(next angles) -
      sum log sin(previous angles)| around an interior vertex (the wheel condition).
    residual_history (iterations + 1,) float: the residual before the first step, then after each.
    """

    uv: FloatArray
    angles: FloatArray
    optimal_angles: FloatArray
    iterations: int
    residual: float
    residual_history: FloatArray


@positional_options("method")
def abf(V: ArrayLike, F: ArrayLike, *, method: str = "abf++", max_iterations: int = 30, tolerance: float = 1e-8,
        minimum_angle: float = 1e-4, progress: ProgressCallback = None) -> AbfResult:
    """Angle-based flattening of a disk-topology mesh (§5.1.3; Sheffer & de Sturler 2001, ABF;
    Sheffer, Lévy, Mogilnitskaya & Bogart 2005, ABF++).

    Minimizes sum (alpha - beta)^2 / beta^2 over the angles alpha of the flat mesh, subject to
    triangle sums pi, interior-vertex sums 2 pi and the wheel (sine-product) condition at every
    interior vertex, by Newton's method on the Lagrangian from alpha = beta; then lays the
    angles out in the plane by the least-squares sine-law system (:func:`uv_from_angles`),
    pinning the two boundary vertices farthest apart (the first at the origin), scaled so that
    the UV area equals the surface area (a developable surface comes out isometric).

    V: (n, 3) float array. F: (m, 3) int array: one connected, manifold, oriented component with
    one boundary loop, no zero-area face (needles are fine: their beta are clamped to
    minimum_angle); vertices no face uses get NaN rows in uv.
    method: "abf++" solves each Newton step through the reduced system of ABF++ (CHOLMOD on a
    2 x #interior-vertices SPD matrix); "abf" solves the full KKT system by sparse LU, its
    unknowns ordered angles first (the same iterates, about twice as slow: for comparison). max_iterations bounds the Newton iterations;
    tolerance is on the constraint residual (infinity-norm, see :class:`AbfResult`).
    minimum_angle (radians, in (0, pi/6)) clamps beta. progress: optional callable
    ``(fraction, stage) -> bool`` called once per Newton iteration (stage
    "ABF++ Newton iteration k, residual r") and, for "abf", around each factorization,
    throttled to one call per 50 ms; returning False raises :class:`meshsmith.Cancelled`, and
    Ctrl-C raises KeyboardInterrupt at the next call.

    Returns an :class:`AbfResult`. Raises InputError for a closed mesh (cut it first with
    ``parametrization.cut_to_disk``), several boundary loops or components, a non-manifold or
    non-oriented mesh (clean it with ``meshsmith.repair.clean``), a face repeating a vertex or of zero area, or bad
    options; SolverError
    if the residual is still above tolerance after max_iterations (the message gives it).
    """
    mesh = on_referenced_vertices(V, F)
    result = _core.abf(mesh.V, mesh.F, method, max_iterations, _arguments.real(tolerance, "tolerance"),
                         _arguments.real(minimum_angle, "minimum_angle"), progress)
    return AbfResult(**{**result, "uv": mesh.to_input_rows(result["uv"])})


def uv_from_angles(F: ArrayLike, angles: ArrayLike, *, n_vertices: int | None = None, pinned: ArrayLike | None = None,
                   pinned_uv: ArrayLike | None = None) -> FloatArray:
    """Planar layout of triangles with prescribed angles (the last step of ABF++, §5.1.3).

    For every face the sine law and the angle at one corner give a linear equation between
    its three UV positions; the 2m equations are solved in the least-squares sense with two
    pinned vertices. Angles satisfying ABF's conditions are reproduced exactly.

    F: (m, 3) int array. angles: (m, 3) float array in (0, pi), column k at corner k.
    n_vertices: number of vertices (default: max index + 1). Vertices no face uses get NaN rows
    (the layout is made on the used ones, as the other parametrizations do).
    pinned: two vertex indices, used by some face (default: F[0, 0] and F[0, 1]); pinned_uv:
    (2, 2) their positions (default (0, 0) and (1, 0)).
    Returns (n_vertices, 2) float UV. Raises InputError for bad shapes, an angle outside
    (0, pi), bad pins or a pin on an unused vertex; SolverError if the faces are not edge-connected.
    """
    faces = _arguments.index_array(F, "F", 3)
    count = (int(faces.max()) + 1 if faces.size else 0) if n_vertices is None else n_vertices
    if (faces.size == 0 or faces.min() < 0 or not isinstance(count, (int, np.integer)) or isinstance(count, bool)
            or count < faces.max() + 1 or count > _arguments.MAX_ELEMENTS):
        return _core.uv_from_angles(F, angles, n_vertices, pinned, pinned_uv)  # the binding names what is wrong
    vertex_map, new_index = referenced_indices(faces, int(count))
    if new_index is None:
        return _core.uv_from_angles(F, angles, n_vertices, pinned, pinned_uv)  # the binding checks every argument
    if pinned is not None:
        pins = _arguments.index_array(pinned, "pinned")
        used = np.zeros(int(count), dtype=bool)
        used[vertex_map] = True
        for pin in pins:
            if 0 <= pin < count and not used[pin]:
                raise InputError(f"pinned vertex {int(pin)} is used by no face: pin two vertices of the faces")
        pinned = np.where((pins >= 0) & (pins < count), new_index[np.clip(pins, 0, int(count) - 1)], pins)
    uv = _core.uv_from_angles(new_index[faces], angles, len(vertex_map), pinned, pinned_uv)
    out = np.full((int(count), 2), np.nan)
    out[vertex_map] = uv
    return out
