"""Iterative closest points (§2.3.1) and voxel reduction; binding cpp/python/registration.cpp."""
from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import registration as _core
from .._typing import ArrayLike, BoolArray, FloatArray, IndexArray, ProgressCallback

__all__ = ["ICP_METHODS", "IcpResult", "icp", "IcpMultiResult", "icp_multi", "voxel_downsample"]

ICP_METHODS = ("point_to_point", "point_to_plane")


class IcpResult(NamedTuple):
    """Result of :func:`icp`; unpacks as ``transform, rms, iterations, converged, ...``.

    transform: (4, 4) float64, maps the source onto the target (``initial`` included);
    rms: RMS distance of the inlier pairs at ``transform`` (inf if none is left);
    iterations: iterations run; converged: whether a convergence test was met within
    max_iterations (which one: ``stop``);
    inlier_fraction: inlier pairs / source points at ``transform``;
    rms_history: (iterations,) RMS of the inlier pairs at the start of each iteration;
    inliers: (n,) bool, per source point, whether its pair is an inlier at ``transform``;
    stop: why the iterations ended: converged by "tolerance", "relative_change", "cycle" or
    "stalled" (see :func:`icp`), not converged by "max_iterations", "lost_pairs" (too few pairs
    left within max_distance) or "singular" (no finite point-to-plane step).
    """
    transform: FloatArray
    rms: float
    iterations: int
    converged: bool
    inlier_fraction: float
    rms_history: FloatArray
    inliers: BoolArray
    stop: str


@_arguments.real_options
def icp(source: ArrayLike, target: ArrayLike, *, method: str = "point_to_point", max_iterations: int = 50,
        tolerance: float = 1e-6, max_distance: float | None = None, trim: float = 1.0,
        voxel_size: float | None = None, normal_angle: float | None = None, target_normals: ArrayLike | None = None,
        source_normals: ArrayLike | None = None, normal_neighbours: int = 16,
        initial: ArrayLike | None = None, relative_rmse: float = 1e-6, relative_fitness: float = 1e-6,
        patience: int = 10, threads: int | None = None, progress: ProgressCallback = None) -> IcpResult:
    """Rigid registration of ``source`` onto ``target`` by iterative closest points (§2.3.1;
    Besl & McKay 1992, Chen & Medioni 1992; trimmed ICP, Chetverikov et al. 2002).

    source: (n, 3), target: (m, 3) float arrays. Each iteration pairs every source point with
    its closest target point (a kd-tree on the target, built once), rejects outliers, and
    applies the transform that best aligns the pairs:
    method: "point_to_point" (Horn's closed form, :func:`align`) or "point_to_plane" (the
    distance to the target point's tangent plane, linearised; converges in far fewer
    iterations on smooth surfaces).
    max_iterations: at most this many iterations (>= 1). Convergence, the first test met
    (``IcpResult.stop`` names it):
    "tolerance": an iteration rotates by less than ``tolerance`` radians and moves by less than
    ``tolerance`` times the target's bounding-box diagonal;
    "relative_change" (Open3D's relative_rmse / relative_fitness, here relative to the values):
    from one iteration to the next the inlier RMS changes by at most ``relative_rmse`` of itself
    and the inlier count by at most ``relative_fitness`` of itself (relative_rmse=0: off);
    "cycle": the pairs repeat those of 2 .. ``patience`` iterations earlier, or the pose comes
    back to within ``tolerance`` of one of those poses; "stalled": no iteration of the last
    ``patience`` lowered the least RMS so far by more than ``relative_rmse`` of it nor raised the
    most inliers so far by more than ``relative_fitness`` of it (with max_distance, pairs join as
    the alignment improves, which may raise the RMS). A cycle or a stall is an oscillation
    between pair sets that differ at a rejection threshold (trim, max_distance), at the noise
    level, which a pose tolerance alone never ends; the result is then the pose of least inlier
    RMS among the last ``patience`` iterations. patience=0: neither test.
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

    Returns an :class:`IcpResult`. Not converging within max_iterations, or losing the pairs,
    is reported as ``converged=False`` with the reason in ``stop``. Raises InputError for empty
    input, NaN/Inf, an unknown method, an option out of range (a zero or negative voxel size or
    max_distance, a negative relative_rmse or relative_fitness, patience 1 or < 0 included), a
    bad initial transform, zero target normals, too few points after the voxel reduction, or a
    max_distance that no pair meets at the start.
    """
    return IcpResult(*_core.icp(source, target, target_normals, method, max_iterations, tolerance,
                                _positive_or_none(max_distance, "max_distance"), trim,
                                _positive_or_none(voxel_size, "voxel_size"), normal_neighbours, initial, threads,
                                progress, source_normals, _normal_angle(normal_angle), relative_rmse,
                                relative_fitness, patience))


class IcpMultiResult(NamedTuple):
    """Result of :func:`icp_multi`; unpacks as ``transforms, rms, inlier_fraction, ...``.

    transforms: (k, 4, 4) float64, transforms[i] maps scan i into the common frame (the first
    scan's; transforms[0] is its start pose, the identity by default);
    rms: (k,) RMS distance of each scan's inlier pairs with the union of the other scans at the
    final poses; inlier_fraction: (k,) those inlier pairs / the scan's (reduced) points;
    scan_converged: (k,) bool, whether each scan's last registration converged (the first: True);
    rounds: refinement rounds run (strategy "pose_graph": Gauss–Newton iterations of the global
    solve); converged: every registration converged and the last round (iteration) moved no
    pose by more than the tolerance (pose graph: and every scan is connected to the first);
    edges: (e, 2) int64, the pairs (i, j), i < j, of overlapping scans that are the pose graph's
    edges (strategy "growing": empty).
    """
    transforms: FloatArray
    rms: FloatArray
    inlier_fraction: FloatArray
    scan_converged: BoolArray
    rounds: int
    converged: bool
    edges: IndexArray


@_arguments.real_options
def icp_multi(scans: Sequence[ArrayLike], *, method: str = "point_to_plane", max_iterations: int = 50,
              tolerance: float = 1e-6, max_distance: float | None = None, trim: float = 0.7,
              voxel_size: float | None = None, normal_angle: float | None = None, normal_neighbours: int = 16,
              initial: ArrayLike | Sequence[ArrayLike] | None = None, rounds: int = 10, round_tolerance: float = 1e-3,
              relative_rmse: float = 1e-6, relative_fitness: float = 1e-6, patience: int = 10,
              strategy: str = "growing", overlap_distance: float | None = None, min_overlap: float = 0.2,
              edge_samples: int = 2000, threads: int | None = None,
              progress: ProgressCallback = None) -> IcpMultiResult:
    """Registration of several scans into one frame (§2.3.1, multi-view registration); the
    first scan anchors the frame (its pose stays its start pose). Two strategies:

    ``strategy="pose_graph"``: every pair of scans i < j is registered by :func:`icp` (scan j
    onto scan i, from their start poses); a pair is an edge of the pose graph when at least
    ``min_overlap`` of scan j's points then lie within ``overlap_distance`` (input units; None:
    0.5% of the largest scan's diagonal; 2–3 times the noise suits) of scan i, those points (at
    most ``edge_samples``, evenly spaced) its samples. The poses start from the pairwise results
    composed along a spanning tree from the first scan; then a multi-view ICP refines them all at
    once: each iteration pairs every edge's samples with their closest points at the current
    poses and takes one Gauss–Newton step of the sum over the edges of ‖X_i p − X_j q‖²
    (point-to-plane: its component along the normal at p) over linearised rotations (Pulli
    1999; Lu & Milios 1997 for the graph), at most ``rounds`` iterations, until no pose moves by
    more than ``round_tolerance``. The error is spread over every loop of the graph at once, not
    along the order of the scans. A scan with no chain of edges to the first keeps its start
    pose and is reported (``scan_converged`` False, ``converged`` False).

    ``strategy="growing"`` (default): each later scan is registered by :func:`icp` onto the
    union of the earlier ones (a growing
    model, Chen & Medioni 1992), then ``rounds`` refinement rounds register every scan but the
    first onto the union of all the others at their current poses (Bergevin et al. 1996, Pulli
    1999), which spreads the error accumulated along the sequence and closes loops; the rounds
    stop once no pose moves in a round by more than ``round_tolerance`` (radians, and diagonals
    of the largest scan: the poses settle slowly, as each fit moves the others' targets).

    scans: a sequence of k >= 2 arrays (n_i, 3). Each is reduced once (voxel_size) and gets PCA
    normals once (``normal_neighbours``; for point-to-plane or normal_angle), turned along with
    its pose. Scans overlap only partly, hence the default ``trim=0.7`` (each registration keeps
    the closest 70% of its pairs); max_distance, normal_angle, method, max_iterations, tolerance,
    relative_rmse, relative_fitness, patience as in :func:`icp`. initial: k start poses (4, 4) (a (k, 4, 4) array or a sequence), or None
    for the identity; the scans must start within ICP's reach of each other. threads, progress
    as in :func:`icp`; the result does not depend on the thread count.

    Returns an :class:`IcpMultiResult`. Non-convergence is reported (``converged=False``), not
    raised. Raises InputError for fewer than 2 scans, a scan that is not an (n, 3) finite array
    or has fewer than 3 points (after the reduction), ``initial`` of the wrong length or shape,
    rounds < 0 (< 1 for the pose graph), a round_tolerance that is not positive, an unknown
    strategy, overlap_distance <= 0, min_overlap outside (0, 1], edge_samples < 3, or an option
    icp() rejects (naming the scan, or the pair of scans, where one is concerned).
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
    transforms, rms, fraction, scan_converged, rounds_run, converged, edges = _core.icp_multi(
        points, method, max_iterations, tolerance, _positive_or_none(max_distance, "max_distance"), trim,
        _positive_or_none(voxel_size, "voxel_size"), _normal_angle(normal_angle), normal_neighbours, poses, rounds,
        round_tolerance, threads, progress, relative_rmse, relative_fitness, patience, strategy,
        _positive_or_none(overlap_distance, "overlap_distance"), min_overlap, edge_samples)
    return IcpMultiResult(transforms, rms, fraction, scan_converged, int(rounds_run), bool(converged), edges)


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
