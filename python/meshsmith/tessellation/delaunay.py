"""2D Delaunay and constrained Delaunay triangulations, Voronoi diagrams, Lawson flips and Ruppert/Chew refinement (§2.1.1); binding cpp/python/tessellation_delaunay.cpp.
"""
from __future__ import annotations

from typing import NamedTuple, Sequence

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import tessellation as _core
from .._deprecation import positional_options
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from ..core import Mesh

__all__ = ["default_bounds", "Triangulation", "delaunay", "constrained_delaunay", "VoronoiDiagram", "voronoi",
           "FlippedTriangulation", "flip_to_delaunay", "RefinedMesh", "refine", "triangle_angles"]


class Triangulation(NamedTuple):
    """Result of :func:`delaunay`; unpacks as ``F, merged``."""

    F: IndexArray       #: (m, 3) CCW triangles indexing the points
    merged: IndexArray  #: (n,) the kept representative of each point


class FlippedTriangulation(NamedTuple):
    """Result of :func:`flip_to_delaunay`; unpacks as ``F, flip_count``."""

    F: IndexArray    #: (m, 3) CCW triangles, locally Delaunay
    flip_count: int  #: edge flips performed


class RefinedMesh(NamedTuple):
    """Result of :func:`refine`; unpacks as ``V, F, steiner_count``."""

    V: FloatArray       #: (n + k, 2) the input points followed by the k added ones
    F: IndexArray       #: (m, 3) CCW triangles of the domain
    steiner_count: int  #: k, the points added


def default_bounds(P: ArrayLike) -> FloatArray:
    """The box cells are clipped to when no bounds are given: the bounding box of the (n, 2) or
    (n, 3) points P enlarged by 10% of its size on each side (an axis of zero extent gets 10% of
    the largest extent, or 0.1). Returned as (xmin, ymin, xmax, ymax[, zmin, zmax]).
    Raises InputError for P that is empty, not (n, 2) or (n, 3) real numbers, or not finite.
    """
    P = _arguments.finite(_arguments.real_array(P, "P", (2, 3)), "P")
    if len(P) == 0:
        raise InputError("P is empty: expected at least one point")
    lower, upper = P.min(axis=0), P.max(axis=0)
    margin = 0.1 * (upper - lower)
    margin[margin == 0] = max(float(np.max(upper - lower)), 1.0) * 0.1
    lower, upper = lower - margin, upper + margin
    if P.shape[1] == 2:
        return np.array([lower[0], lower[1], upper[0], upper[1]])
    return np.array([lower[0], lower[1], upper[0], upper[1], lower[2], upper[2]])


def _seeds(holes: ArrayLike | None) -> ArrayLike:
    return np.empty((0, 2)) if holes is None else holes


def _segments(segments: ArrayLike | None) -> ArrayLike:
    return np.empty((0, 2), dtype=np.int64) if segments is None else segments


def delaunay(P: ArrayLike) -> Triangulation:
    """Delaunay triangulation of planar points (CGAL Delaunay_triangulation_2).

    P: (n, 2) real array. Returns a :class:`Triangulation` (F, merged): F (m, 3) int64 CCW triangles indexing P; merged
    (n,) int64, the kept representative of each point (merged[i] == i for kept points; exactly
    equal points are merged into the first occurrence, which alone appears in F).
    With cocircular points (a grid) any of the valid triangulations of the cocircular polygons
    may be returned. Raises InputError for NaN/Inf, fewer than 3 distinct points, or all points
    collinear.
    """
    F, merged = _core.delaunay(P)
    return Triangulation(F, merged)


def constrained_delaunay(P: ArrayLike, segments: ArrayLike | None, holes: ArrayLike | None = None) -> Mesh:
    """Constrained Delaunay triangulation of a planar straight-line graph, restricted to its domain.

    P: (n, 2) points. segments: (s, 2) integer index pairs into P, each becoming an edge (or a
    chain of edges when points lie on it or segments cross); None or empty: the convex hull
    edges are the segments. holes: (h, 2) seed points, or None.
    The domain (Triangle's convention) is every triangle that cannot be reached from outside the
    convex hull, nor from the triangle holding a hole seed, without crossing a segment.
    Returns a :class:`meshsmith.core.Mesh` (V, F): V (n + k, 2) is P unchanged followed by the k intersection points of
    crossing segments (float64); F (m, 3) int64 CCW triangles of the domain. Duplicate points
    of P stay in V unreferenced.
    Raises InputError for NaN/Inf, an index out of range, a zero-length segment, fewer than 3
    distinct points or all points collinear.
    """
    V, F, _ = _core.constrained_delaunay(P, _segments(segments), _seeds(holes))
    return Mesh(V, F)


class VoronoiDiagram(NamedTuple):
    """Voronoi diagram of n sites (see voronoi())."""

    vertices: FloatArray     #: (m, 2) circumcentre of Delaunay triangle t is vertex t
    edges: IndexArray        #: (e, 2) int64 vertex indices; -1 as second index: a ray
    directions: FloatArray   #: (e, 2) unit direction of each ray, zero rows for segments
    edge_sites: IndexArray   #: (e, 2) int64 the two sites each edge is equidistant from
    cells: list[FloatArray]  #: n arrays (k, 2): the cell of each site clipped to bounds, CCW
    triangles: IndexArray    #: (m, 3) int64 the dual Delaunay triangulation


@positional_options("bounds")
def voronoi(P: ArrayLike, *, bounds: Sequence[float] | FloatArray | None = None) -> VoronoiDiagram:
    """Voronoi diagram of planar sites, the dual of their Delaunay triangulation.

    P: (n, 2) points. bounds: (xmin, ymin, xmax, ymax) box the cells are clipped to; default the
    bounding box of P enlarged by 10% of its size on each side (20% wider and taller).
    Cells are the box clipped by the bisectors of each site's Delaunay neighbours (half-plane
    clipping in float64); a site outside the box gets an empty (0, 2) cell, and duplicate sites
    share the cell of their first occurrence. Cocircular sites give coincident Voronoi vertices
    joined by zero-length edges.
    Raises InputError as delaunay(), or for an empty or non-finite box.
    """
    box = tuple((default_bounds(_arguments.real_array(P, "P", 2)) if bounds is None
                 else _arguments.real_array(bounds, "bounds")).tolist())
    if len(box) != 4:
        raise InputError("bounds: expected (xmin, ymin, xmax, ymax)")
    return VoronoiDiagram(*_core.voronoi(P, box))


def flip_to_delaunay(V: ArrayLike, F: ArrayLike) -> FlippedTriangulation:
    """Lawson edge flips until every interior edge is locally Delaunay (α + γ ≤ 180°).

    V: (n, 2) points; F: (m, 3) triangles of a planar triangulation (clockwise ones are
    reoriented). Uses the exact incircle test, so cocircular quadruples are not flipped back and
    forth. Returns a :class:`FlippedTriangulation` (F_flipped, flip_count): (m, 3) int64 CCW triangles, same count, same vertices.
    Raises InputError for NaN/Inf, an index out of range, a zero-area triangle, an edge shared
    by more than two triangles or overlapping triangles; SolverError if more than n(n-1)/2 flips
    would be needed (only possible on input that is not a planar triangulation).
    """
    F_flipped, flips = _core.flip_to_delaunay(V, F)
    return FlippedTriangulation(F_flipped, int(flips))


@positional_options("min_angle", "max_area")
def refine(P: ArrayLike, segments: ArrayLike | None, holes: ArrayLike | None = None, *, min_angle: float = 20.7,
           max_area: float | None = None, max_steiner_points: int = 1_000_000,
           progress: ProgressCallback = None) -> RefinedMesh:
    """Ruppert's Delaunay refinement of a planar straight-line graph (quality triangulation, §2.1.1).

    P: (n, 2) points; segments: (s, 2) index pairs or None; holes: (h, 2) seed points or None
    (domain as in constrained_delaunay). min_angle: degrees, in (0, 35); max_area: > 0 to bound triangle
    areas, or None; max_steiner_points: a last-resort cap. progress: callback (fraction, stage) -> bool,
    polled every few microseconds of work (throttled to one call per 50 ms); False, an exception or
    Ctrl-C stops the refinement within a fraction of a second.
    Our own Ruppert loop on CGAL's constrained Delaunay triangulation: encroached subsegments
    (diametral circles) are split first, then the worst triangle gets its circumcentre or
    off-centre, unless that point encroaches a subsegment or lies beyond one, which is split instead.
    Near small input angles (segments meeting at less than 60°) it terminates instead of running to
    the cap (Shewchuk 2002; Miller, Pav & Walkington 2003): subsegments at the apex are split on
    concentric shells (power-of-two distances from it); a skinny triangle whose shortest edge joins
    the two sides at one shell is left alone (Triangle's rule); and inside a wedge narrower than
    0.5°, whose resolution would take of the order of 1/angle points per doubling of the distance
    from its apex, the ladder of triangles between its two sides is left as it is.
    Guarantee: every triangle with an angle below min_angle has its three vertices on the two
    segments of one small input angle (it lies in that angle's cluster; its smallest angle is at
    least about the input angle), or is so small that its split point would lie within 2^-40
    (~1e-12) of the coordinates' magnitude from its vertices, too close for double precision.
    Termination is proven for min_angle <= 20.7° away from small input angles and holds in practice
    up to 33° (every test domain, the issue's 1e-9 slivers in under 0.02 s, where Triangle does not
    finish); at 34° some domains run to the cap (2.5 s next to a 1e-15 feature). Area-bad
    triangles are always split.
    Returns a :class:`RefinedMesh` (V, F, steiner_count): V (n + k, 2) is P followed by the k added points (segment
    intersections included), F (m, 3) int64 CCW triangles of the domain. Steiner counts are close
    to Triangle's (see benchmarks/bench_tessellation.py).
    Raises InputError as constrained_delaunay or for a bad min_angle / max_area; SolverError
    when more than max_steiner_points points would be inserted (a channel narrower than 1e-6 of
    its length needs a million); Cancelled when the callback returns False.
    """
    area = 0.0 if max_area is None else _arguments.real(max_area, "max_area")
    if max_area is not None and not area > 0:
        raise InputError(f"max_area: must be > 0 or None, got {max_area}")
    V, F, steiner = _core.refine(P, _segments(segments), _seeds(holes), _arguments.real(min_angle, "min_angle"), area, max_steiner_points,
                                 progress)
    return RefinedMesh(V, F, int(steiner))


def triangle_angles(V: ArrayLike, F: ArrayLike) -> FloatArray:
    """Interior angles in degrees of planar triangles: V (n, 2) points, F (m, 3) indices.

    Returns (m, 3): column c is the angle at corner c (atan2 of |cross| and dot, accurate for
    tiny and obtuse angles alike). The quality measure of Delaunay refinement (§2.1.1).
    Raises InputError for shapes other than (n, 2) and (m, 3) or out-of-range indices.
    """
    points = _arguments.finite(_arguments.real_array(V, "V", 2), "V")
    faces = _arguments.index_array(F, "F", 3)
    if faces.size and (faces.min() < 0 or faces.max() >= len(points)):
        raise InputError(f"F indexes a vertex outside [0, {len(points)})")
    # Angles are scale-invariant: each triangle's corners are scaled into (-1, 1) by a power of
    # two (exact; the rule of core/normalization.h, per triangle), so neither the differences
    # nor the cross and dot products overflow or underflow at 1e±300.
    corners = points[faces]
    largest = np.abs(corners).max(axis=(1, 2)) if len(faces) else np.zeros(0)
    corners = np.ldexp(corners, -np.frexp(largest)[1][:, None, None])
    angles = np.empty(faces.shape, dtype=float)
    for c in range(3):
        a = corners[:, (c + 1) % 3] - corners[:, c]
        b = corners[:, (c + 2) % 3] - corners[:, c]
        cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        angles[:, c] = np.degrees(np.arctan2(np.abs(cross), np.einsum("ij,ij->i", a, b)))
    return angles
