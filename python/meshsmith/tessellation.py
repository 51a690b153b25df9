"""Tessellation chapter (curriculum §2.1): Delaunay triangulations and Voronoi diagrams, Delaunay
refinement, contouring by Voronoi filtering (crust, medial axis, local feature size), 3D surface
reconstruction by the Cocone crust, and power diagrams.

Points are float64 arrays of shape (n, 2) (or (n, 3) where 3D is supported); triangles come back
as (m, 3) int64 arrays, counter-clockwise. Triangulations use CGAL's exact predicates, so
collinear and cocircular input is handled consistently; constructed points (segment
intersections, Steiner points, circumcentres, cell corners) are float64.
Bad input raises :class:`meshsmith.InputError`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ._core import InputError
from ._core import tessellation as _core

__all__ = [
    "delaunay",
    "constrained_delaunay",
    "voronoi",
    "VoronoiDiagram",
    "flip_to_delaunay",
    "refine",
    "PowerDiagram",
    "power_diagram",
    "crust",
    "medial_axis",
    "local_feature_size",
    "sampling_ratio",
    "is_r_sample",
    "crust_3d",
    "default_bounds",
    "triangle_angles",
]


def default_bounds(P: np.ndarray) -> np.ndarray:
    """The box cells are clipped to when no bounds are given: the bounding box of the (n, 2) or
    (n, 3) points P enlarged by 10% of its size on each side (an axis of zero extent gets 10% of
    the largest extent, or 0.1). Returned as (xmin, ymin, xmax, ymax[, zmin, zmax]).
    """
    lower, upper = P.min(axis=0), P.max(axis=0)
    margin = 0.1 * (upper - lower)
    margin[margin == 0] = max(float(np.max(upper - lower)), 1.0) * 0.1
    lower, upper = lower - margin, upper + margin
    if P.shape[1] == 2:
        return np.array([lower[0], lower[1], upper[0], upper[1]])
    return np.array([lower[0], lower[1], upper[0], upper[1], lower[2], upper[2]])


def _seeds(holes):
    return np.empty((0, 2)) if holes is None else holes


def _segments(segments):
    return np.empty((0, 2), dtype=np.int64) if segments is None else segments


def delaunay(P):
    """Delaunay triangulation of planar points (CGAL Delaunay_triangulation_2).

    P: (n, 2) real array. Returns (F, merged): F (m, 3) int64 CCW triangles indexing P; merged
    (n,) int64, the kept representative of each point (merged[i] == i for kept points; exactly
    equal points are merged into the first occurrence, which alone appears in F).
    With cocircular points (a grid) any of the valid triangulations of the cocircular polygons
    may be returned. Raises InputError for NaN/Inf, fewer than 3 distinct points, or all points
    collinear.
    """
    return _core.delaunay(P)


def constrained_delaunay(P, segments, holes=None):
    """Constrained Delaunay triangulation of a planar straight-line graph, restricted to its domain.

    P: (n, 2) points. segments: (s, 2) integer index pairs into P, each becoming an edge (or a
    chain of edges when points lie on it or segments cross); None or empty: the convex hull
    edges are the segments. holes: (h, 2) seed points, or None.
    The domain (Triangle's convention) is every triangle that cannot be reached from outside the
    convex hull, nor from the triangle holding a hole seed, without crossing a segment.
    Returns (V, F): V (n + k, 2) is P unchanged followed by the k intersection points of
    crossing segments (float64); F (m, 3) int64 CCW triangles of the domain. Duplicate points
    of P stay in V unreferenced.
    Raises InputError for NaN/Inf, an index out of range, a zero-length segment, fewer than 3
    distinct points or all points collinear.
    """
    V, F, _ = _core.constrained_delaunay(P, _segments(segments), _seeds(holes))
    return V, F


class VoronoiDiagram(NamedTuple):
    """Voronoi diagram of n sites (see voronoi())."""

    vertices: np.ndarray    #: (m, 2) circumcentre of Delaunay triangle t is vertex t
    edges: np.ndarray       #: (e, 2) int64 vertex indices; -1 as second index: a ray
    directions: np.ndarray  #: (e, 2) unit direction of each ray, zero rows for segments
    edge_sites: np.ndarray  #: (e, 2) int64 the two sites each edge is equidistant from
    cells: list             #: n arrays (k, 2): the cell of each site clipped to bounds, CCW
    triangles: np.ndarray   #: (m, 3) int64 the dual Delaunay triangulation


def voronoi(P, bounds=None) -> VoronoiDiagram:
    """Voronoi diagram of planar sites, the dual of their Delaunay triangulation.

    P: (n, 2) points. bounds: (xmin, ymin, xmax, ymax) box the cells are clipped to; default the
    bounding box of P enlarged by 10% of its size on each side (20% wider and taller).
    Cells are the box clipped by the bisectors of each site's Delaunay neighbours (half-plane
    clipping in float64); a site outside the box gets an empty (0, 2) cell, and duplicate sites
    share the cell of their first occurrence. Cocircular sites give coincident Voronoi vertices
    joined by zero-length edges.
    Raises InputError as delaunay(), or for an empty or non-finite box.
    """
    if bounds is None:
        points = np.asarray(P, dtype=float)
        if points.ndim == 2 and points.shape[1] == 2 and len(points) and np.isfinite(points).all():
            bounds = default_bounds(points)
        else:
            bounds = (0.0, 0.0, 1.0, 1.0)  # the core rejects P with a precise message
    bounds = tuple(float(b) for b in bounds)
    if len(bounds) != 4:
        raise InputError("bounds: expected (xmin, ymin, xmax, ymax)")
    return VoronoiDiagram(*_core.voronoi(P, bounds))


def flip_to_delaunay(V, F):
    """Lawson edge flips until every interior edge is locally Delaunay (α + γ ≤ 180°).

    V: (n, 2) points; F: (m, 3) triangles of a planar triangulation (clockwise ones are
    reoriented). Uses the exact incircle test, so cocircular quadruples are not flipped back and
    forth. Returns (F_flipped, flip_count): (m, 3) int64 CCW triangles, same count, same vertices.
    Raises InputError for NaN/Inf, an index out of range, a zero-area triangle, an edge shared
    by more than two triangles or overlapping triangles; SolverError if more than n(n-1)/2 flips
    would be needed (only possible on input that is not a planar triangulation).
    """
    return _core.flip_to_delaunay(V, F)


def refine(P, segments, holes=None, min_angle: float = 20.7, max_area: float | None = None, *,
           max_steiner_points: int = 1_000_000, progress=None):
    """Ruppert/Chew Delaunay refinement of a planar straight-line graph (quality triangulation).

    P: (n, 2) points; segments: (s, 2) index pairs or None; holes: (h, 2) seed points or None
    (domain as in constrained_delaunay). min_angle: degrees, in (0, 35); max_area: > 0 to bound triangle
    areas, or None. Uses CGAL's Delaunay_mesher_2: circumcentres of bad triangles are inserted,
    segments encroached upon (diametral circles) are split at midpoints first, with Shewchuk's
    cluster treatment of small input angles. Termination is guaranteed for min_angle ≤ 20.7°
    and usual up to about 33°. Triangles at (or next to) a corner where input segments meet
    at less than 60° may keep angles below min_angle: the bound holds away from small input
    angles.
    Returns (V, F, steiner_count): V (n + k, 2) is P followed by the k added points (segment
    intersections included), F (m, 3) int64 CCW triangles of the domain.
    Choice of CGAL's mesher over own code: it meets the guarantees above and, on the test
    domains, adds about as many Steiner points as Shewchuk's Triangle (see
    benchmarks/bench_tessellation.py); it is several times slower than Triangle on large meshes.
    Raises InputError as constrained_delaunay or for a bad min_angle / max_area; SolverError
    when more than max_steiner_points points would be inserted (so it never hangs).
    """
    area = 0.0 if max_area is None else float(max_area)
    if max_area is not None and not area > 0:
        raise InputError(f"max_area: must be > 0 or None, got {max_area}")
    return _core.refine(P, _segments(segments), _seeds(holes), float(min_angle), area,
                        int(max_steiner_points), progress)


@dataclass
class PowerDiagram:
    """Result of power_diagram().

    triangulation: (m, 3) CCW triangles (2D) or (m, 4) positively oriented tetrahedra (3D), int64
        indices into the sites: the regular (weighted Delaunay) triangulation. Empty (0 rows) when
        the visible sites are degenerate (collinear in 2D, coplanar in 3D).
    cells: one entry per site. 2D: a (k, 2) float array, the power cell's corners in
        counter-clockwise order. 3D: a tuple (vertices (k, 3), faces (f, 3) int64) of the convex
        cell, each planar face fanned into triangles, outward-oriented. An empty cell (a hidden
        site, or a cell outside the bounds) has k = 0.
    hidden: int64 indices of the sites whose power cell is empty in the whole plane/space
        (their weight is dominated by their neighbours'), increasing.
    bounds: the box the cells were clipped to, (xmin, ymin, xmax, ymax[, zmin, zmax]).
    """

    triangulation: np.ndarray
    cells: list
    hidden: np.ndarray
    bounds: np.ndarray = field(repr=False)


def power_diagram(P, weights, bounds=None) -> PowerDiagram:
    """Power diagram of weighted sites in 2D or 3D (§2.1.4).

    The power distance of q to site i is |q - p_i|^2 - weights[i] (weights are squared radii);
    each site's cell holds the points whose power distance to it is smallest. With equal weights
    this is the Voronoi diagram.

    P: (n, 2) or (n, 3) real array of sites, finite. weights: (n,) real array (may be negative).
    bounds: (xmin, ymin, xmax, ymax) in 2D, (xmin, ymin, xmax, ymax, zmin, zmax) in 3D; default
    the sites' bounding box enlarged by 10% of its extent on each side.
    Cells are built by clipping the box with the power half-spaces of the site's neighbours in the
    regular triangulation, in double precision with a relative tolerance of 1e-12 (corners closer
    than 1e-10 of the box diagonal are merged).
    Returns a PowerDiagram. Raises InputError for empty or non-finite input, a wrong number of
    weights, or an empty box.
    """
    P_checked = np.asarray(P) if P is not None else P
    if bounds is None:
        if not isinstance(P_checked, np.ndarray) or P_checked.ndim != 2 or P_checked.shape[0] == 0 \
                or P_checked.shape[1] not in (2, 3) or not np.all(np.isfinite(P_checked)):
            bounds = np.zeros(4)  # let the core report what is wrong with P
        else:
            bounds = default_bounds(P_checked.astype(float))
    triangulation, cells, hidden = _core.power_diagram(P, weights, bounds)
    return PowerDiagram(triangulation, cells, hidden, np.asarray(bounds, dtype=float))


def crust(samples) -> np.ndarray:
    """Reconstruct closed curves from 2D samples by Voronoi filtering: the crust (§2.1.3).

    Delaunay triangulation of the samples together with their Voronoi vertices; the edges joining
    two samples are the crust (Amenta, Bern & Eppstein 1998). When the samples are an R-sample of
    smooth closed curves with R < 0.25 (see sampling_ratio) each sample is joined to exactly its
    two neighbours along its curve.
    samples: (n, 2) real array, n >= 3, not all collinear, no duplicates.
    Returns E: (k, 2) int64 edges (i < j, sorted). Raises InputError if a precondition fails.
    """
    return _core.crust(samples)


def medial_axis(samples) -> tuple[np.ndarray, np.ndarray]:
    """Approximate medial axis (§2.1.2) of the curves sampled by `samples`.

    The Voronoi edges of the samples whose dual Delaunay edges are not crust edges: the Voronoi
    skeleton, which converges to the inner and outer medial axis as the sampling gets denser.
    Exactly the Voronoi edges between two Voronoi vertices are returned: the inner axis and the
    bounded part of the outer axis (circumcentres of the Delaunay triangles between the curve and
    the convex hull, far out for thin triangles on the hull). The
    unbounded Voronoi rays, dual to the convex hull's edges that are not crust edges (the outer
    axis's branches running to infinity), are left out; so are the rays dual to crust edges on
    the hull, which cross the curve.
    samples: (n, 2) real array (as crust). Returns (vertices (k, 2) float, edges (e, 2) int64).
    Raises InputError as crust.
    """
    return _core.medial_axis(samples)


def local_feature_size(samples) -> np.ndarray:
    """Approximate local feature size LFS(p) = d(p, medial axis) of each sample (§2.1.2).

    The distance to the nearest vertex of medial_axis(samples) (Voronoi vertices approximate the
    medial axis in 2D); it converges as the sampling gets denser. +inf when the approximate
    medial axis is empty.
    samples: (n, 2) real array (as crust). Returns (n,) float. Raises InputError as crust.
    """
    return _core.local_feature_size(samples)


def sampling_ratio(samples) -> float:
    """Estimated smallest R for which `samples` are an R-sample of their curve (§2.1.2).

    R-sample: every curve point c has a sample within R·LFS(c). The curve is taken to be the crust:
    on each crust edge pq the worst point is its midpoint, at |pq|/2 from a sample, and there
    LFS >= max(LFS(p), LFS(q)) - |pq|/2 (LFS is 1-Lipschitz), with LFS from local_feature_size.
    Returns max over crust edges of (|pq|/2) / that bound (+inf if a bound is not positive).
    samples: (n, 2) real array (as crust). Raises InputError as crust.
    """
    return float(_core.sampling_ratio(samples))


def is_r_sample(samples, R: float) -> bool:
    """Whether `samples` are an R-sample of the curve they describe: sampling_ratio(samples) <= R.

    samples: (n, 2) real array (as crust). R: positive number. Raises InputError as crust.
    """
    from ._core import InputError

    if not (isinstance(R, (int, float, np.floating, np.integer)) and R > 0):
        raise InputError(f"is_r_sample: R must be a positive number, got {R!r}")
    return sampling_ratio(samples) <= float(R)


def crust_3d(points, *, cocone_angle: float = np.pi / 8,
             max_hole_edges: int = 8, progress=None) -> tuple[np.ndarray, np.ndarray]:
    """Reconstruct a triangle mesh from points sampled on a closed surface: Cocone (§2.1.3, 3D).

    The Cocone refinement (Amenta, Choi, Dey & Leekha 2002) of the 3D crust with poles: on the
    Delaunay triangulation of the points, each point's pole (farthest Voronoi vertex of its cell)
    estimates its normal; a Delaunay triangle is kept when its dual Voronoi edge meets the cocone
    (the directions within `cocone_angle` of the plane orthogonal to the normal) at each corner.
    Then a manifold is extracted: sharp-edge pruning (candidates around an edge that all lie in a
    wedge under pi/2 are removed: triangles folded across flat tetrahedra), dangling triangles (a
    free edge, and an edge shared by more than two candidates) are removed repeatedly, the outer
    surface of the rest is collected by a walk that turns outwards across each edge and never
    uses a directed edge twice (consistent orientation). Repair: holes bounded by simple loops of
    at most `max_hole_edges` edges, or of at most 4 * `max_hole_edges` edges when nearly planar,
    are closed by the minimum-area triangulation of the loop (avoiding triangles that face
    against the pole normals); points left on no triangle are inserted and the
    edges around them flipped towards the corner normals; inward triangles are cut out with
    their neighbours and the hole re-triangulated.
    points: (n, 3) real array, n >= 4, not coplanar, no duplicates. cocone_angle: radians in
    (0, pi/2), default pi/8. max_hole_edges: >= 0 (0 leaves holes open), default 8.
    progress: optional callback (fraction, stage) -> bool; returning False cancels.
    Returns (V, F): V the points (n, 3) float, F (m, 3) int64 triangles oriented outwards.
    Manifold and watertight when the sampling is dense and free of noise. Samples needed
    (measured on random uniform samples, seeds 0-5): a sphere from 8, the torus of radii 1 and
    0.35 from 225 (about 2 samples per square minor radius); the result then keeps every point.
    Raises InputError if a precondition fails; Cancelled if progress returns False.
    """
    return _core.crust_3d(points, float(cocone_angle), int(max_hole_edges), progress)


def triangle_angles(V, F) -> np.ndarray:
    """Interior angles in degrees of planar triangles: V (n, 2) points, F (m, 3) indices.

    Returns (m, 3): column c is the angle at corner c (atan2 of |cross| and dot, accurate for
    tiny and obtuse angles alike). The quality measure of Delaunay refinement (§2.1.1).
    Raises InputError for shapes other than (n, 2) and (m, 3) or out-of-range indices.
    """
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    if V.ndim != 2 or V.shape[1] != 2:
        raise InputError(f"V has shape {V.shape}: expected (n, 2)")
    if F.ndim != 2 or F.shape[1] != 3 or F.dtype.kind not in "iu":
        raise InputError(f"F has shape {F.shape} and dtype {F.dtype}: expected (m, 3) integers")
    if F.size and (F.min() < 0 or F.max() >= len(V)):
        raise InputError(f"F indexes a vertex outside [0, {len(V)})")
    corners = V[F]
    angles = np.empty(F.shape, dtype=float)
    for c in range(3):
        a = corners[:, (c + 1) % 3] - corners[:, c]
        b = corners[:, (c + 2) % 3] - corners[:, c]
        cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        angles[:, c] = np.degrees(np.arctan2(np.abs(cross), np.einsum("ij,ij->i", a, b)))
    return angles
