"""Incremental decimation with error quadrics (§4.2): greedy edge or half-edge collapses; binding cpp/python/decimation_qem.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, NamedTuple, overload

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import decimation as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from ..core import Mesh

__all__ = ["DecimationReport", "DecimatedMesh", "decimate"]


@dataclass
class DecimationReport(Unpackable):
    """What :func:`decimate` did (``return_report=True``). Unpacks in field order.

    vertex_origin: (n',) int64, the input vertex each output vertex was (output vertices are
    input vertices that survived, possibly moved). max_error: the largest cost of a performed
    collapse (for ``cost="quadric"`` in length² units: a sum of squared distances to the planes of
    the merged input faces, each weighted by its area over the mean face area); +inf when it
    exceeds the double range (a length² cost from coordinates of about 1e154 on), and then
    ``max_error_normalized · 2**max_error_exponent`` still states it: the cost in the normalized
    frame the decimation ran in (core/normalization.h) and the power of two that maps it to input
    units. target_reached: whether ``target_faces`` was reached (False when ``max_error`` stopped
    it first or no further collapse was admissible). collapse_count: collapses performed. split_vertex_origin: empty, or
    when the input had non-manifold or inconsistently oriented vertices, the input vertex of each
    working vertex (the input's followed by the copies made to split them). collapses: with
    ``record_collapses=True``, the collapses in order as arrays ``removed, kept, left, right``
    (k,) int64 (−1 where a side is boundary; indices of working vertices) and
    ``removed_position, kept_position_before, kept_position_after`` (k, 3) float64 — the vertex
    splits of a progressive mesh read backwards (§4.3); else None.
    """

    vertex_origin: IndexArray
    max_error: float
    target_reached: bool
    collapse_count: int
    split_vertex_origin: IndexArray
    collapses: dict[str, np.ndarray] | None = None
    max_error_normalized: float = 0.0
    max_error_exponent: int = 0


class DecimatedMesh(NamedTuple):
    """Result of :func:`decimate` with ``return_report=True``; unpacks as ``V, F, report``."""

    V: FloatArray
    F: IndexArray
    report: DecimationReport


@overload
def decimate(V: ArrayLike, F: ArrayLike, *, target_faces: int | None = ..., ratio: float | None = ...,
             max_error: float | None = ..., operator: str = ..., cost: str = ..., candidates: int | None = ...,
             prevent_normal_flips: bool = ..., max_normal_deviation: float | None = ...,
             min_quality: float | None = ..., max_valence: int | None = ..., keep_boundary: bool = ...,
             seed: int = ..., record_collapses: bool = ..., return_report: Literal[False] = ...,
             parallel: bool = ..., progress: ProgressCallback = ...) -> Mesh: ...
@overload
def decimate(V: ArrayLike, F: ArrayLike, *, target_faces: int | None = ..., ratio: float | None = ...,
             max_error: float | None = ..., operator: str = ..., cost: str = ..., candidates: int | None = ...,
             prevent_normal_flips: bool = ..., max_normal_deviation: float | None = ...,
             min_quality: float | None = ..., max_valence: int | None = ..., keep_boundary: bool = ...,
             seed: int = ..., record_collapses: bool = ..., return_report: Literal[True],
             parallel: bool = ..., progress: ProgressCallback = ...) -> DecimatedMesh: ...
def decimate(V: ArrayLike, F: ArrayLike, *, target_faces: int | None = None, ratio: float | None = None,
             max_error: float | None = None, operator: str = "edge", cost: str = "quadric",
             candidates: int | None = None, prevent_normal_flips: bool = True,
             max_normal_deviation: float | None = None, min_quality: float | None = None,
             max_valence: int | None = None, keep_boundary: bool = True, seed: int = 0,
             record_collapses: bool = False, return_report: bool = False, parallel: bool = True,
             progress: ProgressCallback = None) -> Mesh | DecimatedMesh:
    """Decimate a triangle mesh by greedy edge collapses ordered by error quadrics (§4.2).

    V: (n, 3) float array of vertex positions. F: (m, 3) int array of triangles.
    Stop rules (at least one): ``target_faces`` (int >= 1) or ``ratio`` (in (0, 1]: target
    ``round(ratio·m)`` faces, at least 1), not both; ``max_error`` (> 0, units of the cost: for
    the quadric, length², see :class:`DecimationReport`) stops when the cheapest collapse costs
    more. operator: ``"edge"`` (merged vertex at the quadric's optimal point, pseudo-inverse when
    singular) or ``"halfedge"`` (merged into one endpoint, positions are a subset of the input).
    cost: ``"quadric"`` (Garland–Heckbert), ``"plane_distance"`` (distance to the least-squares
    plane of the two one-rings) or ``"volume_change"`` (|swept volume|). candidates: k >= 1 for
    multiple-choice decimation (best of k random edges per step, Wu & Kobbelt), None for the full
    priority queue; seed: its random stream.
    Fairness criteria (§4.2.3): prevent_normal_flips (default True); max_normal_deviation
    (degrees a face normal may turn per collapse); min_quality (reject collapses that make a
    face's 4√3·area/Σedge² lower than this and lower than before); max_valence; keep_boundary
    (boundary vertices only slide along the boundary; default True). The link condition always
    holds: a manifold mesh stays manifold with the same Euler characteristic.
    parallel: on meshes of 100,000 faces or more (quadric cost, full queue), the first 95% of the
    collapses, down to no fewer than 20,000 faces, run on four spatial parts at once, in rounds
    under a common cost ceiling, and a serial greedy run does the part borders and the rest
    (1.3–1.4× faster on 2 cores at 1.3M faces; the result does not depend on the thread
    count). False: one serial greedy run, the strict cheapest-first order.
    Faces with a repeated index are dropped; non-manifold or inconsistently oriented vertices
    are split into one copy per fan first (nothing is torn further). Unreferenced vertices are
    dropped. progress: optional callable ``(fraction, stage) -> bool | None``; returning False
    raises :class:`meshsmith.Cancelled`.

    Returns a :class:`meshsmith.core.Mesh` (V', F'): (n', 3) float64 and (m', 3) int64; with
    ``return_report=True`` a :class:`DecimatedMesh` (V', F', :class:`DecimationReport`).
    Raises InputError for bad input or an impossible request (no stop rule, target 0, ratio
    outside (0, 1], both target_faces and ratio, an unknown operator or cost, a negative option,
    no face without a repeated index).
    """
    if target_faces is not None and ratio is not None:
        raise InputError("decimate: give target_faces or ratio, not both")
    target = 0
    if ratio is not None:
        ratio = _arguments.real(ratio, "ratio")
        if not 0 < ratio <= 1:
            raise InputError(f"decimate: ratio must be in (0, 1], got {ratio}")
        target = max(1, int(round(ratio * len(_arguments.index_array(F, "F", 3)))))
    elif target_faces is not None:
        target = _arguments.integer(target_faces, "target_faces", 1, 2 ** 63 - 1)
    if max_error is not None:
        max_error = _arguments.real(max_error, "max_error")
    if max_error is not None and not max_error > 0:
        raise InputError(f"decimate: max_error must be > 0, got {max_error}")
    if target == 0 and max_error is None:
        raise InputError("decimate: no stop rule: give target_faces, ratio or max_error")
    if candidates is not None:  # the binding bounds it from above
        candidates = _arguments.integer(candidates, "candidates (None: the full priority queue)", 1, 2 ** 31 - 1)
    V2, F2, report = _core.decimate_qem(
        V, F, target_faces=target, max_error=max_error or 0.0, operator=operator, cost=cost,
        candidates=candidates or 0, seed=seed, prevent_normal_flips=prevent_normal_flips,
        max_normal_deviation_deg=0.0 if max_normal_deviation is None else _arguments.real(max_normal_deviation, "max_normal_deviation"),
        min_triangle_quality=0.0 if min_quality is None else _arguments.real(min_quality, "min_quality"),
        max_valence=max_valence or 0, keep_boundary=keep_boundary,
        record_collapses=record_collapses, parallel=parallel, progress=progress)
    if not return_report:
        return Mesh(V2, F2)
    return DecimatedMesh(V2, F2, DecimationReport(
        vertex_origin=report["vertex_origin"], max_error=report["max_error"],
        target_reached=report["target_reached"], collapse_count=report["collapse_count"],
        split_vertex_origin=report["split_vertex_origin"], collapses=report.get("collapses"),
        max_error_normalized=report["max_error_normalized"], max_error_exponent=report["max_error_exponent"]))
