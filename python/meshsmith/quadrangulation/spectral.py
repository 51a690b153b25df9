"""Spectral Morse–Smale quadrangulation (§5.2.1): a Laplacian eigenfunction, its Morse–Smale complex,
a seamless parametrization of its quad cells coupled by transition functions (or each cell's own
harmonic map onto the unit square), and the extracted grid; binding
cpp/python/quadrangulation_spectral.cpp."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _arguments
from .._core import quadrangulation as _core
from .._results import Unpackable
from .._typing import ArrayLike, BoolArray, FloatArray, IndexArray, ProgressCallback
from .pipeline import SMOOTH_ROUNDS, _irregular_vertices, _relax, _smooth_angles, _untangle
from .quality import quad_quality

__all__ = ["MorseSmaleComplex", "morse_smale_complex", "SpectralQuadrangulationReport",
           "SpectralQuadrangulation", "spectral_quadrangulate", "CRITICAL_TYPES"]

#: vertex_type codes of :class:`MorseSmaleComplex`.
CRITICAL_TYPES = {0: "regular", 1: "minimum", 2: "saddle", 3: "maximum"}

#: Rounds of the untangling of inverted quads (before and, where needed, after the relaxation), at most.
UNTANGLE_ROUNDS = 300


@dataclass(frozen=True)
class MorseSmaleComplex(Unpackable):
    """The result of :func:`morse_smale_complex`; unpacks in field order.

    vertex_type: (n,) int64, 0 regular, 1 minimum, 2 saddle, 3 maximum (:data:`CRITICAL_TYPES`);
    saddle_multiplicity: (n,) int64, k - 1 at a saddle whose ring has 2k wedges, else 0;
    maxima, minima, saddles: counts (saddles with multiplicity, so maxima - saddles + minima = χ);
    lines: the separatrices, each an int64 vertex path from a saddle to an extremum along mesh
    edges; line_ascending: (l,) bool, the line goes up to a maximum; detours: lines that met
    another line and went on beside it (the shortest free path to that line's extremum); face_patch: (m,) int64, the
    cell of each face (-1 when incomplete); patch_corners: (p, 4) int64 vertices, counter-clockwise,
    maximum, saddle, minimum, saddle; patch_sides: (p, 4) int64, the line from corner k to k+1;
    problem: '' when complete, else what failed first; complete: every cell is a disk with four
    sides and max-saddle-min-saddle corners.
    """

    vertex_type: IndexArray
    saddle_multiplicity: IndexArray
    maxima: int
    minima: int
    saddles: int
    lines: list[IndexArray]
    line_ascending: BoolArray
    detours: int
    face_patch: IndexArray
    patch_corners: IndexArray
    patch_sides: IndexArray
    problem: str
    complete: bool


def morse_smale_complex(V: ArrayLike, F: ArrayLike, f: ArrayLike) -> MorseSmaleComplex:
    """The Morse–Smale complex of a function on the vertices of a closed mesh (§5.2.1).

    Vertices are classified by the wedges of their one-ring (Banchoff's criterion; ties broken by
    vertex index, the simulation of simplicity): a maximum, a minimum, a saddle (2k wedges,
    multiplicity k - 1) or regular. From every saddle, one line per wedge follows steepest ascent
    (an upper wedge) to a maximum or steepest descent to a minimum along mesh edges; lines never
    share a vertex but at their ends, so they cannot cross. A line that meets another (PL gradient
    lines merge in valleys) goes on beside it by the shortest free path to the other's extremum.
    A saddle with no free vertex in a wedge leaves the complex incomplete (``problem`` says where;
    :func:`spectral_quadrangulate` then refines the mesh), as does a cell that is not a disk with
    max-saddle-min-saddle corners.

    V: (n, 3) float array; F: (m, 3) integer array, a clean, connected, closed, oriented manifold;
    f: (n,) finite floats. Returns a :class:`MorseSmaleComplex`. Raises InputError for bad input
    (boundaries included, naming the element).
    """
    out = _core.morse_smale_complex(V, F, f)
    out["line_ascending"] = np.asarray(out["line_ascending"], dtype=bool)
    out["complete"] = not out["problem"]
    return MorseSmaleComplex(**out)


@dataclass(frozen=True)
class SpectralQuadrangulationReport(Unpackable):
    """What :func:`spectral_quadrangulate` made; unpacks in field order.

    quads: faces of the result; target_faces: the number asked for (None: quads of twice the
    mean edge length); patches: cells of the Morse–Smale complex (each an n×m grid);
    eigenvector, eigenvalue: the eigenpair used (-L u = λ M u, input units); maxima, minima,
    saddles (with multiplicity), multi_saddles (saddle vertices of multiplicity > 1),
    saddle_vertices: its critical points, maxima - saddles + minima = χ, and patches = saddles +
    saddle_vertices (a saddle with 2k lines is a corner of k cells); refinements: 1-to-4 subdivisions the tracing needed;
    detours: lines that went on beside another (see :func:`morse_smale_complex`); gap_routes: of
    them, lines walled in by others that went on through the gaps between them (the mesh edges
    across a gap split at their midpoints);
    candidates_tried: eigenvectors traced; traced_faces: faces of the (refined) surfaces the
    complexes were traced on, summed over every trace (the search's work); cancelled_extrema: extrema of the eigenvector cancelled
    with as many saddles by the persistence-based simplification before tracing (persistence
    below 3% of its range, or beyond the most persistent ones the target asks for);
    simplification_rounds: its sweep rounds (-1: it did not converge and the eigenvector was used
    as it was); cancelled_two_cell_extrema: of cancelled_extrema, those cancelled after tracing
    because only two lines reached them (a layout corner of valence 2; the complex was traced
    again without them); two_cell_extrema: such extrema left in the complex used (a layout corner
    of valence 2: when three rounds of cancellation did not remove them, or the last traced
    again incomplete); irregular_vertices: vertices of valence other than 4;
    mean_angle_deviation, max_angle_deviation: |angle - 90°| over every quad corner, degrees (the
    final quads); mean_angle_deviation_extracted: the mean as the grids were extracted;
    mean_angle_deviation_unsmoothed: the mean after the untangling (and relaxing), before the tangential
    smoothing (equal to the final one with ``smooth=0``);
    min_scaled_jacobian: over every corner; inverted_quads: quads with a corner of scaled
    Jacobian <= 0 (at the end); inverted_before_relaxing: the same count as the grids
    were extracted (before the untangling, the relaxation and the smoothing);
    relaxed_vertices: vertices moved by the untangling, the relaxation or the smoothing (0 with
    ``smooth=0`` and no inverted quad);
    coupled: the quads come from the coupled parametrization (asked for and its extraction
    complete); flipped_before,
    flipped_after: its triangles with det ≤ 0 in (u, v) as first solved and after the stiffening
    repair (the extraction untangles some of those left), repair_rounds: the rounds of that repair
    (all 0 with ``coupled=False``). The report
    holds no timings, so equal calls give equal reports.
    """

    quads: int
    target_faces: int | None
    patches: int
    eigenvector: int
    eigenvalue: float
    maxima: int
    minima: int
    saddles: int
    multi_saddles: int
    saddle_vertices: int
    refinements: int
    detours: int
    gap_routes: int
    candidates_tried: int
    traced_faces: int
    cancelled_extrema: int
    simplification_rounds: int
    cancelled_two_cell_extrema: int
    two_cell_extrema: int
    irregular_vertices: int
    mean_angle_deviation: float
    max_angle_deviation: float
    mean_angle_deviation_extracted: float
    mean_angle_deviation_unsmoothed: float
    min_scaled_jacobian: float
    inverted_quads: int
    inverted_before_relaxing: int
    relaxed_vertices: int
    coupled: bool
    flipped_before: int
    flipped_after: int
    repair_rounds: int


@dataclass(frozen=True)
class SpectralQuadrangulation(Unpackable):
    """The result of :func:`spectral_quadrangulate`; unpacks as ``V, Q, report``.

    V: (k, 3) float64 quad-mesh vertices on the input surface; Q: (q, 4) int64 quads,
    counter-clockwise like the input; quad_patch: (q,) int64 the cell each quad lies in (with the
    coupled map, whose quads cross the cells' sides: the cell holding most of its corners);
    patch_corners: (p, 4) int64 each cell's corners as rows of V (maximum, saddle, minimum,
    saddle); report: a :class:`SpectralQuadrangulationReport`.
    """

    unpacks = ("V", "Q", "report")
    V: FloatArray
    Q: IndexArray
    quad_patch: IndexArray
    patch_corners: IndexArray
    report: SpectralQuadrangulationReport


@_arguments.real_options
def spectral_quadrangulate(V: ArrayLike, F: ArrayLike, *, target_faces: int | None = None,
                           target_patches: int | None = None, eigenvector: int | None = None,
                           relax: int = 30, smooth: int = SMOOTH_ROUNDS, coupled: bool = False,
                           progress: ProgressCallback = None) -> SpectralQuadrangulation:
    """Quadrangulate a closed surface with the Morse–Smale complex of a Laplacian eigenfunction
    (§5.2.1; Dong et al., "Spectral Surface Quadrangulation", 2006).

    The lowest eigenpairs of the cotangent Laplacian with the Voronoi mass matrix
    (:func:`meshsmith.geometry.laplacian_eigenpairs`) give the function; the eigenvector's index
    sets the frequency, hence the number of cells (2 per saddle). Its :func:`morse_smale_complex`
    cuts the surface into quads with max-saddle-min-saddle corners. Integer counts are chosen per
    chain of sides (opposite sides of a cell, the shared side of two cells), so that opposite
    sides agree. With ``coupled=True`` (Dong et al.'s global relaxation; not the default: at
    2,000 quads, measured 2026-12-04, complete and flip-free on spot, kitten, rocker-arm,
    fertility, pmp-bunny and cheburashka, mean |angle - 90°| 18.5, 16.2, 20.9, 34.3, 15.4, 12.9
    against 21.5, 19.6, 22.1, 38.6, 17.8, 15.6 with ``coupled=False``, but fertility keeps one
    inverted quad) all cells
    get one seamless parametrization: cell p's chart is the n×m rectangle of its counts, its
    corners held at (0, 0), (n, 0), (n, m), (0, m), the mesh cut along the lines, and across each
    line the two charts related by a transition function (a rotation by kπ/2 and an integer
    translation), so lines move freely and iso-lines cross them smoothly; the energy
    Σ A_f ‖∇(u, v) − J*_f‖² is minimized in one sparse solve (flipped triangles stiffened and
    re-solved, as :func:`miq`), its per-face target J*_f = (1 - β) J_f + β √det J_f · R_f, J_f the
    Jacobian of the cell's own harmonic map below and R_f its rotation (β = 0.6, else 0.3, else
    0.15, until a map is flip-free; the plain Dirichlet energy, held only at the corners, folded
    1,334 triangles on spot and 495 on kitten), and
    the integer grid extracted by :func:`extract_quads`. Where the coupled map keeps flips that
    leave its extraction incomplete, that candidate's cells are mapped one by one instead
    (``report.coupled`` False, its flip counts kept). With ``coupled=False`` each cell is mapped on its own by a mean-value harmonic map
    (:func:`meshsmith.parametrization.harmonic`) onto the unit square and sampled by its n×m grid
    (quads then align with the cells, the grids meeting node for node, but kink across every
    side). Either way: a pure, manifold, consistently oriented quad mesh with the input's Euler
    characteristic.

    V: (n, 3) float array; F: (m, 3) integer array, a clean, connected, closed, oriented manifold.
    target_faces: about how many quads (None: quads of twice the mean edge length);
    target_patches: about how many cells (None: one per ~25 quads, in [8, 240]); eigenvector: its
    index (>= 1) instead, overriding target_patches. The extracted quads are then untangled: the
    corners of inverted quads (scaled Jacobian <= 0) move one at a time to the best of a few trial
    points on the surface around them (:func:`_untangle` in pipeline.py; measured at 2,000 quads,
    2026-12-04: spot, kitten, rocker-arm, fertility, cheburashka, pmp-bunny and bumpy-cube keep
    none, from 0-573 as extracted). relax: only where that leaves an inverted quad, at most this
    many rounds of moving the corners of quads with scaled Jacobian below 0.2 (and their
    neighbours) towards the mean of their quad-edge neighbours within the tangent plane and back
    onto the surface, the best round kept (as :func:`quadrangulate` does, without its shrinking
    pass), then the untangling again; 0: none. smooth: at most this many rounds of the tangential
    smoothing of :func:`quadrangulate` (every vertex towards the mean of its quad-edge neighbours,
    no quad's scaled Jacobian below the minimum and none newly inverted), stopping at the first
    round that does not lower the mean |angle − 90°|; 0: none. Extrema that only two lines reach
    (layout corners of valence 2, whose quads fold) are cancelled and the complex traced again
    (``report.cancelled_two_cell_extrema``). progress: optional callback (fraction, stage) -> bool
    (False cancels).

    Returns a :class:`SpectralQuadrangulation` (unpacks as ``V, Q, report``). Raises InputError
    for bad input, boundaries, or options out of range; SolverError when no candidate
    eigenvector gives a complete complex (the message says why); Cancelled from `progress`.
    """
    relax = _arguments.integer(relax, "relax", 0, 1000)
    smooth = _arguments.integer(smooth, "smooth", 0, 1000)
    progress = _arguments.progress(progress)
    out = _core.spectral_quadrangulate(V, F, target_faces, target_patches, eigenvector, coupled, progress)
    Vq, Q = out["V"], out["Q"]
    quality = quad_quality(Vq, Q)
    inverted_before = int((quality.scaled_jacobian <= 0).sum())
    extracted_deviation = float(np.abs(quality.angles - 90.0).mean())
    moved = np.zeros(len(Vq), dtype=bool)
    surface = None
    if inverted_before or smooth:
        from ..geometry.metrics import SurfaceDistance
        surface = SurfaceDistance(V, F)

    def untangle(P: FloatArray) -> FloatArray:
        untangled, _ = _untangle(P, Q, V, F, surface, UNTANGLE_ROUNDS)
        moved[np.any(untangled != P, axis=1)] = True
        return untangled

    if inverted_before:
        Vq = untangle(Vq)
        quality = quad_quality(Vq, Q)
    # the relaxation only where the untangling left inverted quads (its moves can slide vertices far
    # along the surface: rocker-arm's Hausdorff distance 0.08 -> 0.17 of the diagonal when it ran first)
    if relax and (quality.scaled_jacobian <= 0).any():
        relaxed, _ = _relax(Vq, Q, V, F, relax, shrink=False)
        moved[np.any(relaxed != Vq, axis=1)] = True
        Vq = untangle(relaxed)
        quality = quad_quality(Vq, Q)
    unsmoothed_deviation = float(np.abs(quality.angles - 90.0).mean())
    if smooth:
        smoothed, _ = _smooth_angles(Vq, Q, surface, smooth)
        moved |= np.any(smoothed != Vq, axis=1)
        Vq = smoothed
        quality = quad_quality(Vq, Q)
    deviation = np.abs(quality.angles - 90.0)
    report = SpectralQuadrangulationReport(
        quads=len(Q), target_faces=None if target_faces is None else int(target_faces),
        patches=len(out["patch_corners"]), eigenvector=int(out["eigenvector"]),
        eigenvalue=float(out["eigenvalue"]), maxima=int(out["maxima"]), minima=int(out["minima"]),
        saddles=int(out["saddles"]), multi_saddles=int(out["multi_saddles"]),
        saddle_vertices=int(out["saddle_vertices"]),
        refinements=int(out["refinements"]), detours=int(out["detours"]), gap_routes=int(out["gap_routes"]), candidates_tried=int(out["candidates_tried"]),
        traced_faces=int(out["traced_faces"]),
        cancelled_extrema=int(out["cancelled_extrema"]), simplification_rounds=int(out["simplification_rounds"]),
        cancelled_two_cell_extrema=int(out["cancelled_two_cell_extrema"]), two_cell_extrema=int(out["two_cell_extrema"]),
        irregular_vertices=_irregular_vertices(Q, quality.valence),
        mean_angle_deviation=float(deviation.mean()), max_angle_deviation=float(deviation.max()),
        mean_angle_deviation_extracted=extracted_deviation, mean_angle_deviation_unsmoothed=unsmoothed_deviation,
        min_scaled_jacobian=float(quality.scaled_jacobian.min()),
        inverted_quads=int((quality.scaled_jacobian <= 0).sum()), inverted_before_relaxing=inverted_before,
        relaxed_vertices=int(moved.sum()), coupled=bool(out["coupled"]), flipped_before=int(out["flipped_before"]),
        flipped_after=int(out["flipped_after"]), repair_rounds=int(out["repair_rounds"]))
    return SpectralQuadrangulation(Vq, Q, out["quad_patch"], out["patch_corners"], report)
