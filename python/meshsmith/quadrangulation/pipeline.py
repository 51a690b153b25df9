"""`quadrangulate`: a triangle mesh to a pure quad mesh — cross field, MIQ, quad extraction (§5.2.2)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .. import _arguments
from .._core import InputError
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from .cross_field import cross_field, singularities
from .extraction import QuadExtractionReport, extract_quads
from .miq import miq
from .quality import quad_quality

__all__ = ["QuadrangulationReport", "Quadrangulation", "quadrangulate"]


@dataclass(frozen=True)
class QuadrangulationReport(Unpackable):
    """What :func:`quadrangulate` made, stage by stage; unpacks in field order.

    quads: faces of the result (all quads); target_faces: the number asked for (None when a
    target_edge_length was given); target_edge_length: the quad edge length MIQ used (input units);
    singular_vertices (s,) int64 and singular_indices (s,) int64: the cross field's singularities
    (indices in quarter turns: their sum is 4χ); flipped_before, flipped_after: flipped triangles of the
    MIQ map before and after its repair; extraction: the :class:`QuadExtractionReport`;
    irregular_vertices: interior vertices of the quad mesh whose valence is not 4; mean_angle_deviation,
    max_angle_deviation: over every quad corner, |angle − 90°| in degrees; min_scaled_jacobian:
    over every corner (these three are NaN when no quad was made: a grid too coarse for the
    surface). The report holds no timings, so equal calls give equal reports.
    """

    quads: int
    target_faces: int | None
    target_edge_length: float
    singular_vertices: IndexArray
    singular_indices: IndexArray
    flipped_before: int
    flipped_after: int
    extraction: QuadExtractionReport
    irregular_vertices: int
    mean_angle_deviation: float
    max_angle_deviation: float
    min_scaled_jacobian: float


@dataclass(frozen=True)
class Quadrangulation(Unpackable):
    """The result of :func:`quadrangulate`; unpacks as ``V, Q, report``.

    V: (k, 3) float64 quad-mesh vertices on the input surface; Q: (q, 4) int64 quads,
    counter-clockwise like the input; UV: (m, 3, 2) float64 the seamless map the quads were
    extracted from (per input face corner); report: a :class:`QuadrangulationReport`.
    """

    unpacks = ("V", "Q", "report")
    V: FloatArray
    Q: IndexArray
    UV: FloatArray
    report: QuadrangulationReport


def _stage(progress: ProgressCallback, begin: float, end: float) -> ProgressCallback:
    """A callback for one stage that maps its [0, 1] onto [begin, end] of `progress`."""
    if progress is None:
        return None
    callback: Callable[[float, str], Any] = progress

    def report(fraction: float, stage: str) -> Any:
        return callback(begin + (end - begin) * fraction, stage)
    return report


@_arguments.real_options
def quadrangulate(V: ArrayLike, F: ArrayLike, *, target_faces: int | None = None,
                  target_edge_length: float | None = None, align: str = "curvature",
                  sharp_angle: float | None = None, progress: ProgressCallback = None) -> Quadrangulation:
    """Quadrangulate a triangle mesh: a smooth cross field, its mixed-integer seamless
    parametrization, and the quad mesh of that map's integer grid (§5.2.2; Bommes et al. 2009,
    Ebke et al. 2013).

    V: (n, 3) float array; F: (m, 3) integer array, a clean connected oriented manifold (see
    :func:`cross_field`). target_faces: about how many quads (the grid size from the surface
    area), or target_edge_length: the quad edge length in input units; neither: MIQ's default
    (twice the mean triangle side). align, sharp_angle: as :func:`cross_field` ("curvature",
    "boundary" or "smooth"; feature edges above sharp_angle degrees are followed).
    progress: optional callback (fraction, stage) -> bool (False cancels).

    Returns a :class:`Quadrangulation` (unpacks as ``V, Q, report``): always a manifold,
    consistently oriented pure quad mesh; ``report.extraction.complete`` says it covers the
    surface with the input's Euler characteristic (where the map is degenerate the squares
    concerned are left out and counted there). Raises InputError as :func:`cross_field` and
    :func:`miq`, for both targets or target_faces outside [1, 2^24], and as :func:`extract_quads`
    for a grid of more than 2^26 unit squares; Cancelled from `progress`.
    """
    if target_faces is not None and target_edge_length is not None:
        raise InputError("quadrangulate: give target_faces or target_edge_length, not both")
    if target_faces is not None:
        target_faces = _arguments.integer(target_faces, "target_faces", 1, 2 ** 24)
    progress = _arguments.progress(progress)
    field = cross_field(V, F, align=align, sharp_angle=sharp_angle, progress=_stage(progress, 0.0, 0.15))
    singular = singularities(V, F, field)
    param = miq(V, F, field, target_edge_length=target_edge_length, target_quads=target_faces,
                progress=_stage(progress, 0.15, 0.85))
    quads = extract_quads(V, F, param.UV, progress=_stage(progress, 0.85, 1.0))
    if len(quads.Q):
        quality = quad_quality(quads.V, quads.Q)
        deviation = np.abs(quality.angles - 90.0)
        mean_deviation, max_deviation = float(deviation.mean()), float(deviation.max())
        min_jacobian = float(quality.scaled_jacobian.min())
        irregular = _irregular_vertices(quads.Q, quality.valence)
    else:
        mean_deviation = max_deviation = min_jacobian = float("nan")
        irregular = 0
    report = QuadrangulationReport(
        quads=len(quads.Q), target_faces=target_faces, target_edge_length=param.target_edge_length,
        singular_vertices=singular.vertices, singular_indices=singular.indices,
        flipped_before=param.flipped_before, flipped_after=param.flipped_after, extraction=quads.report,
        irregular_vertices=irregular, mean_angle_deviation=mean_deviation, max_angle_deviation=max_deviation,
        min_scaled_jacobian=min_jacobian)
    return Quadrangulation(quads.V, quads.Q, param.UV, report)


def _irregular_vertices(Q: IndexArray, valence: IndexArray) -> int:
    """Interior vertices of valence other than 4 (a vertex is interior when every edge at it has
    two quads)."""
    edges = np.sort(np.stack([Q, np.roll(Q, -1, axis=1)], -1).reshape(-1, 2), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    boundary = np.zeros(len(valence), dtype=bool)
    boundary[unique[counts == 1].ravel()] = True
    used = valence > 0
    return int((used & ~boundary & (valence != 4)).sum())
