"""Iterative closest points (§2.3.1) and voxel reduction; binding cpp/python/registration.cpp."""
from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import registration as _core
from .._typing import ArrayLike, BoolArray, FloatArray, ProgressCallback

__all__ = ["ICP_METHODS", "IcpResult", "icp", "IcpMultiResult", "icp_multi", "voxel_downsample"]

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
        voxel_size: float | None = None, normal_angle: float | None = None, target_normals: ArrayLike | None = None,
        source_normals: ArrayLike | None = None, normal_neighbours: int = 16,
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
    normal_angle: normal compatibility (Rusinkiewicz & Levoy 2001), degrees in (0, 90]: a pair
    whose normals (the source's turned by the current rotation, the target's) differ by more is
    rejected, like one beyond max_distance, before trimming; normals are compared as lines
    (either sign), as estimated normals are unoriented. None: off.
    target_normals: (m, 3) normals of the target for point-to-plane or normal_angle (any nonzero
    length, either sign); None: estimated by PCA over ``normal_neighbours`` neighbours, once.
    source_normals: (n, 3) normals of the source for normal_angle (in the source's own frame);
    None: estimated the same way.
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
                                progress, source_normals, _normal_angle(normal_angle)))


class IcpMultiResult(NamedTuple):
    """Result of :func:`icp_multi`; unpacks as ``transforms, rms, inlier_fraction, ...``.

    transforms: (k, 4, 4) float64, transforms[i] maps scan i into the common frame (the first
    scan's; transforms[0] is its start pose, the identity by default);
    rms: (k,) RMS distance of each scan's inlier pairs with the union of the other scans at the
    final poses; inlier_fraction: (k,) those inlier pairs / the scan's (reduced) points;
    scan_converged: (k,) bool, whether each scan's last registration converged (the first: True);
    rounds: refinement rounds run; converged: every registration converged and the last round
    moved no pose by more than the tolerance.
    """
    transforms: FloatArray
    rms: FloatArray
    inlier_fraction: FloatArray
    scan_converged: BoolArray
    rounds: int
    converged: bool


@_arguments.real_options
def icp_multi(scans: Sequence[ArrayLike], *, method: str = "point_to_plane", max_iterations: int = 50,
              tolerance: float = 1e-6, max_distance: float | None = None, trim: float = 0.7,
              voxel_size: float | None = None, normal_angle: float | None = None, normal_neighbours: int = 16,
              initial: ArrayLike | Sequence[ArrayLike] | None = None, rounds: int = 10, round_tolerance: float = 1e-3,
              threads: int | None = None, progress: ProgressCallback = None) -> IcpMultiResult:
    """Registration of several scans into one frame (§2.3.1): the first scan anchors the frame;
    each later scan is registered by :func:`icp` onto the union of the earlier ones (a growing
    model, Chen & Medioni 1992), then ``rounds`` refinement rounds register every scan but the
    first onto the union of all the others at their current poses (Bergevin et al. 1996, Pulli
    1999), which spreads the error accumulated along the sequence and closes loops; the rounds
    stop once no pose moves in a round by more than ``round_tolerance`` (radians, and diagonals
    of the largest scan: the poses settle slowly, as each fit moves the others' targets).

    scans: a sequence of k >= 2 arrays (n_i, 3). Each is reduced once (voxel_size) and gets PCA
    normals once (``normal_neighbours``; for point-to-plane or normal_angle), turned along with
    its pose. Scans overlap only partly, hence the default ``trim=0.7`` (each registration keeps
    the closest 70% of its pairs); max_distance, normal_angle, method, max_iterations, tolerance
    as in :func:`icp`. initial: k start poses (4, 4) (a (k, 4, 4) array or a sequence), or None
    for the identity; the scans must start within ICP's reach of each other. threads, progress
    as in :func:`icp`; the result does not depend on the thread count.

    Returns an :class:`IcpMultiResult`. Non-convergence is reported (``converged=False``), not
    raised. Raises InputError for fewer than 2 scans, a scan that is not an (n, 3) finite array
    or has fewer than 3 points (after the reduction), ``initial`` of the wrong length or shape,
    rounds < 0, a round_tolerance that is not positive, or an option icp() rejects (naming the scan where one is concerned).
    """
    if isinstance(scans, np.ndarray) and scans.ndim == 3:
        scans = list(scans)
    if not isinstance(scans, (list, tuple)):
        raise InputError(f"scans is a {type(scans).__name__}: expected a list of (n, 3) arrays")
    points = [_arguments.finite(_arguments.real_array(scan, f"scans[{i}]", 3), f"scans[{i}]")
              for i, scan in enumerate(scans)]
    if len(points) < 2:
        raise InputError(f"scans has {len(points)} scan(s): expected at least 2")
    poses = None
    if initial is not None:
        stacked: list[object]
        if isinstance(initial, (list, tuple)):
            stacked = list(initial)
        else:
            array = np.asarray(initial)
            stacked = [array] if array.ndim == 2 else list(array) if array.ndim == 3 else [array]
        poses = [_arguments.finite(_arguments.real_array(T, f"initial[{i}]", 4), f"initial[{i}]")
                 for i, T in enumerate(stacked)]
    rounds = _arguments.integer(rounds, "rounds", 0, 1000)
    transforms, rms, fraction, scan_converged, rounds_run, converged = _core.icp_multi(
        points, method, max_iterations, tolerance, _positive_or_none(max_distance, "max_distance"), trim,
        _positive_or_none(voxel_size, "voxel_size"), _normal_angle(normal_angle), normal_neighbours, poses, rounds,
        round_tolerance, threads, progress)
    return IcpMultiResult(transforms, rms, fraction, scan_converged, int(rounds_run), bool(converged))


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


def _normal_angle(value: float | None) -> float:
    """normal_angle in degrees (None: off) → radians for the core; (0, 90] or an InputError."""
    if value is None:
        return 0.0
    if not 0 < value <= 90:
        raise InputError(f"normal_angle = {value}: expected an angle in (0, 90] degrees (None: no normal test)")
    return float(np.radians(value))
