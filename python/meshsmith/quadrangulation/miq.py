"""Mixed-integer quadrangulation: a seamless integer-grid parametrization following a cross
field (§5.2.2 step 3); C++ src/quadrangulation/miq.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _arguments
from .._core import quadrangulation as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, ProgressCallback
from .._core import InputError
from ..repair.unreferenced import on_referenced_vertices
from .cross_field import FieldLike, field_angles
from .cut_graph import FieldCut, field_cut

__all__ = ["MiqResult", "miq"]


@dataclass(frozen=True)
class MiqResult(Unpackable):
    """The result of :func:`miq`; unpacks as ``UV, flipped_before, flipped_after``.

    UV: (m, 3, 2) float64, the (u, v) of each face's three corners (integer grid units: one
    unit is one quad edge); flipped_before / flipped_after: triangles whose (u, v) triangle has
    det(B − A, C − A) ≤ 0 after the integer rounding / after the repair; cut: the
    :class:`FieldCut` the map follows (seams, singularities, combed field, seam jumps);
    integer_variables: seam translations and singular coordinates rounded; rounding_residual:
    the largest distance to an integer a variable had when it was rounded; repair_rounds:
    stiffening rounds run; target_edge_length: the quad edge length used, in input units
    (with target_quads, after the calibration);
    feature_edges: feature edges (``sharp_angle``) held on an integer iso-line; separations:
    pairs of integer corners (feature-line corners, cones) of one coordinate within a quad edge of
    each other on different iso-lines, which the rounding keeps on distinct integers in their
    order; separation_conflicts: roundings where none of the four nearest integers kept every
    separation (the nearest was taken); released_feature_edges: feature edges left free because
    the map folded with them held (where flips remain, the feature edges within one quad edge of
    them are released and the map solved again, kept when it has fewer flips, else the radius
    grows by half a quad edge; at most ten re-solves); release_rounds: the re-solve the result
    came from (0: every feature as asked); rerounded_integers: integer unknowns moved by ±1
    after the repair because flips were left (each move kept only when the repaired map has
    fewer flips: two cones rounded onto one point or into an order the triangles between them
    cannot follow); flipped_unconstrained: where flips were left with the feature edges held, the
    flips of the map solved with every one released (−1: not solved) — the release re-solves run
    only when it is below those (else the cones fold the map, not the features: pmp-bunny at
    sharp_angle=60 ran ten fruitless re-solves in each of five merge distances, 255 s);
    log_scale_min, log_scale_max: the range over the faces of the grid's log scale λφ
    (``conformal_scale``; 0, 0 with conformal_scale=0): the quads are about e^(−λφ) times the
    mean quad edge there.
    """

    unpacks = ("UV", "flipped_before", "flipped_after")
    UV: FloatArray
    flipped_before: int
    flipped_after: int
    cut: FieldCut
    integer_variables: int
    rounding_residual: float
    repair_rounds: int
    target_edge_length: float
    feature_edges: int
    separations: int
    separation_conflicts: int
    released_feature_edges: int
    release_rounds: int
    rerounded_integers: int
    flipped_unconstrained: int
    log_scale_min: float
    log_scale_max: float


@_arguments.real_options
def miq(V: ArrayLike, F: ArrayLike, field: FieldLike, *, target_edge_length: float | None = None,
        target_quads: int | None = None, round_singularities: bool = True, round_translations: bool = True,
        repair_iterations: int = 10, stiffening: float = 5.0, sharp_angle: float | None = None,
        reround: bool = True, conformal_scale: float = 1.0, progress: ProgressCallback = None) -> MiqResult:
    """A seamless integer-grid parametrization of (V, F) following a cross field (MIQ, §5.2.2
    step 3; Bommes, Zimmer & Kobbelt 2009).

    The mesh is cut into a disk through the field's singularities (:func:`cut_graph`); the map
    minimizes Σ_f A_f (‖∇u − s·u*‖² + ‖∇v − s·v*‖²) (u*, v* the combed cross, s = 1 /
    target_edge_length) subject to the transition functions across the seams — rotation by the
    seam's k·π/2 and a translation — with the translations and the singular vertices' (u, v)
    integers, rounded greedily (closest to an integer first, each rounding re-solving the rest
    exactly from one CHOLMOD factorization). Triangles left flipped are stiffened and the map
    re-solved on the unknowns within three quad edges of them (``repair_iterations`` rounds,
    weight × ``stiffening``); where flips remain, an
    integer that the corners near them depend on is moved by ±1 and the map repaired again,
    kept when it has fewer flips (at most four moves; ``rerounded_integers``; ``reround=False``:
    none).
    conformal_scale: λ in [0, 1], how far the grid's scale s follows the conformal factor of the
    field's flat cone metric: s = e^(λφ)/target_edge_length per face, φ the least-squares
    solution of ∇φ = J∇θ (θ the field's turning against parallel transport, J the quarter turn:
    Cauchy–Riemann for φ − iθ; Ben-Chen, Gotsman & Bunin 2008, Crane, Desbrun & Schröder 2010),
    normalized so that the mean of s² is the uniform grid's. Where a smooth field turns, the
    uniformly scaled targets are no gradient and the map shears; scaled by e^φ they are one up
    to the field's harmonic part (genus > 0). 0: Bommes et al.'s uniform scale. Measured at
    3,000 quads (2026-12-04, the continuous map of quadrangulate's first attempt, area-weighted
    mean Beltrami coefficient |μ|): fandisk 0.092 → 0.043, spot 0.095 → 0.049, rocker-arm 0.121 →
    0.048, pmp-bunny 0.095 → 0.033, fertility 0.131 → 0.096; on a torus along its parallels the
    map's area element follows the analytic factor 1/ρ² (ρ the distance from the axis). The quads
    then vary in size: the factor's range is in ``log_scale_min/max``.
    sharp_angle: None, or degrees: interior edges whose dihedral angle exceeds it are features
    (as in :func:`cross_field`, whose field should follow them: pass it the same sharp_angle);
    where the combed cross follows a feature edge to within 10°, the coordinate across it is
    constant along it and an integer on both sides (MIQ's feature iso-lines), so the feature
    becomes a chain of quad edges. Feature lines and cones less than a quad edge apart are
    rounded onto distinct iso-lines (in their order), and where triangles stay flipped the
    feature edges near them are released and the map solved again (``released_feature_edges``;
    fandisk at 3,000 quads: 0 flips, 675 of its 710 feature edges held, 95% of their length).

    V: (n, 3) float array, F: (m, 3) integer array; field: a :class:`CrossField`, (m,) angles or
    (m, 3) directions. target_edge_length (input units) or target_quads: the grid size; neither:
    twice the mean length of the faces' sides. With target_quads the grid unit starts at
    √(surface area / target_quads) and is calibrated on the continuous map (before the
    rounding) so that it covers target_quads unit squares: the map's gradients are shorter than
    the field's where the field curls, and √(area / quads) alone gave 6–11% fewer quads on the
    shared meshes. ``MiqResult.target_edge_length`` is the unit used.
    Returns a :class:`MiqResult` (unpacks as ``UV, flipped_before, flipped_after``). Across
    every seam edge the two sides' UVs differ by a rotation by k·π/2 and an integer translation;
    singular vertices sit on integer points.
    Raises InputError as :func:`cross_field`, for a field with NaN or of the wrong size, both
    target_edge_length and target_quads, or a non-positive one; Cancelled from `progress`.
    """
    if target_edge_length is not None and target_quads is not None:
        raise InputError("miq: give target_edge_length or target_quads, not both")
    theta = field_angles(V, F, field)
    mesh = on_referenced_vertices(V, F)
    length = grid_length(mesh.V, mesh.F, target_edge_length, target_quads, "miq")
    angle = 0.0
    if sharp_angle is not None:
        angle = float(sharp_angle)
        if not 0 < angle < 180:
            raise InputError(f"miq: sharp_angle must be in (0, 180) degrees, got {sharp_angle}")
    out = _core.miq(mesh.V, mesh.F, theta, target_edge_length=length,
                    target_quads=0.0 if target_quads is None else float(target_quads), round_singularities=round_singularities,
                    round_translations=round_translations, repair_iterations=repair_iterations,
                    stiffening=stiffening, sharp_angle=angle, reround=reround,
                    conformal_scale=conformal_scale, progress=progress)
    return MiqResult(UV=out["uv"], flipped_before=int(out["flipped_before"]), flipped_after=int(out["flipped_after"]),
                     cut=field_cut(out["cut"], mesh, V), integer_variables=int(out["integer_variables"]),
                     rounding_residual=float(out["rounding_residual"]), repair_rounds=int(out["repair_rounds"]),
                     target_edge_length=float(out["target_edge_length"]), feature_edges=int(out["feature_edges"]),
                     separations=int(out["separations"]), separation_conflicts=int(out["separation_conflicts"]),
                     released_feature_edges=int(out["released_feature_edges"]), release_rounds=int(out["release_rounds"]),
                     rerounded_integers=int(out["rerounded_integers"]),
                     flipped_unconstrained=int(out["flipped_unconstrained"]),
                     log_scale_min=float(out["log_scale_min"]), log_scale_max=float(out["log_scale_max"]))


def grid_length(V: ArrayLike, F: ArrayLike, target_edge_length: float | None, target_quads: int | None,
                function: str) -> float:
    """The quad edge length in input units: target_edge_length (checked > 0), else
    √(surface area / target_quads), else twice the mean length of the faces' sides."""
    P = np.asarray(V, dtype=np.float64)
    faces = np.asarray(F, dtype=np.int64)
    if target_edge_length is not None:
        length = float(target_edge_length)
        if not (np.isfinite(length) and length > 0):
            raise InputError(f"{function}: target_edge_length must be a finite number > 0, got {target_edge_length}")
        return length
    if target_quads is not None:
        quads = _arguments.integer(target_quads, "target_quads", 1, 2 ** 40)
        area = 0.5 * np.linalg.norm(np.cross(P[faces[:, 1]] - P[faces[:, 0]], P[faces[:, 2]] - P[faces[:, 0]]), axis=1).sum()
        return float(np.sqrt(area / quads))
    return float(2 * np.linalg.norm(P[faces] - P[np.roll(faces, -1, axis=1)], axis=2).mean())
