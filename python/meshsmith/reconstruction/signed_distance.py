"""Signed distance fields: to oriented samples' tangent planes (Hoppe 1992) and to a mesh, signed
by the generalized winding number, and the regular grids to sample them on (§2.2, §3.1);
binding cpp/python/reconstruction.cpp, C++ src/reconstruction/signed_distance.cpp."""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import reconstruction as _core
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback

__all__ = ["MeshSignedDistance", "SampleGrid", "mesh_sdf", "sample_grid", "tangent_plane_sdf", "winding_number"]


class MeshSignedDistance(NamedTuple):
    """The result of :func:`mesh_sdf`; unpacks as ``distance, face, point, winding``.

    distance: (q,) float64 signed distances (negative inside); face: (q,) int64 nearest faces;
    point: (q, 3) float64 closest points; winding: (q,) float64 generalized winding numbers.
    """

    distance: FloatArray
    face: IndexArray
    point: FloatArray
    winding: FloatArray


class SampleGrid(NamedTuple):
    """A regular grid (:func:`sample_grid`); unpacks as ``points, shape, origin, spacing``.

    points: (nx·ny·nz, 3) float64 grid points in C order (``values.reshape(shape)`` gives the
    array :func:`meshsmith.reconstruction.marching_cubes` takes with this origin and spacing).
    """

    points: FloatArray
    shape: tuple[int, int, int]
    origin: FloatArray
    spacing: FloatArray


def tangent_plane_sdf(P: ArrayLike, N: ArrayLike, Q: ArrayLike, *, k: int = 1,
                      progress: ProgressCallback = None) -> FloatArray:
    """Signed distance of query points to the tangent planes of oriented samples (Hoppe et al. 1992).

    P: (n, 3) samples, N: (n, 3) their outward normals (any non-zero length), Q: (q, 3) queries.
    k = 1: ``(q - p) · n`` for the nearest sample p (unit n); k > 1: the blend of the k nearest
    tangent planes with weights ``exp(-(d_i / d_k)^2)``. Returns (q,) float64, negative inside.
    Raises InputError for a zero or NaN normal (naming its row), shapes that do not match, or
    k outside [1, n]. O((n + q k) log n), parallel.
    """
    return _core.tangent_plane_sdf(P, N, Q, k, progress)


@_arguments.real_options
def winding_number(V: ArrayLike, F: ArrayLike, Q: ArrayLike, *, accuracy: float = 4.0,
                   progress: ProgressCallback = None) -> FloatArray:
    """Generalized winding number of the triangle mesh (V, F) at the query points Q (Jacobson et
    al. 2013), evaluated hierarchically: a cluster of triangles farther than `accuracy` times its
    radius contributes its first two Taylor terms (Barill et al. 2018), nearer triangles their
    exact solid angle. 1 inside a closed outward mesh, 0 outside, in between near holes.

    V: (n, 3), F: (m, 3), Q: (q, 3); accuracy >= 1 (larger: slower, more accurate). Returns (q,)
    float64. Raises InputError for an invalid mesh, a NaN query or a bad accuracy.
    O(m log m + q log m), parallel.
    """
    return _core.winding_number(V, F, Q, accuracy, progress)


def mesh_sdf(V: ArrayLike, F: ArrayLike, Q: ArrayLike, *, progress: ProgressCallback = None) -> MeshSignedDistance:
    """Signed distance of the query points Q to the triangle mesh (V, F).

    The distance is exact (the geometry chapter's AABB tree, :class:`meshsmith.geometry.SurfaceDistance`);
    the sign is negative where the generalized winding number (:func:`winding_number`) is at
    least 1/2, so meshes with holes or several components still get a sensible sign (as
    ``igl.signed_distance`` with the winding-number sign). V: (n, 3), F: (m, 3), Q: (q, 3).
    Returns a :class:`MeshSignedDistance`. Raises InputError for an invalid mesh or a NaN query.
    """
    return MeshSignedDistance(**_core.mesh_sdf(V, F, Q, progress))


def sample_grid(bounds: ArrayLike, resolution: int) -> SampleGrid:
    """A regular grid over a box with equal spacing on every axis.

    bounds: (2, 3) float array, the box's lower and upper corners (upper > lower on every axis).
    resolution: points along the longest axis (>= 2); the spacing is that axis' length divided by
    resolution - 1, and every axis gets ceil(length / spacing) + 1 points (so the grid covers the
    box). Returns a :class:`SampleGrid`. Raises InputError for bad bounds or resolution, or more
    than 2^26 points.
    """
    box = _arguments.finite(_arguments.real_array(bounds, "bounds", 3), "bounds")
    if box.shape != (2, 3):
        raise InputError(f"bounds has shape {box.shape}: expected (2, 3), the lower and upper corners")
    n = _arguments.integer(resolution, "resolution", 2, 2 ** 20)
    extent = box[1] - box[0]
    if np.any(extent <= 0):
        axis = int(np.argmax(extent <= 0))
        raise InputError(f"bounds: upper[{axis}] = {box[1, axis]} is not above lower[{axis}] = {box[0, axis]}")
    h = float(extent.max()) / (n - 1)
    shape = tuple(int(np.ceil(e / h - 1e-9)) + 1 for e in extent)
    if np.prod(shape, dtype=float) > _arguments.MAX_ELEMENTS:
        raise InputError(f"sample_grid of shape {shape}: more than 2^26 points")
    axes = [box[0, a] + h * np.arange(shape[a]) for a in range(3)]
    points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return SampleGrid(points, (shape[0], shape[1], shape[2]), box[0].copy(), np.full(3, h))
