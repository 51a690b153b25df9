"""Iterative closest points (§2.3.1) and voxel reduction; binding cpp/python/registration.cpp."""
from __future__ import annotations

from typing import NamedTuple

from .. import _arguments
from .._core import InputError
from .._core import registration as _core
from .._typing import ArrayLike, BoolArray, FloatArray, ProgressCallback

__all__ = ["ICP_METHODS", "IcpResult", "icp", "voxel_downsample"]

ICP_METHODS = ("point_to_point", "point_to_plane")


class IcpResult(NamedTuple):
    """Result of :func:`icp`; unpacks as ``transform, rms, iterations, converged, ...``.

    transform: (4, 4) float64, maps the source onto the target (``initial`` included);
    rms: RMS distance of the inlier pairs at ``transform`` (inf if none is left);
    iterations: iterations run; converged: whether the tolerance was met within max_iterations;
    inlier_fraction: inlier pairs / source points at ``transform``;
    rms_history: (iterations,) RMS of the inlier pairs at the start of each iteration;
    inliers: (n,) bool, per source point, whether its pair is an inlier at ``transform``.
    """
    transform: FloatArray
    rms: float
    iterations: int
    converged: bool
    inlier_fraction: float
    rms_history: FloatArray
    inliers: BoolArray


@_arguments.real_options
def icp(source: ArrayLike, target: ArrayLike, *, method: str = "point_to_point", max_iterations: int = 50,
        tolerance: float = 1e-6, max_distance: float | None = None, trim: float = 1.0,
        voxel_size: float | None = None, target_normals: ArrayLike | None = None, normal_neighbours: int = 16,
        initial: ArrayLike | None = None, threads: int | None = None,
        progress: ProgressCallback = None) -> IcpResult:
    """Rigid registration of ``source`` onto ``target`` by iterative closest points (§2.3.1;
    Besl & McKay 1992, Chen & Medioni 1992; trimmed ICP, Chetverikov et al. 2002).

    source: (n, 3), target: (m, 3) float arrays. Each iteration pairs every source point with
    its closest target point (a kd-tree on the target, built once), rejects outliers, and
    applies the transform that best aligns the pairs:
    method: "point_to_point" (Horn's closed form, :func:`align`) or "point_to_plane" (the
    distance to the target point's tangent plane, linearised; converges in far fewer
    iterations on smooth surfaces).
    max_iterations: at most this many iterations (>= 1). tolerance: converged when an iteration
    rotates by less than this many radians and moves by less than this fraction of the target's
    bounding-box diagonal.
    max_distance: pairs farther apart (input units) are outliers (None: no limit).
    trim: trimmed ICP, keep only this fraction (0, 1] of the closest pairs each iteration
    (e.g. 0.8 when about 20% of the source has no counterpart).
    voxel_size: first reduce both sets to one point per occupied cube of this edge
    (:func:`voxel_downsample`), once; None: use every point.
    target_normals: (m, 3) normals of the target for point-to-plane (any nonzero length, either
    sign); None: estimated by PCA over ``normal_neighbours`` neighbours.
    initial: (4, 4) start transform applied to the source first (None: identity); ICP is local,
    so start within about 30° and a tenth of the size.
    threads: at most this many threads (None: all cores); the result does not depend on it.
    progress: optional ``(fraction, stage) -> bool`` callback.

    Returns an :class:`IcpResult`. Not converging within max_iterations, or losing every pair,
    is reported as ``converged=False``. Raises InputError for empty input, NaN/Inf, an unknown
    method, an option out of range (a zero or negative voxel size or max_distance included), a
    bad initial transform, zero target normals, too few points after the voxel reduction, or a
    max_distance that no pair meets at the start.
    """
    return IcpResult(*_core.icp(source, target, target_normals, method, max_iterations, tolerance,
                                _positive_or_none(max_distance, "max_distance"), trim,
                                _positive_or_none(voxel_size, "voxel_size"), normal_neighbours, initial, threads,
                                progress))


@_arguments.real_options
def voxel_downsample(P: ArrayLike, voxel_size: float) -> FloatArray:
    """One point per occupied cube of edge ``voxel_size`` (a grid anchored at the points'
    minimum corner): the centroid of the points of P (n, 3) in it, the cubes in lexicographic
    order of their integer (x, y, z) coordinates. Returns (k, 3) float64. Raises InputError
    for empty input, NaN/Inf, a voxel size that is not positive and finite, or one so small
    that an axis needs 2**21 cubes or more."""
    return _core.voxel_downsample(P, voxel_size)


def _positive_or_none(value: float | None, name: str) -> float:
    """None → 0 (the core's "off"); an explicit value must be > 0 (0 is a bad parameter, not "off")."""
    if value is None:
        return 0.0
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r}: expected a positive length") from None
    if not number > 0:
        raise InputError(f"{name} = {value}: expected a positive length (None: no {name.replace('_', ' ')})")
    return number
