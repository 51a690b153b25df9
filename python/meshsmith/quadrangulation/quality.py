"""Quality of a quad mesh (§5.2): corner angles, scaled Jacobians, aspect ratios, valences."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._arguments import finite, index_array, real_array
from .._core import InputError
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray

__all__ = ["QuadQuality", "quad_quality"]


@dataclass(frozen=True)
class QuadQuality(Unpackable):
    """The result of :func:`quad_quality`; unpacks in field order.

    angles: (k, 4) float64 corner angles in degrees (corner c between the edges to corners c-1 and
    c+1). angle_deviation: (k,) float64, max over the corners of |angle - 90|. scaled_jacobian: (k,)
    float64, min over the corners of (e_next × e_prev)·n / (|e_next| |e_prev|) with n the quad's
    (Newell) unit normal: 1 for a rectangle, sin(angle) at a convex corner, <= 0 at a reflex or
    folded one. aspect_ratio: (k,) float64, longest over shortest edge. valence: (n,) int64, the
    number of quads at each vertex (0 for vertices no quad uses); valence_histogram: (d+1,) int64,
    how many used vertices have each valence (entry 0 is 0).
    """

    angles: FloatArray
    angle_deviation: FloatArray
    scaled_jacobian: FloatArray
    aspect_ratio: FloatArray
    valence: IndexArray
    valence_histogram: IndexArray


def quad_quality(V: ArrayLike, Q: ArrayLike) -> QuadQuality:
    """Corner angles, scaled Jacobians, aspect ratios and valences of a quad mesh (§5.2).

    V: (n, 3) float array (or (n, 2): read as z = 0); Q: (k, 4) integer array, each quad's corners
    in order around it. Returns a :class:`QuadQuality`. Raises InputError for NaN/Inf, indices out
    of range, or a quad with a zero-length edge.
    """
    points = finite(real_array(V, "V", (2, 3)), "V")
    quads = index_array(Q, "Q", 4).astype(np.int64)
    if points.shape[1] == 2:
        points = np.column_stack([points, np.zeros(len(points))])
    if len(quads) and (quads.min() < 0 or quads.max() >= len(points)):
        bad = int(np.argmax((quads < 0).any(1) | (quads >= len(points)).any(1)))
        raise InputError(f"Q[{bad}] = {quads[bad].tolist()} indexes outside V (n = {len(points)})")
    angles, jacobian, lengths = corner_measures(points, quads)
    valence = np.bincount(quads.ravel(), minlength=len(points)).astype(np.int64)
    histogram = np.bincount(valence[valence > 0]).astype(np.int64) if len(quads) else np.zeros(1, np.int64)
    return QuadQuality(
        angles=angles,
        angle_deviation=np.abs(angles - 90.0).max(axis=1) if len(quads) else np.zeros(0),
        scaled_jacobian=jacobian,
        aspect_ratio=lengths.max(axis=1) / lengths.min(axis=1) if len(quads) else np.zeros(0),
        valence=valence,
        valence_histogram=histogram,
    )


def corner_measures(points: FloatArray, quads: IndexArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The corner angles (k, 4) in degrees, the per-quad scaled Jacobian (k,) and the edge lengths
    (k, 4) of :func:`quad_quality`, without its argument checks (points (n, 3) float64 and quads
    (k, 4) int64 already checked): the smoothing in :func:`quadrangulate` measures every round.
    Raises InputError for a quad with a zero-length edge."""
    P = points[quads]                                   # (k, 4, 3)
    forward = np.roll(P, -1, axis=1) - P                # corner c → c+1
    backward = np.roll(P, 1, axis=1) - P                # corner c → c-1
    lengths = np.linalg.norm(forward, axis=2)
    if len(quads) and not (lengths > 0).all():
        bad = int(np.argmax((lengths <= 0).any(1)))
        raise InputError(f"Q[{bad}] = {quads[bad].tolist()} has a zero-length edge")
    back_lengths = np.roll(lengths, 1, axis=1)
    cosine = np.einsum("kcd,kcd->kc", forward, backward) / (lengths * back_lengths)
    angles = np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))
    jacobian = corner_jacobians(P, forward, backward, lengths * back_lengths)
    return angles, jacobian.min(axis=1) if len(quads) else np.zeros(0), lengths


def corner_jacobians(P: FloatArray, forward: FloatArray | None = None, backward: FloatArray | None = None,
                     length_products: FloatArray | None = None) -> FloatArray:
    """The scaled Jacobian of every corner of quads given by their corners, P (..., 4, 3) float64:
    (e_next × e_prev)·n / (|e_next| |e_prev|), n the quad's (Newell) unit normal; returns (..., 4).
    forward, backward (P[c+1] − P[c], P[c−1] − P[c]) and the products of their lengths may be passed
    when known. A corner with a zero-length edge gets −1 (the worst value), so that a batch of
    trial positions (the untangling after :func:`spectral_quadrangulate`) can be measured at once."""
    if forward is None or backward is None or length_products is None:
        forward = np.roll(P, -1, axis=-2) - P
        backward = np.roll(P, 1, axis=-2) - P
        length_products = np.linalg.norm(forward, axis=-1) * np.linalg.norm(backward, axis=-1)
    normal = np.cross(P, np.roll(P, -1, axis=-2)).sum(axis=-2)   # Newell: twice the vector area
    norm = np.linalg.norm(normal, axis=-1, keepdims=True)
    normal = np.divide(normal, norm, out=np.zeros_like(normal), where=norm > 0)
    numerator = np.einsum("...cd,...d->...c", np.cross(forward, backward), normal)
    return np.divide(numerator, length_products, out=np.full_like(numerator, -1.0), where=length_products > 0)
