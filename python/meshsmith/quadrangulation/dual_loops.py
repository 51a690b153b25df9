"""Dual-loop quad layouts: loops traced along a cross field, selected until every region is a disk
with at most one singularity, and the dual of their arrangement as a coarse quad layout (§5.3;
Campen, Bommes & Kobbelt 2012); C++ src/quadrangulation/dual_loops.cpp.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import quadrangulation as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from ..datasets import _split_in_four
from ..geometry import gaussian_curvature, surface_area
from ..repair.unreferenced import ReferencedMesh, on_referenced_vertices
from .cross_field import (CrossField, FieldLike, _carry_index, _edge_rows, field_angles, merge_singularities,
                          singularities)

__all__ = ["DualLoopReport", "DualLoopLayout", "DualLoopAttempt", "DUAL_LOOP_SCHEDULE", "dual_loop_layout",
           "RefinedField", "refine_field"]


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
    attempts: the option sets of ``DUAL_LOOP_SCHEDULE`` tried (1 when the first gave a complete
    layout); merge, refine, parallel_crossing_penalty (inf: no parallel crossings),
    max_failed_seeds: the options of the attempt returned.
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
    attempts: int
    merge: float
    refine: int
    parallel_crossing_penalty: float
    max_failed_seeds: int


@dataclass(frozen=True)
class DualLoopLayout(Unpackable):
    """The result of :func:`dual_loop_layout`; unpacks as ``loops, region, Vq, Q, report``.

    loops: list of (k,) int64 arrays, each a closed path of input vertices (consecutive entries and
    the last and first joined by mesh edges); loop_crossings: per loop, the (c,) int64 positions in
    it where another loop crosses; loop_lengths: (loops,) float64 in input units; region: (m,)
    int64 the region of each face; Vq: (r, 3) float64 layout vertices, one per region (its singular
    vertex, else its vertex farthest from the loops, else — every vertex of the region on a loop —
    the centroid of its largest face), at input vertices Vq_vertex (r,) int64 (for a centroid: that
    face's nearest corner); Q:
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
    V_traced: FloatArray
    F_traced: IndexArray
    face_parent: IndexArray
    theta: FloatArray


def _face_directions(V: ArrayLike, F: ArrayLike, theta: ArrayLike) -> FloatArray:
    """(m, 3) float64 unit vectors at the angles θ (m,) in each face's frame (against the
    reference edge F[f,0] → F[f,1], counter-clockwise about the face normal), as
    :attr:`CrossField.directions`. V, F: a validated mesh without zero-area faces."""
    P, T = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    e1 = (b - a) / np.linalg.norm(b - a, axis=1, keepdims=True)
    t = np.asarray(theta, dtype=np.float64)[:, None]
    return np.asarray(np.cos(t) * e1 + np.sin(t) * np.cross(normal, e1), dtype=np.float64)


@dataclass(frozen=True)
class RefinedField(Unpackable):
    """The result of :func:`refine_field`; unpacks as ``V, F, theta, parent``.

    V: (n', 3) float64, F: (m', 3) int64 the split mesh; theta: (m',) float64 the carried field's
    angles in F's frames; parent: (m',) int64 the input face of each face.
    """

    V: FloatArray
    F: IndexArray
    theta: FloatArray
    parent: IndexArray


def refine_field(V: ArrayLike, F: ArrayLike, field: FieldLike, *, times: int = 1) -> RefinedField:
    """The mesh split 1-to-4 at its edge midpoints `times` times with the cross field carried over:
    a :class:`RefinedField` (V2, F2, theta2, parent). Children are coplanar with their parent, so each keeps the parent's
    cross exactly; the field's singularities stay on the input's vertices (a midpoint sees its two
    faces' crosses, whose jump it crosses twice: index 0), and two singularities on neighbouring
    input vertices get a regular vertex between them, through which a loop can pass (§5.3).
    V: (n, 3), F: (m, 3); field as :func:`dual_loop_layout`. V2 (n', 3): V's referenced vertices
    in order, then the midpoints; F2 (4^times·m, 3); theta2: angles in F2's frames; parent (4^times·m,)
    int64: the input face of each. Raises InputError as :func:`field_angles`, for times outside [0, 3].
    """
    times = _arguments.integer(times, "times", 0, 3)
    mesh = on_referenced_vertices(V, F)
    P, T = np.asarray(mesh.V, dtype=np.float64), np.asarray(mesh.F, dtype=np.int64)
    theta = field_angles(P, T, field)
    singularities(P, T, theta)  # the checks of the field's mesh (zero-area faces, manifold) before the splits
    directions = _face_directions(P, T, theta)
    parent = np.arange(len(T), dtype=np.int64)
    for _ in range(times):
        P, T = _split_in_four(P, T)
        parent, directions = np.tile(parent, 4), np.tile(directions, (4, 1))  # children: corners a, b, c, middle
    return RefinedField(V=P, F=T, theta=field_angles(P, T, directions), parent=parent)


def _separate_neighbouring_pairs(P: np.ndarray, T: np.ndarray, theta: np.ndarray, reach: float) -> np.ndarray:
    """theta (m,) with each ±1 pair of singularities on neighbouring vertices pulled apart: the
    member whose index fits its vertex's angle defect less moves to a vertex about `reach` from
    the other (index 0, |angle defect| < 0.5 rad, none of the other singularities within 0.8·reach),
    through period jumps changed along the shortest path, and the angles within 2·reach re-solved
    with those jumps fixed (as merge_singularities). The input theta if no pair or if the re-solve
    does not give exactly the intended singularities. P, T: a closed mesh without unreferenced vertices.

    Why: merge_singularities leaves such pairs where one vertex has a large angle defect (kitten's
    +1 at valence-3 and -4 vertices of 1.6–2.5 rad next to −1 at −0.8 to −1.3 rad): its re-solve
    brings them back, and no edge loop passes between neighbours. Measured (merge=1.5, refine=1,
    parallel_crossing_penalty=4, max_failed_seeds=300, reach half a spacing): kitten's 3 pairs moved
    apart, its layout complete (12 loops, 111 quads, χ 0); rocker-arm's pair moved but still in one
    region; pmp-bunny complete either way.
    """
    import scipy.sparse
    import scipy.sparse.csgraph

    dijkstra: Any = scipy.sparse.csgraph.dijkstra
    n = len(P)
    computed = _core.field_edges(P, T, theta)
    edges = np.asarray(computed["edges"], dtype=np.int64)
    edge_faces = np.asarray(computed["edge_faces"], dtype=np.int64)
    connection = np.asarray(computed["connection"], dtype=np.float64)
    vertices, indices = _core.singularities(P, T, theta)
    index = np.zeros(n, dtype=np.int64)
    index[np.asarray(vertices, dtype=np.int64)] = indices
    adjacent = {(int(a), int(b)) for a, b in edges.tolist()}
    pairs = [(int(a), int(b)) for a in vertices for b in vertices
             if a < b and index[a] * index[b] == -1 and (int(a), int(b)) in adjacent]
    if not pairs:
        return theta
    jumps = np.round((theta[edge_faces[:, 1]] - theta[edge_faces[:, 0]] - connection) / (np.pi / 2)).astype(np.int64)
    defect = gaussian_curvature(P, T)
    length = np.linalg.norm(P[edges[:, 1]] - P[edges[:, 0]], axis=1)
    graph = scipy.sparse.coo_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    edge_row = _edge_rows(edges, n)
    moved: list[int] = []
    for a, b in pairs:
        if index[a] == 0 or index[b] == 0:
            continue
        stay, go = (a, b) if defect[a] * index[a] >= defect[b] * index[b] else (b, a)
        from_stay = dijkstra(graph, directed=False, indices=stay, limit=3 * reach)
        from_go, row = dijkstra(graph, directed=False, indices=go, limit=3 * reach, return_predecessors=True)
        target = np.isfinite(from_stay) & np.isfinite(from_go) & (index == 0) & (np.abs(defect) < 0.5)
        others = [int(v) for v in np.flatnonzero(index) if v not in (stay, go)]
        if others:
            target &= ~(dijkstra(graph, directed=False, indices=others, min_only=True, limit=reach) < 0.8 * reach)
        score = np.where(target, np.abs(from_stay - reach) + 0.5 * from_go, np.inf)
        t = int(np.argmin(score))
        if not np.isfinite(score[t]):
            continue
        _carry_index(jumps, edge_row, row, go, t, int(index[go]))
        index[t], index[go] = index[go], 0
        moved.extend([stay, go, t])
    if not moved:
        return theta
    near = dijkstra(graph, directed=False, indices=np.unique(moved), limit=2 * reach, min_only=True)
    free = np.isfinite(near)[T].any(axis=1)
    resolved = _core.resolve_angles(P, T, theta, jumps, ~free)
    intended = np.flatnonzero(index)
    if not (np.array_equal(np.asarray(resolved["singular_vertices"], dtype=np.int64), intended)
            and np.array_equal(np.asarray(resolved["singular_indices"], dtype=np.int64), index[intended])):
        return theta
    return np.asarray(resolved["theta"], dtype=np.float64)


class DualLoopAttempt(NamedTuple):
    """The options one attempt of :func:`dual_loop_layout` uses (an entry of ``DUAL_LOOP_SCHEDULE``).

    merge: singularities closer than merge × spacing merged first (0: none); refine: 1-to-4 splits
    before tracing; parallel_crossing_penalty: the extra cost × spacing of two loops of one family
    crossing (inf: they never cross); max_failed_seeds: when the selection gives up.
    """

    merge: float
    refine: int
    parallel_crossing_penalty: float
    max_failed_seeds: int


#: The option sets :func:`dual_loop_layout` tries in order, until a layout is complete (for the
#: options the caller leaves None). Measured 2026-12-04 (smooth fields, spacing √area/4, one run
#: each, load 1-5 on 2 cores), layout quads and seconds of each attempt where it is complete:
#: 1. merge 1.5 on the input mesh without parallel crossings (the CLI's setting before the schedule,
#:    with 300 failed seeds instead of 2,000): cheap, no sheared quads, loops on the input's
#:    vertices. Complete: spot 58 (0.1 s), fandisk 62 (0.4-0.7 s), bumpy-cube 34 (0.9 s); not
#:    kitten, rocker-arm, fertility, pmp-bunny (3.7 s spent), cheburashka, bunny, armadillo.
#: 2. merge 1.5, the mesh split 1-to-4, parallel crossings at 4: the set that alone completes the
#:    most meshes (9 of 14: also spot 58, fandisk 54, bumpy-cube 58). Complete: kitten 111 (0.5 s),
#:    fertility 172 (4.0 s), pmp-bunny 96 (2.8 s), cheburashka 132, bunny 60, armadillo 144 (4.6 s);
#:    not rocker-arm (a ±1 pair still shares a region).
#: 3. merge 2.5, likewise: rocker-arm 19 (3.7 s; 4 singularities left). First, it would leave spot
#:    and kitten a valence-2 layout vertex and fertility regions with several cones.
#: 4. merge 1.0, likewise (alone it completes kitten 97, armadillo 342; not rocker-arm or fertility).
#: 5. the field as it is, on the input mesh, no parallel crossings, 2,000 failed seeds (the defaults
#:    before the schedule): torus.obj 168 (0.35 s), whose 8 singularities every merge above cancels,
#:    leaving a field on which the selected loops never cross (0 layout quads); here its loops
#:    close after 1,726 unclosed seeds. Alone it completes none of the meshes above.
#: None of them completes bob_tri, decimated-knight (158 singularities at 1,000 faces) or
#: decimated-max.
DUAL_LOOP_SCHEDULE: tuple[DualLoopAttempt, ...] = (
    DualLoopAttempt(merge=1.5, refine=0, parallel_crossing_penalty=math.inf, max_failed_seeds=300),
    DualLoopAttempt(merge=1.5, refine=1, parallel_crossing_penalty=4.0, max_failed_seeds=300),
    DualLoopAttempt(merge=2.5, refine=1, parallel_crossing_penalty=4.0, max_failed_seeds=300),
    DualLoopAttempt(merge=1.0, refine=1, parallel_crossing_penalty=4.0, max_failed_seeds=300),
    DualLoopAttempt(merge=0.0, refine=0, parallel_crossing_penalty=math.inf, max_failed_seeds=2000),
)


def _faults(report: DualLoopReport) -> int:
    """How far a layout is from complete: faulty regions, defects of the dual, |χ − χ_input|, no crossing."""
    return (report.non_disk_regions + report.multi_singular_regions + report.degenerate_quads
            + report.non_manifold_edges + report.non_manifold_vertices + report.low_valence_vertices
            + abs(report.euler_layout - report.euler_input) + (report.crossings == 0))


@_arguments.real_options
def dual_loop_layout(V: ArrayLike, F: ArrayLike, field: FieldLike, *, spacing: float | None = None,
                     anisotropy: float = 4.0, max_deviation: float = 70.0, max_loops: int = 300,
                     max_failed_seeds: int | None = None, parallel_crossing_penalty: float | None = None,
                     merge: float | None = None, refine: int | None = None,
                     progress: ProgressCallback = None) -> DualLoopLayout:
    """A coarse quad layout from dual loops along a cross field (§5.3; Campen, Bommes & Kobbelt 2012).

    Loops are closed edge paths following one direction of the field: each is the shortest closed
    path through a seed vertex in a metric where travel along the field costs its length and travel
    across it ``anisotropy`` times more (edges more than ``max_deviation`` degrees off are not
    taken), returning with the same direction class after the period jumps. They avoid singular
    vertices, share no edge, never revisit a vertex, and cross only transversally and orthogonally
    at vertices. Seeds are chosen greedily, farthest (geodesically) from the loops of their family,
    within a faulty region while one exists, until every region cut by the loops is a disk with at
    most one singularity and no vertex is farther than 0.75·spacing from a loop; then a loop at a
    layout vertex of valence 2 is dropped where that lowers the layout's faults (where valence 2 is
    the only fault left, with the selection run again). The layout is the arrangement's dual: a
    vertex per region, a quad per crossing.

    The options merge, refine, parallel_crossing_penalty and max_failed_seeds left None are taken
    from ``DUAL_LOOP_SCHEDULE``, whose option sets are tried in order until the layout is complete
    (those given are used in every attempt; with all four given, one attempt); the attempt with the
    fewest faults is returned, ``report.attempts`` says how many were made and ``report.merge``,
    ``report.refine``, ... which one it is. With the defaults and a smooth field (``cross_field(V,
    F, align="smooth")``) the layout is complete on spot, fandisk and bumpy-cube at the first
    attempt (0.1-0.4 s), on kitten (0.6 s), fertility (4.3 s), pmp-bunny (4.3 s), cheburashka,
    bunny and armadillo at the second, on rocker-arm at the third (8.4 s), on torus.obj at the
    fifth (measured 2026-12-04, load 1-3 on 2 cores); not on bob_tri, decimated-knight or
    decimated-max (every attempt made, the one with the fewest faults returned).

    V: (n, 3) float array, F: (m, 3) integer array, a clean, connected, oriented, closed manifold;
    field: a :class:`CrossField`, (m,) angles or (m, 3) directions (as :func:`cross_field`).
    spacing: target distance between neighbouring loops of one family, in input units (about the
    layout's edge length); None: sqrt(area) / 4. max_loops, max_failed_seeds: when to give up.
    parallel_crossing_penalty: a number ≥ 0: loops of one family may cross, at that extra cost ×
    spacing (sheared layout quads there, counted in the report); ``math.inf``: they never cross.
    merge: when > 0, the field (a :class:`CrossField`) first has its singularities closer than
    merge × spacing cancelled or moved apart (:func:`merge_singularities`): a ±1 pair closer than
    the loops' spacing would need two loops between them; a ±1 pair it leaves on neighbouring
    vertices (no edge loop passes between them) is then pulled half a spacing apart; 0: the field
    as it is (the schedule's value when the field is not a CrossField). refine: 1-to-4 midpoint
    splits of the mesh before tracing (:func:`refine_field`, 0 to 3): loops then also run through
    the input's triangles (via edge midpoints) and can pass between singularities on neighbouring
    vertices; the result is then on the refined mesh (``V_traced``, ``F_traced``: check which
    mesh the returned attempt traced on).
    progress: optional callback (fraction, stage) -> bool (False cancels).
    Returns a :class:`DualLoopLayout` (unpacks as ``loops, region, Vq, Q, report``);
    ``report.complete`` says the layout is a manifold quad mesh with the input's Euler
    characteristic and every region a disk with at most one singularity; otherwise
    ``report.failure`` says where it falls short. Raises InputError as :func:`cross_field`, for a
    mesh with boundary, a field with NaN or of the wrong size, spacing ≤ 0, anisotropy < 1,
    max_deviation outside (0, 90), parallel_crossing_penalty < 0 or NaN, merge < 0 or > 0 with a
    field that is not a CrossField, refine outside [0, 3], max_failed_seeds < 0; Cancelled from
    `progress`.
    """
    theta = field_angles(V, F, field)
    length = 0.0
    if spacing is not None:
        length = float(spacing)
        if not (np.isfinite(length) and length > 0):
            raise InputError(f"dual_loop_layout: spacing must be a finite number > 0, got {spacing}")
    if merge is not None:
        if not (np.isfinite(merge) and merge >= 0):
            raise InputError(f"dual_loop_layout: merge must be a finite number >= 0, got {merge}")
        if merge > 0 and not isinstance(field, CrossField):
            raise InputError("dual_loop_layout: merge needs the field as a CrossField (from cross_field)")
    if refine is not None:
        refine = _arguments.integer(refine, "refine", 0, 3)
    if parallel_crossing_penalty is not None and not parallel_crossing_penalty >= 0:
        raise InputError(f"dual_loop_layout: parallel_crossing_penalty must be None, a number >= 0 or inf, "
                         f"got {parallel_crossing_penalty}")
    if max_failed_seeds is not None:
        max_failed_seeds = _arguments.integer(max_failed_seeds, "max_failed_seeds", 0, 2 ** 31 - 1)
    plans: list[DualLoopAttempt] = []
    for entry in DUAL_LOOP_SCHEDULE:  # the options given held, the merge 0 without a CrossField
        plan = DualLoopAttempt(
            merge=(entry.merge if merge is None else merge) if isinstance(field, CrossField) else 0.0,
            refine=entry.refine if refine is None else refine,
            parallel_crossing_penalty=(entry.parallel_crossing_penalty if parallel_crossing_penalty is None
                                       else parallel_crossing_penalty),
            max_failed_seeds=entry.max_failed_seeds if max_failed_seeds is None else max_failed_seeds)
        if plan not in plans:
            plans.append(plan)
    progress = _arguments.progress(progress)
    mesh = on_referenced_vertices(V, F)
    P, T = np.asarray(mesh.V, dtype=np.float64), np.asarray(mesh.F, dtype=np.int64)
    step = length if length > 0 else float(np.sqrt(surface_area(P, T))) / 4  # the C++ default spacing
    merged: dict[float, np.ndarray] = {}
    best: DualLoopLayout | None = None
    for attempt, plan in enumerate(plans):
        if plan.merge not in merged:
            trial = theta
            if plan.merge > 0:
                assert isinstance(field, CrossField)
                trial = merge_singularities(V, F, field, plan.merge * step).theta
                trial = _separate_neighbouring_pairs(P, T, trial, 0.5 * step)
            merged[plan.merge] = trial
        layout = _trace(V, F, mesh, merged[plan.merge], plan, spacing=length, anisotropy=anisotropy,
                        max_deviation=max_deviation, max_loops=max_loops,
                        progress=_arguments.stage(progress, attempt / len(plans), (attempt + 1) / len(plans)))
        if best is None or _faults(layout.report) < _faults(best.report):
            best = layout
        if layout.report.complete:
            break
    assert best is not None
    _arguments.report(progress, 1.0, "dual loops")
    return dataclasses.replace(best, report=dataclasses.replace(best.report, attempts=attempt + 1))


def _trace(V: ArrayLike, F: ArrayLike, mesh: ReferencedMesh, theta: np.ndarray, plan: DualLoopAttempt, *,
           spacing: float, anisotropy: float, max_deviation: float, max_loops: int,
           progress: ProgressCallback) -> DualLoopLayout:
    """One attempt of :func:`dual_loop_layout`: the (merged) angles theta on mesh (the input on its
    referenced vertices) split plan.refine times, the loops traced with plan's options."""
    P, T = np.asarray(mesh.V, dtype=np.float64), np.asarray(mesh.F, dtype=np.int64)
    parent = np.arange(len(T), dtype=np.int64)
    times = plan.refine
    if times:
        P, T, theta, parent = refine_field(P, T, theta, times=times)
    penalty = -1.0 if math.isinf(plan.parallel_crossing_penalty) else float(plan.parallel_crossing_penalty)
    out = _core.dual_loop_layout(P, T, theta, spacing=spacing, anisotropy=anisotropy,
                                 max_deviation=max_deviation, max_loops=max_loops,
                                 max_failed_seeds=plan.max_failed_seeds, parallel_crossing_penalty=penalty,
                                 progress=progress)
    to_input = mesh.to_input_indices if not times else (lambda indices: np.asarray(indices, dtype=np.int64))
    report = DualLoopReport(**out["report"], attempts=1, merge=float(plan.merge), refine=times,
                            parallel_crossing_penalty=float(plan.parallel_crossing_penalty),
                            max_failed_seeds=plan.max_failed_seeds)
    return DualLoopLayout(
        loops=[to_input(loop) for loop in out["loops"]], loop_crossings=list(out["loop_crossings"]),
        loop_lengths=np.asarray(out["loop_lengths"], dtype=np.float64), region=out["region"], Vq=out["Vq"],
        Vq_vertex=to_input(out["Vq_vertex"]), Q=out["Q"], Q_vertex=to_input(out["Q_vertex"]),
        singular_vertices=to_input(out["singular_vertices"]), singular_indices=out["singular_indices"],
        report=report, V_traced=np.asarray(V, dtype=np.float64) if not times else P,
        F_traced=np.asarray(F, dtype=np.int64) if not times else T, face_parent=parent,
        theta=np.asarray(theta, dtype=np.float64))
