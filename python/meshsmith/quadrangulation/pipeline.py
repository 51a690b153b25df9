"""`quadrangulate`: a triangle mesh to a pure quad mesh — cross field, MIQ, quad extraction (§5.2.2)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import quadrangulation as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from .cross_field import CrossField, cross_field, merge_singularities, singularities
from .extraction import QuadExtractionReport, extract_quads
from .miq import grid_length, miq
from .quality import corner_jacobians, corner_measures, quad_quality

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
    surface); merge_distance: the distance (input units) below which the field's singularity
    pairs were cancelled or moved apart (:func:`merge_singularities`; 0: not merged);
    feature_edges: feature edges held on integer iso-lines by MIQ (sharp_angle); miq_attempts:
    MIQ solves run (one per merge distance and feature setting tried); relaxed_vertices: quad
    vertices moved by the relaxation of poorly shaped quads or the smoothing (0 with ``relax=0, smooth=0``);
    min_scaled_jacobian_extracted: the minimum scaled Jacobian before that relaxation (after the doublets'
    removal); removed_doublets: interior quad vertices of valence 2 removed after the extraction, each
    with its two quads merged into one (see :func:`_remove_doublets`); map_distortion: the area-weighted
    mean Beltrami coefficient |μ| = (σ1 − σ2) / (σ1 + σ2) of the MIQ map kept (0 for a conformal map;
    see ``MAP_DISTORTION_LIMIT``). The report holds no timings, so equal calls give equal reports.
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
    merge_distance: float
    feature_edges: int
    miq_attempts: int
    relaxed_vertices: int
    min_scaled_jacobian_extracted: float
    removed_doublets: int
    map_distortion: float


#: Merge distances tried, in quad edges, until MIQ leaves no flipped triangle (the flips do not
#: fall monotonically with the distance). Largest first: every pair merged is a pair of irregular
#: vertices fewer in the quad mesh. Measured at 3,000 quads (2026-12-03, with MIQ's re-rounding,
#: over three OpenBLAS kernels × four 1e-9 perturbations of each mesh): starting at 4.0, kitten /
#: pmp-bunny / fandisk get 24–28 / 28–30 / 18–20 irregular vertices where 3.5 gave 28–30 / 36–38 /
#: 20–22 (QuadriFlow 30 / 56 / 40: at 3.5 kitten only tied it), rocker-arm and fertility the same
#: (18–22, 36; fertility folds at 4.0 and needs 3.5, a second MIQ solve), spot 48 instead of 44
#: (QuadriFlow 62); the mean quad angle deviation moves by −0.1° to +1.2° (rocker-arm 5.8° → 6.9°
#: on two of the four copies). Shorter distances remain for meshes where long merges fold; kitten at
#: 2,000 quads needs up to 2.5.
MERGE_SCHEDULE = (4.0, 3.5, 3.0, 2.5, 2.0, 1.5, 1.0, 1.25, 0.75, 0.5)

#: The merge distances tried while feature edges are held on iso-lines (sharp_angle), shortest
#: first: cones beside a feature stay where the feature needs them (the fixed feature faces keep
#: most of them anyway). Measured on fandisk at 3,000 quads, sharp_angle=40: 1.0 and 1.5 hold 675 of
#: 710 feature edges flip-free with 32 irregular vertices; 2.5–3.5 fold until the constraints are
#: dropped (34–36 irregular, 0 feature edges held).
FEATURE_MERGE_SCHEDULE = (1.0, 1.5, 2.0, 0.5, 2.5, 0.75, 1.25, 3.0, 4.0)

#: The largest mean Beltrami coefficient |μ| (area-weighted over the input's triangles) of an MIQ
#: map that ends the merge schedule: a flip-free map above it is kept only when the next distances
#: (at most ``MAP_RETRIES`` more) are worse. |μ| = 0.1 turns a right angle by up to ~11°.
#: Measured at 3,000 quads with conformal_scale=1 (2026-12-04): fertility's merge at 4 quad edges
#: (34 cones) leaves |μ| = 0.105 and quads 7.3° off square, at 3.5 (36 cones) 0.093 and 4.9°;
#: every other shared mesh's first flip-free map had 0.037–0.084 (fandisk 0.049, kitten 0.079).
MAP_DISTORTION_LIMIT = 0.1

#: Flip-free maps over ``MAP_DISTORTION_LIMIT``, or whose extraction is incomplete, after which the
#: next merge distances are tried, at most.
MAP_RETRIES = 2

#: Rounds of the tangential smoothing of the quad mesh (`smooth` of :func:`quadrangulate`) at most.
#: The smoothing had not converged at 40 rounds of step 0.5 on any of the six meshes (measured
#: 2026-12-04 at 3,000 quads, mean |angle − 90°|): 60 rounds of step 0.8 take fandisk 6.29° →
#: 5.96°, spot 4.78° → 4.25°, kitten 5.58° → 5.14°, pmp-bunny 5.02° → 4.77° for ~0.1 s more
#: (200 rounds of 0.5: 5.81°, 3.91°, 4.93°, 4.65°, for ~1 s), the same min scaled Jacobian and
#: Hausdorff distance.
SMOOTH_ROUNDS = 60

#: The smoothing's step: the fraction of the way to the neighbours' mean each round moves.
SMOOTH_STEP = 0.8


@dataclass(frozen=True)
class Quadrangulation(Unpackable):
    """The result of :func:`quadrangulate`; unpacks as ``V, Q, report``.

    V: (k, 3) float64 quad-mesh vertices on the input surface; Q: (q, 4) int64 quads,
    counter-clockwise like the input; UV: (m, 3, 2) float64 the seamless map the quads were
    extracted from (per input face corner); report: a :class:`QuadrangulationReport`; field: the
    :class:`CrossField` that map follows (the input's field after merging singularity pairs: its
    singularities are ``report.singular_vertices``).
    """

    unpacks = ("V", "Q", "report")
    V: FloatArray
    Q: IndexArray
    UV: FloatArray
    report: QuadrangulationReport
    field: CrossField


@_arguments.real_options
def quadrangulate(V: ArrayLike, F: ArrayLike, *, target_faces: int | None = None,
                  target_edge_length: float | None = None, align: str = "curvature",
                  sharp_angle: float | None = None, curvature_weight: float = 1e-3, crease_weight: float | None = None,
                  conformal_scale: float = 1.0, merge: bool = True,
                  relax: int = 30, rounding: str = "none", smooth: int = SMOOTH_ROUNDS,
                  progress: ProgressCallback = None) -> Quadrangulation:
    """Quadrangulate a triangle mesh: a smooth cross field, its mixed-integer seamless
    parametrization, and the quad mesh of that map's integer grid (§5.2.2; Bommes et al. 2009,
    Ebke et al. 2013).

    V: (n, 3) float array; F: (m, 3) integer array, a clean connected oriented manifold (see
    :func:`cross_field`). target_faces: about how many quads (MIQ's grid unit calibrated on
    its continuous map to cover that many unit squares, see :func:`miq`), or target_edge_length: the quad edge length in input units; neither: MIQ's default
    (twice the mean triangle side). align, sharp_angle: as :func:`cross_field` ("curvature",
    "boundary" or "smooth"; feature edges above sharp_angle degrees are followed); rounding: the
    cross field's period-jump rounding, as :func:`cross_field` ("none", "resolve" or "greedy").
    curvature_weight, crease_weight: the pull of the principal curvature directions and of the
    edges where the surface folds against the field's smoothness (align="curvature"; as
    :func:`cross_field`; crease_weight None: 0.2 with sharp_angle, else 0). The crease term makes the quads
    follow folds (fandisk's crease faces within 5° of the edge: 97% at 0.2, 79% at 0); it was this
    function's default (0.2) until the conformal scale below, which does more for the angles
    without it. Measured at 3,000 quads with conformal_scale=1 (2026-12-04, the mesh as read and
    three 1e-9 perturbations), mean |angle − 90°| at crease_weight 0 / 0.2: fandisk 2.75° / 3.38°,
    decimated-max 3.28° / 3.92° (irregular vertices 18–22 / 30–46), camelhead 3.28° / 3.66°,
    fertility 4.45° / 4.93°, nefertiti-lowres 3.01° / 3.06°; spot 3.85° / 3.50°, kitten 4.13° /
    3.69°, rocker-arm 3.48° / 2.83°, pmp-bunny 4.09° / 3.21°. A stronger curvature_weight
    (0.025–0.03) also follows creases, at a cost elsewhere (spot's minimum scaled Jacobian 0.27 →
    0.001–0.04, measured with crease_weight=0 and a uniform scale). With sharp_angle the crease term
    stays (pmp-bunny at sharp_angle=60, whose 139 "feature" edges are scan noise: 2 MIQ attempts and
    38 s with it, 6 and 171 s without; 2026-12-04).
    conformal_scale: as :func:`miq` (default 1: the grid's scale follows the conformal factor of the
    field's flat cone metric; 0: uniform), for the MIQ attempts that hold no feature line: those
    that do (sharp_angle) use the uniform scale, with which they fold less (measured 2026-12-04 at
    3,000 quads: with the conformal scale pmp-bunny at sharp_angle=60 ran all 19 attempts, 236 s,
    and kitten at 40 ended incomplete; uniform: 2 attempts, 38 s, and 6, complete). Measured at 3,000 quads (bench_quadrangulation.py,
    2026-12-04): mean |angle − 90°| fandisk 2.94° (7.94° with 0; Instant Meshes at the same size
    5.27°), spot 3.90°, kitten 4.06°, rocker-arm 3.45°, pmp-bunny 4.12°, fertility 4.45° (4.25°,
    5.14°, 5.14°, 4.77°, 5.43° this morning with 0 and crease_weight=0.2); the quads' sizes vary
    more (edge length std ÷ mean 0.13–0.21 → 0.20–0.29) and the Hausdorff distance to the input
    grows (fandisk 0.014 → 0.025 of the diagonal, spot 0.014 → 0.019).
    merge: cancel or separate singularity pairs closer than about a quad edge before MIQ
    (:func:`merge_singularities`), trying the distances of ``MERGE_SCHEDULE`` (4 quad edges
    down to 0.5: the longest merge that does not fold leaves the fewest irregular vertices) until MIQ leaves no flipped triangle and a map whose mean Beltrami coefficient is at most
    ``MAP_DISTORTION_LIMIT`` (asked only of maps with conformal_scale > 0 and no feature lines) and an extraction without holes (after a flip-free map that misses
    either, at most ``MAP_RETRIES`` more distances), keeping the attempt with the fewest flips, then
    an extraction without holes, then the least distortion. With sharp_angle, MIQ first holds
    the feature edges on integer iso-lines (so they become quad edges), trying the distances of
    ``FEATURE_MERGE_SCHEDULE`` (shortest first); if every one still folds, ``MERGE_SCHEDULE`` is
    run without those constraints (the field still follows the features) and
    ``report.feature_edges`` is 0.
    relax: at most this many rounds of relaxing the quads whose scaled Jacobian is below 0.2
    (the non-convex ones MIQ's distortion leaves next to cones): their corners and one ring move
    towards the mean of their quad-edge neighbours within the input's tangent plane and back onto
    the input surface (closest point), the whole way to the mean (which shrinks thin tips) only
    where that leaves an inverted quad; the round with the largest minimum scaled Jacobian is
    kept. 0: the extracted mesh as it is.
    smooth: at most this many rounds (default 60) of tangential smoothing of every quad vertex
    (``SMOOTH_STEP`` = 0.8 of the way to the mean of its quad-edge neighbours, moved within the
    tangent plane and back onto the input surface;
    boundary and crease vertices fixed, no quad's scaled Jacobian below the mesh's minimum),
    stopping at the first round that does not lower the mean |angle − 90°|; 0: none.
    ``report.relaxed_vertices`` counts the vertices either step moved.
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
    relax = _arguments.integer(relax, "relax", 0, 1000)
    smooth = _arguments.integer(smooth, "smooth", 0, 1000)
    if crease_weight is None:
        crease_weight = 0.0 if sharp_angle is None else 0.2
    # the stages share one checked mesh, its face frames and adjacency (one build instead of a dozen)
    with _core.shared_field_mesh():
        field = cross_field(V, F, align=align, sharp_angle=sharp_angle, curvature_weight=curvature_weight,
                            crease_weight=crease_weight,
                            rounding=rounding, progress=_arguments.stage(progress, 0.0, 0.15))
        length = grid_length(V, F, target_edge_length, target_faces, "quadrangulate")
        fixed = _feature_faces(V, F, field, sharp_angle)
        # With features, first with their iso-line constraints, then (if every attempt folds) without.
        plans: list[tuple[float, float | None]] = []
        if sharp_angle is not None:
            plans += [(factor, sharp_angle) for factor in (FEATURE_MERGE_SCHEDULE if merge else (0.0,))]
        plans += [(factor, None) for factor in (MERGE_SCHEDULE if merge else (0.0,))]
        best = None
        best_key: tuple[int, bool, bool, float] | None = None  # flips, incomplete, distorted, |μ|
        attempts = retries = 0
        for attempt, (factor, features) in enumerate(plans):
            trial = field if factor == 0 else merge_singularities(V, F, field, factor * length, fixed_faces=fixed)
            begin = 0.15 + 0.7 * attempt / len(plans)
            param = miq(V, F, trial, target_edge_length=length if target_faces is None else None,
                        target_quads=target_faces, sharp_angle=features,
                        conformal_scale=conformal_scale if features is None else 0.0,   # see the docstring
                        progress=_arguments.stage(progress, begin, begin + 0.7 / len(plans)))
            attempts += 1
            distortion = _map_distortion(V, F, param.UV)
            # a flip-free map can still wind twice around a vertex (nefertiti-lowres at 3,000 quads
            # with conformal_scale=1 and the longest merge): its extraction then leaves a hole. (Squares
            # cut by the input's boundary, which MIQ does not put on iso-lines, are no such failure.)
            extracted = None
            if param.flipped_after == 0:
                extracted = extract_quads(V, F, param.UV, progress=_arguments.stage(progress, 0.85, 1.0))
            incomplete = extracted is None or _broken(extracted.report)
            # held feature lines distort any map (fandisk at sharp_angle=40: 0.11–0.13 at every
            # distance), and so does a uniform scale (0.097–0.122 on the six meshes)
            distorted = features is None and conformal_scale > 0 and distortion > MAP_DISTORTION_LIMIT
            key = (param.flipped_after, incomplete, distorted, distortion)
            if best_key is None or key < best_key:
                best, best_key = (trial, param, factor * length, extracted), key
            if param.flipped_after == 0:
                if not (incomplete or distorted) or retries == MAP_RETRIES:
                    break
                retries += 1
        assert best is not None and best_key is not None
        field, param, merge_distance, quads = best
        singular = singularities(V, F, field)
    if quads is None:
        quads = extract_quads(V, F, param.UV, progress=_arguments.stage(progress, 0.85, 1.0))
    Vq, Q, doublets = _remove_doublets(quads.V, quads.Q)
    extracted_jacobian, relaxed = float("nan"), 0
    if len(Q):
        extracted_jacobian = float(quad_quality(Vq, Q).scaled_jacobian.min())
        if relax and extracted_jacobian < RELAX_BELOW:
            Vq, relaxed = _relax(Vq, Q, V, F, relax)
        if smooth:
            from ..geometry.metrics import SurfaceDistance
            Vq, smoothed = _smooth_angles(Vq, Q, SurfaceDistance(V, F), smooth)
            relaxed = max(relaxed, smoothed)
        quality = quad_quality(Vq, Q)
        deviation = np.abs(quality.angles - 90.0)
        mean_deviation, max_deviation = float(deviation.mean()), float(deviation.max())
        min_jacobian = float(quality.scaled_jacobian.min())
        irregular = _irregular_vertices(Q, quality.valence)
    else:
        mean_deviation = max_deviation = min_jacobian = float("nan")
        irregular = 0
    report = QuadrangulationReport(
        quads=len(Q), target_faces=target_faces, target_edge_length=param.target_edge_length,
        singular_vertices=singular.vertices, singular_indices=singular.indices,
        flipped_before=param.flipped_before, flipped_after=param.flipped_after, extraction=quads.report,
        irregular_vertices=irregular, mean_angle_deviation=mean_deviation, max_angle_deviation=max_deviation,
        min_scaled_jacobian=min_jacobian, merge_distance=merge_distance, feature_edges=param.feature_edges,
        miq_attempts=attempts,
        relaxed_vertices=relaxed, min_scaled_jacobian_extracted=extracted_jacobian, removed_doublets=doublets,
        map_distortion=best_key[3])
    return Quadrangulation(Vq, Q, param.UV, report, field)


def _broken(report: QuadExtractionReport) -> bool:
    """An extraction with a hole, an inconsistent square or quad, or another Euler characteristic
    than the input's (squares cut by the input's boundary alone are not counted)."""
    return bool(report.holes or report.squares_inconsistent or report.quads_non_manifold
                or report.euler_output != report.euler_input)


def _map_distortion(V: ArrayLike, F: ArrayLike, UV: FloatArray) -> float:
    """The area-weighted mean Beltrami coefficient |μ| = (σ1 − σ2) / (σ1 + σ2) of a per-corner map
    UV (m, 3, 2) of the triangles (V, F) (σ the singular values of each triangle's Jacobian, as
    :func:`meshsmith.geometry.triangle_distortion`); a triangle collapsed in UV counts as 1."""
    from ..geometry.metrics import triangle_distortion
    P = np.asarray(V, dtype=np.float64)[np.asarray(F, dtype=np.int64)].reshape(-1, 3)
    m = len(P) // 3
    measures = triangle_distortion(P, np.arange(3 * m).reshape(m, 3), np.asarray(UV).reshape(-1, 2))
    s1, s2 = measures.singular_values[:, 0], measures.singular_values[:, 1]
    with np.errstate(invalid="ignore"):
        mu = np.where(np.isfinite(s1) & (s1 > 0), (s1 - s2) / np.maximum(s1 + s2, 1e-300), 1.0)
    area = measures.surface_areas
    return float((area * mu).sum() / area.sum())


def _quad_edges(Q: IndexArray) -> IndexArray:
    """The edges of the quads Q (q, 4), one row per quad corner c: (Q[:, c], Q[:, c+1]) sorted,
    quad by quad (4q, 2); repeated where quads share an edge."""
    return np.sort(np.stack([Q, np.roll(Q, -1, axis=1)], -1).reshape(-1, 2), axis=1)


def _remove_doublets(Vq: FloatArray, Q: IndexArray) -> tuple[FloatArray, IndexArray, int]:
    """Removes the doublets of a quad mesh: an interior vertex v in exactly two quads, which then
    share both of its edges, (v, a, x, b) and (v, b, y, a); the two become the one quad
    (a, x, b, y) and v is dropped (χ is kept: one vertex, two edges and one face fewer). Repeated
    while the merges make new ones. The quads at a doublet have corner angles near 180° there:
    with feature iso-lines held (kitten at sharp_angle=40, rocker-arm at 60, 3,000 quads) the
    extraction left one each, the only quads with a scaled Jacobian ≤ 0 (−0.004, −0.001) after the
    relaxation. Vq: (k, 3), Q: (q, 4) counter-clockwise; returns (Vq, Q) without them (vertices
    renumbered in their order) and how many were removed."""
    Q = np.array(Q, dtype=np.int64, copy=True)
    removed = 0
    while len(Q):
        alive = np.ones(len(Q), dtype=bool)
        valence = np.bincount(Q.ravel(), minlength=len(Vq))
        merged = 0
        for v in np.flatnonzero(valence == 2):
            pair = np.flatnonzero(alive & (Q == v).any(axis=1))
            if len(pair) != 2:
                continue
            A, B = Q[pair[0]], Q[pair[1]]
            i, j = int(np.argmax(A == v)), int(np.argmax(B == v))
            a, x, b = A[(i + 1) % 4], A[(i + 2) % 4], A[(i + 3) % 4]
            if B[(j + 1) % 4] != b or B[(j + 3) % 4] != a or B[(j + 2) % 4] == x:
                continue                    # not an interior doublet (or the two quads coincide)
            Q[pair[0]] = [a, x, b, B[(j + 2) % 4]]
            alive[pair[1]] = False
            merged += 1
        Q = Q[alive]
        removed += merged
        if not merged:
            break
    if not removed:
        return Vq, Q, 0
    used = np.unique(Q)
    renumber = np.full(len(Vq), -1, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    return Vq[used], renumber[Q], removed


#: Quads with a smaller scaled Jacobian are relaxed (with their neighbours).
RELAX_BELOW = 0.2


def _relax(Vq: FloatArray, Q: IndexArray, V: ArrayLike, F: ArrayLike, rounds: int,
           shrink: bool = True) -> tuple[FloatArray, int]:
    """Moves the corners of the quads with scaled Jacobian < RELAX_BELOW, and their one ring,
    towards the mean of their quad-edge neighbours within the input's tangent plane there (the
    move's component along the normal of the input face under the vertex removed, so thin tips
    such as pmp-bunny's ears do not shrink), then onto the surface (V, F); `rounds` times, the
    region regrown each round. Where that leaves an inverted quad (scaled Jacobian <= 0), up to
    `rounds` more rounds move the vertices the whole way to the mean, from the best round so far
    (this shrinks tips, but untangles folds the tangent moves cannot; not with ``shrink=False``). Returns the positions of the best round (largest minimum scaled
    Jacobian) and how many vertices that moved; a round that makes a quad degenerate (two corners
    projected onto one point) ends the relaxation at the best earlier round."""
    from ..geometry import face_normals
    from ..geometry.metrics import SurfaceDistance

    surface = SurfaceDistance(V, F)
    face_normal = face_normals(V, F)
    under = surface.closest_points(Vq).face
    edges, counts = np.unique(_quad_edges(Q), axis=0, return_counts=True)
    # boundary vertices stay where they are
    boundary = np.zeros(len(Vq), dtype=bool)
    boundary[edges[counts == 1].ravel()] = True
    degree = np.bincount(edges.ravel(), minlength=len(Vq)).astype(np.float64)
    best, best_jacobian = Vq, float(quad_quality(Vq, Q).scaled_jacobian.min())
    moved = np.zeros(len(Vq), dtype=bool)
    best_moved = 0
    for tangential in (True, False) if shrink else (True,):
        if not tangential and best_jacobian > 0:
            break
        P = best.copy()
        for _ in range(rounds):
            jacobian = quad_quality(P, Q).scaled_jacobian
            region = np.zeros(len(P), dtype=bool)
            region[Q[jacobian < RELAX_BELOW].ravel()] = True
            if not region.any():
                break
            grown = region.copy()
            grown[edges[region[edges[:, 0]], 1]] = True
            grown[edges[region[edges[:, 1]], 0]] = True
            grown &= ~boundary
            mean = np.zeros_like(P)
            np.add.at(mean, edges[:, 0], P[edges[:, 1]])
            np.add.at(mean, edges[:, 1], P[edges[:, 0]])
            mean /= np.maximum(degree, 1)[:, None]
            move = mean[grown] - P[grown]
            if tangential:
                normal = face_normal[under[grown]]
                move -= np.einsum("ij,ij->i", move, normal)[:, None] * normal
            P, under = P.copy(), under.copy()
            closest = surface.closest_points(P[grown] + move)
            P[grown], under[grown] = closest.point, closest.face
            moved |= grown
            try:
                now = float(quad_quality(P, Q).scaled_jacobian.min())
            except InputError:  # two corners of a quad projected onto one surface point: keep the best round
                break
            if now > best_jacobian:
                best, best_jacobian, best_moved = P, now, int(moved.sum())
    return best, best_moved


#: Trial moves of the untangling (:func:`_untangle`): directions in the tangent plane, and step
#: lengths as fractions of the vertex's mean quad-edge length.
UNTANGLE_DIRECTIONS = 12
UNTANGLE_STEPS = (0.05, 0.15, 0.35, 0.7)

#: The untangling's objective counts every incident quad whose scaled Jacobian is below this.
UNTANGLE_MARGIN = 0.1


#: The untangling also tries this many of the input's face centroids nearest each vertex.
UNTANGLE_CENTROIDS = 16


def _untangle(Vq: FloatArray, Q: IndexArray, V: ArrayLike, F: ArrayLike, surface: Any,
              rounds: int) -> tuple[FloatArray, int]:
    """Untangles a closed quad mesh on a surface: moves the corners of inverted quads (scaled
    Jacobian <= 0) one at a time to the best of a few trial points on the surface around them.

    Vq: (k, 3) float64, Q: (q, 4) int64 counter-clockwise; V, F: the input surface, surface: its
    SurfaceDistance. Each round takes the corners of the inverted quads, worst first, as far as
    they share no quad (so their moves are independent), and tries for each its current position,
    UNTANGLE_DIRECTIONS × len(UNTANGLE_STEPS) points in the input's tangent plane there (steps
    relative to its mean quad-edge length) projected onto the surface (closest point), and the
    UNTANGLE_CENTROIDS input face centroids nearest it (points the projection cannot reach: near a
    sharp convex vertex of the input every nearby point projects onto that vertex, where two quad
    corners may already sit together); it keeps the trial that maximizes the smallest scaled Jacobian of its
    quads plus Σ min(J − UNTANGLE_MARGIN, 0) over them (so a move that frees one quad without
    worsening the worst still counts), when that beats staying. A vertex that found nothing better
    is not tried again until a neighbour moves; when every corner of an inverted quad is such, their
    one ring is tried as well, and when that too finds nothing it ends. Stops when no quad is
    inverted, or after `rounds` rounds. A vertex in two quads only (a valence-2 vertex between two quads that
    share both its edges) has corners near 180° there that no move makes convex on a flat
    surface. Returns (positions, how many vertices moved)."""
    from ..geometry import face_normals
    from ..points import KdTree

    P = np.array(Vq, dtype=np.float64, copy=True)
    n = len(P)
    if not len(Q):
        return P, 0
    points, triangles = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
    face_normal = face_normals(points, triangles)
    centroids = points[triangles].mean(axis=1)
    centroid_tree = KdTree(centroids)
    nearby = min(UNTANGLE_CENTROIDS, len(centroids))
    face = surface.closest_points(P).face
    # the quads at each vertex, padded with -1
    valence = np.bincount(Q.ravel(), minlength=n)
    order = np.argsort(Q.ravel(), kind="stable")
    start = np.concatenate([[0], np.cumsum(valence)])
    owner = Q.ravel()[order]
    incident = np.full((n, int(valence.max())), -1, dtype=np.int64)
    incident[owner, np.arange(len(order)) - start[owner]] = order // 4
    edges = np.unique(_quad_edges(Q), axis=0)
    angles = np.linspace(0.0, 2.0 * np.pi, UNTANGLE_DIRECTIONS, endpoint=False)
    directions = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    steps = np.repeat(np.asarray(UNTANGLE_STEPS, dtype=np.float64), UNTANGLE_DIRECTIONS)
    moved = np.zeros(n, dtype=bool)
    stale = np.zeros(n, dtype=bool)     # tried without a better trial since its quads last changed
    grow = False
    for _ in range(rounds):
        jacobian = corner_jacobians(P[Q]).min(axis=1)
        inverted = jacobian <= 0
        if not inverted.any():
            break
        region = np.zeros(n, dtype=bool)
        region[Q[inverted].ravel()] = True
        if grow:
            region[Q[region[Q].any(axis=1)].ravel()] = True
        vertices = np.flatnonzero(region & ~stale)
        if not len(vertices):
            if grow:
                break
            grow = True
            continue
        local = np.where(incident[vertices] >= 0, jacobian[incident[vertices]], np.inf).min(axis=1)
        taken = np.zeros(len(Q), dtype=bool)
        picked = []
        for v in vertices[np.argsort(local, kind="stable")]:
            quads = incident[v, :valence[v]]
            if not taken[quads].any():
                taken[quads] = True
                picked.append(v)
        chosen = np.asarray(picked, dtype=np.int64)
        k = len(chosen)
        # trial points in the input's tangent plane at each chosen vertex
        normal = face_normal[face[chosen]]
        helper = np.where(np.abs(normal[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        first = np.cross(normal, helper)
        first /= np.linalg.norm(first, axis=1, keepdims=True)
        second = np.cross(normal, first)
        length = np.linalg.norm(P[edges[:, 0]] - P[edges[:, 1]], axis=1)
        mean_length = (np.bincount(edges.ravel(), np.concatenate([length, length]), minlength=n)
                       / np.maximum(np.bincount(edges.ravel(), minlength=n), 1))[chosen]
        offsets = (np.tile(directions, (len(UNTANGLE_STEPS), 1)) * steps[:, None])          # (t, 2)
        trial = (P[chosen][:, None, :] + mean_length[:, None, None]
                 * (offsets[None, :, :1] * first[:, None, :] + offsets[None, :, 1:] * second[:, None, :]))
        trial = surface.closest_points(trial.reshape(-1, 3)).point.reshape(k, -1, 3)
        near = centroid_tree.query(nearby, P[chosen]).indices
        trial = np.concatenate([P[chosen][:, None, :], trial, centroids[near]], axis=1)     # trial 0: stay
        # each trial's quads: (k, trials, valence, 4, 3)
        quads = incident[chosen]
        present = quads >= 0
        corners = Q[np.maximum(quads, 0)]                                                    # (k, d, 4)
        C = np.broadcast_to(P[corners][:, None], (k, trial.shape[1]) + corners.shape[1:] + (3,)).copy()
        at_vertex = np.broadcast_to((corners == chosen[:, None, None])[:, None, :, :, None], C.shape)
        C = np.where(at_vertex, trial[:, :, None, None, :], C)
        J = corner_jacobians(C).min(axis=-1)                                                 # (k, trials, d)
        score = (np.where(present[:, None], J, np.inf).min(axis=-1)
                 + np.where(present[:, None], np.minimum(J - UNTANGLE_MARGIN, 0.0), 0.0).sum(axis=-1))
        best = score.argmax(axis=1)
        better = score[np.arange(k), best] > score[:, 0] + 1e-12
        stale[chosen[~better]] = True
        if better.any():
            grow = False
            winners = chosen[better]
            P[winners] = trial[np.arange(k), best][better]
            face[winners] = surface.closest_points(P[winners]).face
            moved[winners] = True
            around = incident[winners]
            stale[Q[around[around >= 0]].ravel()] = False
    return P, int(moved.sum())


def _feature_faces(V: ArrayLike, F: ArrayLike, field: CrossField, sharp_angle: float | None) -> IndexArray | None:
    """The faces on edges whose dihedral angle exceeds sharp_angle (the field's hard feature
    constraints), or None."""
    if sharp_angle is None:
        return None
    P, T = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
    normal = np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    pairs = field.edge_faces[field.edge_faces[:, 1] >= 0]
    sharp = np.einsum("ij,ij->i", normal[pairs[:, 0]], normal[pairs[:, 1]]) < np.cos(np.radians(float(sharp_angle)))
    return np.unique(pairs[sharp].ravel())


def _irregular_vertices(Q: IndexArray, valence: IndexArray) -> int:
    """Interior vertices of valence other than 4 (a vertex is interior when every edge at it has
    two quads)."""
    unique, counts = np.unique(_quad_edges(Q), axis=0, return_counts=True)
    boundary = np.zeros(len(valence), dtype=bool)
    boundary[unique[counts == 1].ravel()] = True
    used = valence > 0
    return int((used & ~boundary & (valence != 4)).sum())



def _smooth_angles(Vq: FloatArray, Q: IndexArray, surface: Any, rounds: int,
                   step: float = SMOOTH_STEP, sharp_degrees: float = 50.0) -> tuple[FloatArray, int]:
    """Tangential smoothing of a quad mesh on a surface, for corner angles closer to 90° (§5.2.2,
    after extraction). Vq: (k, 3) float64, Q: (q, 4) int64; surface: a SurfaceDistance of the input.

    Each round moves every free vertex by `step` of the way to the mean of its quad-edge
    neighbours, less that move's component along the vertex normal (area-weighted quad
    normals), then onto the input surface (closest point). Fixed: boundary vertices and the ends
    of quad edges whose two quads meet at more than `sharp_degrees` (creases the quads follow).
    A quad whose scaled Jacobian falls below the mesh's previous minimum, or to 0 or below from
    above 0, has its corners put back (repeated until none does, at most ten times), so the
    minimum scaled Jacobian never drops and no quad becomes inverted. Rounds stop at the first that does not lower the mean |angle − 90°|
    (at most `rounds`). Returns (positions, how many vertices moved)."""
    edge_list = _quad_edges(Q)
    unique, inverse, counts = np.unique(edge_list, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    n = len(Vq)
    fixed = np.zeros(n, dtype=bool)
    fixed[unique[counts == 1].ravel()] = True
    fixed[unique[counts > 2].ravel()] = True

    def normals(P: FloatArray) -> FloatArray:
        C = P[Q]
        normal = np.cross(C, np.roll(C, -1, axis=1)).sum(axis=1)
        return normal / np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)

    # creases: interior quad edges whose two quads' normals differ by more than sharp_degrees
    quad_of = np.repeat(np.arange(len(Q)), 4)
    order = np.argsort(inverse, kind="stable")
    interior = counts[inverse[order]] == 2
    pairs = quad_of[order][interior].reshape(-1, 2)
    pair_edges = unique[inverse[order][interior].reshape(-1, 2)[:, 0]]
    nq = normals(Vq)
    crease = np.einsum("ij,ij->i", nq[pairs[:, 0]], nq[pairs[:, 1]]) < np.cos(np.radians(sharp_degrees))
    fixed[pair_edges[crease].ravel()] = True
    degree = np.bincount(unique.ravel(), minlength=n).astype(np.float64)
    valence = np.bincount(Q.ravel(), minlength=n).astype(np.float64)
    free = ~fixed & (valence > 0)

    # the neighbour mean and the corner-to-vertex sum as sparse matrices, built once (np.add.at per
    # round was a third of the smoothing's time)
    import scipy.sparse
    rows = np.concatenate([unique[:, 0], unique[:, 1]])
    columns = np.concatenate([unique[:, 1], unique[:, 0]])
    neighbour_mean = scipy.sparse.csr_matrix((1.0 / np.maximum(degree, 1)[rows], (rows, columns)), shape=(n, n))
    corner_sum = scipy.sparse.csr_matrix((np.ones(Q.size), (Q.ravel(), np.repeat(np.arange(len(Q)), 4))),
                                         shape=(n, len(Q)))

    def target(P: FloatArray) -> FloatArray:
        return np.asarray(neighbour_mean @ P)

    def vertex_normals(P: FloatArray) -> FloatArray:
        C = P[Q]
        out = np.asarray(corner_sum @ np.cross(C, np.roll(C, -1, axis=1)).sum(axis=1))
        return out / np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-300)

    def mean_deviation(angles: FloatArray) -> float:
        return float(np.abs(angles - 90.0).mean())

    first_angles, jacobian, _ = corner_measures(Vq, Q)
    best_deviation = mean_deviation(first_angles)
    best, P = Vq, Vq
    moved = np.zeros(n, dtype=bool)
    best_moved = 0
    for _ in range(rounds):
        move = step * (target(P) - P)
        normal = vertex_normals(P)
        move -= np.einsum("ij,ij->i", move, normal)[:, None] * normal
        candidate = P.copy()
        candidate[free] = surface.closest_points(P[free] + move[free]).point
        floor = float(jacobian.min())
        measured: tuple[FloatArray, FloatArray] | None = None
        for attempt in range(11):           # the measures of the last candidate are the round's
            try:
                angles, now, _ = corner_measures(candidate, Q)
            except InputError:              # a zero-length edge: this round gives nothing
                measured = None
                break
            measured = angles, now
            bad = (now < floor) | ((now <= 0) & (jacobian > 0))   # with floor <= 0: no new inverted quad
            if not bad.any() or attempt == 10:
                break
            corners = Q[bad].ravel()
            candidate[corners] = P[corners]
        if measured is None:
            break
        deviation, now = mean_deviation(measured[0]), measured[1]
        if now.min() < floor - 1e-12 or deviation >= best_deviation:
            break
        moved |= np.any(candidate != P, axis=1)
        P, jacobian = candidate, now
        best, best_deviation, best_moved = P, deviation, int(moved.sum())
    return best, best_moved
