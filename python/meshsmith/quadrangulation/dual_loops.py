"""Dual-loop quad layouts: loops traced along a cross field, selected until every region is a disk
with at most one singularity, and the dual of their arrangement as a coarse quad layout (§5.3;
Campen, Bommes & Kobbelt 2012); C++ src/quadrangulation/dual_loops.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import quadrangulation as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from ..repair.unreferenced import on_referenced_vertices
from .cross_field import FieldLike, field_angles

__all__ = ["DualLoopReport", "DualLoopLayout", "dual_loop_layout"]


@dataclass(frozen=True)
class DualLoopReport(Unpackable):
    """What :func:`dual_loop_layout` selected and what its dual is; unpacks in field order.

    loops, crossings, segments (loop pieces between consecutive crossings), regions: counts of the
    arrangement; parallel_crossings: crossings of two loops of one family (0 unless allowed). region_euler, region_singularities, region_corners: (regions,) int64 per region its
    Euler characteristic (1: a disk), the singular vertices inside it, and the crossings on its
    boundary (its valence as a layout vertex). non_disk_regions, multi_singular_regions: regions
    with χ ≠ 1 / more than one singularity. degenerate_quads (a repeated vertex), non_manifold_edges
    (not shared by exactly two quads in opposite directions), non_manifold_vertices (quads around
    it not one fan), low_valence_vertices (valence 2: two quads sharing two edges): defects of the
    layout (regions at a defect count as faulty in the selection). euler_input, euler_layout: χ of the input and of the
    layout. seeds_tried, seeds_failed: seeds traced, and those that gave no usable loop, of which
    seeds_unclosed found no closed path back to the seed in its direction class and
    seeds_overlapping only ones that revisit a vertex (a self-overlap).
    max_distance_to_loops: the largest distance of a vertex to the nearer loop family; spacing:
    the spacing used (input units). failure: "" when complete, else where the layout falls short.
    regions_valid: every region is a disk with at most one singularity; complete: regions valid and
    the layout is a manifold quad mesh with the input's χ and no vertex of valence 2.
    """

    loops: int
    crossings: int
    parallel_crossings: int
    segments: int
    regions: int
    region_euler: IndexArray
    region_singularities: IndexArray
    region_corners: IndexArray
    non_disk_regions: int
    multi_singular_regions: int
    degenerate_quads: int
    non_manifold_edges: int
    non_manifold_vertices: int
    low_valence_vertices: int
    euler_input: int
    euler_layout: int
    seeds_tried: int
    seeds_failed: int
    seeds_unclosed: int
    seeds_overlapping: int
    max_distance_to_loops: float
    spacing: float
    failure: str
    regions_valid: bool
    complete: bool


@dataclass(frozen=True)
class DualLoopLayout(Unpackable):
    """The result of :func:`dual_loop_layout`; unpacks as ``loops, region, Vq, Q, report``.

    loops: list of (k,) int64 arrays, each a closed path of input vertices (consecutive entries and
    the last and first joined by mesh edges); loop_crossings: per loop, the (c,) int64 positions in
    it where another loop crosses; loop_lengths: (loops,) float64 in input units; region: (m,)
    int64 the region of each face; Vq: (r, 3) float64 layout vertices, one per region (its singular
    vertex, else its vertex farthest from the loops), at input vertices Vq_vertex (r,) int64; Q:
    (c, 4) int64 layout quads, one per crossing (the regions around it, counter-clockwise), centred
    at input vertex Q_vertex (c,) int64; singular_vertices, singular_indices: the field's
    singularities (quarter turns); report: a :class:`DualLoopReport`.
    """

    unpacks = ("loops", "region", "Vq", "Q", "report")
    loops: list[IndexArray]
    loop_crossings: list[IndexArray]
    loop_lengths: FloatArray
    region: IndexArray
    Vq: FloatArray
    Vq_vertex: IndexArray
    Q: IndexArray
    Q_vertex: IndexArray
    singular_vertices: IndexArray
    singular_indices: IndexArray
    report: DualLoopReport


@_arguments.real_options
def dual_loop_layout(V: ArrayLike, F: ArrayLike, field: FieldLike, *, spacing: float | None = None,
                     anisotropy: float = 4.0, max_deviation: float = 70.0, max_loops: int = 300,
                     max_failed_seeds: int = 2000, parallel_crossing_penalty: float | None = None,
                     progress: ProgressCallback = None) -> DualLoopLayout:
    """A coarse quad layout from dual loops along a cross field (§5.3; Campen, Bommes & Kobbelt 2012).

    Loops are closed edge paths following one direction of the field: each is the shortest closed
    path through a seed vertex in a metric where travel along the field costs its length and travel
    across it ``anisotropy`` times more (edges more than ``max_deviation`` degrees off are not
    taken), returning with the same direction class after the period jumps. They avoid singular
    vertices, share no edge, never revisit a vertex, and cross only transversally and orthogonally
    at vertices. Seeds are chosen greedily, farthest (geodesically) from the loops of their family,
    within a faulty region while one exists, until every region cut by the loops is a disk with at
    most one singularity and no vertex is farther than 0.75·spacing from a loop. The layout is the
    arrangement's dual: a vertex per region, a quad per crossing.

    V: (n, 3) float array, F: (m, 3) integer array, a clean, connected, oriented, closed manifold;
    field: a :class:`CrossField`, (m,) angles or (m, 3) directions (as :func:`cross_field`).
    spacing: target distance between neighbouring loops of one family, in input units (about the
    layout's edge length); None: sqrt(area) / 4. max_loops, max_failed_seeds: when to give up.
    parallel_crossing_penalty: None (default): loops of one family never cross; a number ≥ 0: they
    may, at that extra cost × spacing (sheared layout quads there, counted in the report).
    progress: optional callback (fraction, stage) -> bool (False cancels).
    Returns a :class:`DualLoopLayout` (unpacks as ``loops, region, Vq, Q, report``);
    ``report.complete`` says the layout is a manifold quad mesh with the input's Euler
    characteristic and every region a disk with at most one singularity; otherwise
    ``report.failure`` says where it falls short. Raises InputError as :func:`cross_field`, for a
    mesh with boundary, a field with NaN or of the wrong size, spacing ≤ 0, anisotropy < 1,
    max_deviation outside (0, 90); Cancelled from `progress`.
    """
    theta = field_angles(V, F, field)
    length = 0.0
    if spacing is not None:
        length = float(spacing)
        if not (np.isfinite(length) and length > 0):
            raise InputError(f"dual_loop_layout: spacing must be a finite number > 0, got {spacing}")
    penalty = -1.0
    if parallel_crossing_penalty is not None:
        penalty = float(parallel_crossing_penalty)
        if not (np.isfinite(penalty) and penalty >= 0):
            raise InputError(f"dual_loop_layout: parallel_crossing_penalty must be None or a finite number >= 0, "
                             f"got {parallel_crossing_penalty}")
    mesh = on_referenced_vertices(V, F)
    out = _core.dual_loop_layout(mesh.V, mesh.F, theta, spacing=length, anisotropy=anisotropy,
                                 max_deviation=max_deviation, max_loops=max_loops,
                                 max_failed_seeds=max_failed_seeds, parallel_crossing_penalty=penalty,
                                 progress=_arguments.progress(progress))
    to_input = mesh.to_input_indices
    return DualLoopLayout(
        loops=[to_input(loop) for loop in out["loops"]], loop_crossings=list(out["loop_crossings"]),
        loop_lengths=np.asarray(out["loop_lengths"], dtype=np.float64), region=out["region"], Vq=out["Vq"],
        Vq_vertex=to_input(out["Vq_vertex"]), Q=out["Q"], Q_vertex=to_input(out["Q_vertex"]),
        singular_vertices=to_input(out["singular_vertices"]), singular_indices=out["singular_indices"],
        report=DualLoopReport(**out["report"]))
