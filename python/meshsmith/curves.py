"""Discrete curves (§1.1): arc length, arc-length resampling, tangents, normals, curvature.

A curve is a polyline P, an (n, 2) or (n, 3) float array of points, open (n - 1 segments) or
closed (`closed=True`: a segment joins the last point back to the first; do not repeat the
first point at the end — if you do, it is treated as a repeated point, see below).

Discrete operators (§1.1.3). At an interior point p_i with incoming edge e- = p_i - p_(i-1)
and outgoing edge e+ = p_(i+1) - p_i, of lengths h- and h+, and unit directions d-, d+:

* tangent: the derivative of the quadratic through p_(i-1), p_i, p_(i+1) parametrized by chord
  length, t = (h- d+ + h+ d-) / (h- + h+), normalized (the central difference for uniform
  spacing; second order also for non-uniform spacing);
* curvature vector: the second derivative of the same quadratic, f'' = 2 (d+ - d-) / (h- + h+)
  (the second difference ||p_(i+1) - 2 p_i + p_(i-1)|| / h^2 for uniform spacing).

Conventions that apply to every function:

* Endpoints of open curves have one neighbour only: their tangent is the direction of their
  single edge, their curvature and normal are copied from the adjacent interior point.
* Repeated consecutive points (zero-length edges, including a closed curve's last point equal
  to its first) are skipped: a repeated point gets the values of the point it repeats, and
  contributes nothing to arc length.
* Bad input (not a real (n, 2) / (n, 3) array, NaN/Inf, too few distinct points) raises
  :class:`meshsmith.InputError`.

Everything here is a few vectorized numpy array expressions, O(n), no per-point Python loop.
"""
from __future__ import annotations

import numpy as np

from . import _arguments
from ._core import InputError
from ._core import core as _core
from ._deprecation import positional_options
from ._typing import ArrayLike, FloatArray

__all__ = ["arc_length", "arc_length_parametrization", "tangents", "normals", "curvature"]

CURVATURE_METHODS = ("turning_angle", "osculating_circle", "second_difference")


# --- input handling ---------------------------------------------------------------------------

def _as_curve(P: ArrayLike, name: str = "P") -> FloatArray:
    return _arguments.finite(_arguments.real_array(P, name, (2, 3)), name)


def _normalized_curve(P: ArrayLike, name: str = "P") -> tuple[FloatArray, int]:
    """The validated curve scaled into (-1, 1) by 2^-exponent (core/normalization.h; exact), and
    the exponent. Every operator here is scale-invariant, so each runs on these coordinates:
    curves of size 1e-300 or 1e300 give the answers of size 1 (edge lengths of 1e-300 squared
    underflowed to 0 and of 1e300 overflowed, which made NaN tangents and curvatures)."""
    P = _as_curve(P, name)
    exponent = _core.normalizing_exponent(P) if P.size else 0
    return np.ldexp(P, -exponent), exponent


def _to_input(values: np.ndarray, exponent: int, power: int, what: str) -> np.ndarray:
    """A result of unit length^power computed on normalized coordinates, in input units.
    Raises InputError if it leaves the double range."""
    with np.errstate(over="ignore"):  # reported below, with the index
        result = np.ldexp(values, power * exponent)
    overflowed = np.isfinite(values) & ~np.isfinite(result)
    if overflowed.any():
        index = int(np.flatnonzero(overflowed.ravel())[0])
        raise InputError(f"{what} at index {index} exceeds the double range (about 1.8e308) for a curve "
                         f"of size 2^{exponent}; scale the curve")
    return result


def _norms(X: np.ndarray) -> np.ndarray:
    """Row norms by np.hypot (no overflow or underflow of the squares): a curve with one point at
    1e300 next to points 1 apart keeps its small edges, which become 1e-300 once normalized."""
    result = np.abs(X[:, 0])
    for column in range(1, X.shape[1]):
        result = np.hypot(result, X[:, column])
    return result


def _distinct(P: FloatArray, closed: bool, minimum: int, what: str) -> tuple[FloatArray, np.ndarray]:
    """Drops repeated consecutive points. Returns (distinct points, index of the distinct point
    each original point stands for)."""
    same_as_previous = np.zeros(len(P), dtype=bool)
    same_as_previous[1:] = np.all(P[1:] == P[:-1], axis=1)
    keep = ~same_as_previous
    representative = np.cumsum(keep) - 1
    distinct = P[keep]
    if closed and len(distinct) > 1 and np.all(distinct[-1] == distinct[0]):
        # the closing run repeats the first point
        representative[representative == len(distinct) - 1] = 0
        distinct = distinct[:-1]
    if len(distinct) < minimum:
        kind = "closed" if closed else "open"
        raise InputError(f"P has {len(distinct)} distinct consecutive points: {what} of an {kind} "
                         f"curve needs at least {minimum}")
    return distinct, representative


def _edges(P: np.ndarray, closed: bool) -> np.ndarray:
    """Edge vectors p_(i+1) - p_i; n - 1 of them (open) or n (closed, the last closes)."""
    following = np.roll(P, -1, axis=0) if closed else P[1:]
    return following - (P if closed else P[:-1])


def _interior_stencils(P: FloatArray, closed: bool
                       ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """For each point that has two neighbours: (d-, d+, h-, h+). Closed: all n points;
    open: points 1 .. n-2."""
    edges = _edges(P, closed)
    lengths = _norms(edges)
    directions = edges / lengths[:, None]
    if closed:
        return np.roll(directions, 1, axis=0), directions, np.roll(lengths, 1), lengths
    return directions[:-1], directions[1:], lengths[:-1], lengths[1:]


def _with_open_ends(interior: np.ndarray, closed: bool) -> np.ndarray:
    """Open curves: endpoint values copied from the adjacent interior point."""
    if closed:
        return interior
    return np.concatenate([interior[:1], interior, interior[-1:]], axis=0)


# --- arc length -------------------------------------------------------------------------------

@positional_options("closed")
def arc_length(P: ArrayLike, *, closed: bool = False) -> FloatArray:
    """Cumulative arc length s of the polyline (§1.1.1, s(u) = ∫ ||f'||).

    P: (n, 2) or (n, 3) points, n >= 2. Returns s, (n,) float64 for an open curve (s[0] = 0,
    s[-1] = total length) or (n + 1,) for a closed one (s[n] = total length including the
    closing segment). Repeated points add 0.
    """
    P, exponent = _normalized_curve(P)
    if len(P) < 2:
        raise InputError(f"P has {len(P)} points: arc length needs at least 2")
    lengths = _norms(_edges(P, closed))
    return _to_input(np.concatenate([[0.0], np.cumsum(lengths)]), exponent, 1, "the arc length")


@positional_options("closed")
def arc_length_parametrization(P: ArrayLike, n: int | None = None, *, closed: bool = False) -> FloatArray:
    """Resamples the polyline at n points equally spaced in arc length (§1.1.1).

    P: (m, 2) or (m, 3) points with at least 2 distinct ones (3 if closed). n: number of
    output points (default m), n >= 2 (3 if closed). Open: the samples run from P[0] to P[-1]
    inclusive, n - 1 equal steps. Closed: they start at P[0] and take n equal steps around the
    loop (the first point is not repeated). Points are on the polyline (linear interpolation).
    Returns (n, d) float64.
    """
    P, exponent = _normalized_curve(P)
    P, _ = _distinct(P, closed, 3 if closed else 2, "arc-length resampling")
    n = len(P) if n is None else _arguments.integer(n, "n", 3 if closed else 2, _arguments.MAX_ELEMENTS)
    loop = np.vstack([P, P[:1]]) if closed else P
    s = arc_length(loop)
    total = s[-1]
    targets = total * np.arange(n) / (n if closed else n - 1)
    samples = np.stack([np.interp(targets, s, loop[:, c]) for c in range(P.shape[1])], axis=1)
    return _to_input(samples, exponent, 1, "a resampled point")


# --- tangents, curvature vectors, normals -----------------------------------------------------

@positional_options("closed")
def tangents(P: ArrayLike, *, closed: bool = False) -> FloatArray:
    """Unit tangents (§1.1.3), (n, d) float64: at interior points the derivative of the
    quadratic through the point and its two neighbours (chord-length parameter), at the ends of
    an open curve the direction of the end edge, where the curve doubles back exactly
    (p_(i+1) = p_(i-1)) the outgoing edge's direction. P: (n, d) with >= 2 distinct points (3 closed).
    """
    P, _ = _normalized_curve(P)
    distinct, representative = _distinct(P, closed, 3 if closed else 2, "tangents")
    edges = _edges(distinct, closed)
    directions = edges / _norms(edges)[:, None]
    if len(distinct) == 2:  # open segment
        return directions[[0, 0]][representative]
    d_in, d_out, h_in, h_out = _interior_stencils(distinct, closed)
    t = (h_in[:, None] * d_out + h_out[:, None] * d_in) / (h_in + h_out)[:, None]
    size = np.linalg.norm(t, axis=1)
    reversal = size <= 1e-12  # the curve doubles back on itself: take the outgoing edge
    t[reversal] = d_out[reversal]
    t[~reversal] /= size[~reversal][:, None]
    if not closed:
        t = np.concatenate([directions[:1], t, directions[-1:]], axis=0)
    return t[representative]


def _curvature_vectors(distinct: np.ndarray, closed: bool) -> np.ndarray:
    d_in, d_out, h_in, h_out = _interior_stencils(distinct, closed)
    return 2.0 * (d_out - d_in) / (h_in + h_out)[:, None]


@positional_options("closed")
def normals(P: ArrayLike, *, closed: bool = False) -> FloatArray:
    """Unit normals (§1.1: n = f'^⊥ / ||f'^⊥||), (n, d) float64.

    2D: the tangent turned 90° counter-clockwise, (-t_y, t_x) (points inward on a
    counter-clockwise closed curve). 3D: the discrete Frenet normal, the direction of the
    component of the curvature vector orthogonal to the tangent. Where the curvature vanishes
    (relative size below 1e-9 of the local edge length's inverse) the 3D normal is undefined:
    it is taken from the nearest point where it is defined (projected orthogonal to the local
    tangent); on a straight line, a fixed unit vector orthogonal to the tangent.
    P: (n, d) with >= 3 distinct points.
    """
    P, _ = _normalized_curve(P)
    distinct, representative = _distinct(P, closed, 3, "normals")
    t = tangents(distinct, closed=closed)
    if distinct.shape[1] == 2:
        return np.stack([-t[:, 1], t[:, 0]], axis=1)[representative]
    kappa_vector = _with_open_ends(_curvature_vectors(distinct, closed), closed)
    perpendicular = kappa_vector - (kappa_vector * t).sum(axis=1)[:, None] * t
    size = _norms(perpendicular)
    _, _, h_in, h_out = _interior_stencils(distinct, closed)
    local_length = _with_open_ends(np.minimum(h_in, h_out), closed)
    defined = size * local_length > 1e-9
    if defined.any():
        # nearest defined point (along the index; cyclically for closed curves)
        index = np.arange(len(distinct))
        defined_index = index[defined]
        if closed:
            candidates = np.concatenate([defined_index - len(distinct), defined_index,
                                         defined_index + len(distinct)])
        else:
            candidates = defined_index
        position = np.clip(np.searchsorted(candidates, index), 1, len(candidates) - 1)
        left, right = candidates[position - 1], candidates[position]
        nearest = np.where(index - left <= right - index, left, right) % len(distinct)
        source = np.where(defined[:, None], perpendicular, perpendicular[nearest])
    else:
        axis = np.argmin(np.abs(t[0]))
        source = np.tile(np.eye(3)[axis], (len(distinct), 1))
    source = source - (source * t).sum(axis=1)[:, None] * t
    return (source / np.linalg.norm(source, axis=1)[:, None])[representative]


# --- curvature --------------------------------------------------------------------------------

@positional_options("closed", "method", "signed")
def curvature(P: ArrayLike, *, closed: bool = False, method: str = "turning_angle",
              signed: bool = False) -> FloatArray:
    """Discrete curvature κ at each point (§1.1.3), (n,) float64.

    method:
      * "turning_angle": θ_i / ((h- + h+) / 2), the angle between the incoming and outgoing
        edges over the dual edge length (half the adjacent edges);
      * "osculating_circle": 1 / radius of the circle through p_(i-1), p_i, p_(i+1)
        (2 sin θ_i / ||p_(i+1) - p_(i-1)||; 0 for collinear points, 2 / h where the curve
        doubles back onto its previous point);
      * "second_difference": ||f''|| for the quadratic through the three points parametrized
        by chord length, 2 ||d+ - d-|| / (h- + h+) (= ||p_(i+1) - 2 p_i + p_(i-1)|| / h^2 for
        uniform spacing h).
    signed (2D only): κ > 0 where the curve turns counter-clockwise (left), < 0 where it turns
    clockwise. Endpoints of open curves copy their neighbour's value.
    P: (n, d) with >= 3 distinct points.
    """
    if method not in CURVATURE_METHODS:
        raise InputError(f"method = {method!r}: expected one of {', '.join(CURVATURE_METHODS)}")
    P, exponent = _normalized_curve(P)
    if signed and P.shape[1] != 2:
        raise InputError("signed curvature is defined for planar (n, 2) curves only")
    distinct, representative = _distinct(P, closed, 3, "curvature")
    d_in, d_out, h_in, h_out = _interior_stencils(distinct, closed)
    if distinct.shape[1] == 2:
        sine = d_in[:, 0] * d_out[:, 1] - d_in[:, 1] * d_out[:, 0]  # signed, left turn > 0
    else:
        sine = np.linalg.norm(np.cross(d_in, d_out), axis=1)
    cosine = (d_in * d_out).sum(axis=1)
    turning = np.arctan2(np.abs(sine), cosine)
    if method == "turning_angle":
        kappa = turning / (0.5 * (h_in + h_out))
    elif method == "osculating_circle":
        chord = _norms(h_in[:, None] * d_in + h_out[:, None] * d_out)
        reversal = chord <= 1e-12 * (h_in + h_out)
        # at an exact reversal (p_(i+1) = p_(i-1)) the circle has diameter h
        kappa = np.where(reversal, 2.0 / np.maximum(h_in, h_out),
                         2.0 * np.abs(sine) / np.where(reversal, 1.0, chord))
    else:
        kappa = 2.0 * np.linalg.norm(d_out - d_in, axis=1) / (h_in + h_out)
    if signed:
        kappa = np.where(sine < 0, -kappa, kappa)
    return _to_input(_with_open_ends(kappa, closed)[representative], exponent, -1, "the curvature")
