"""Procedural shapes and point samples for tests, examples and the demo (pure numpy).

Every mesh generator returns a :class:`meshsmith.core.Mesh` ``(V, F)``: V float64 (n, 3), F int64 (m, 3), counter-clockwise
seen from outside (outward normals, positive :func:`meshsmith.geometry.volume` for closed
shapes), manifold, without duplicate or unreferenced vertices. Bad parameters raise
:class:`meshsmith.InputError`, and so do sizes beyond ``MAX_ELEMENTS`` (2^26 ≈ 67M faces or
points, several GB of arrays) rather than exhausting memory.
"""
from __future__ import annotations

import numbers
from typing import NamedTuple

import numpy as np

from . import _arguments
from ._arguments import MAX_ELEMENTS
from ._core import InputError
from ._deprecation import positional_options
from ._typing import ArrayLike, FloatArray
from .core import Mesh, PointCloud

# The finest icosphere within MAX_ELEMENTS faces (20 * 4**10 = 21M; 4**11 would be 84M): the
# bound is on the exponent, checked before 4**subdivisions is computed.
_ICOSPHERE_MAX_SUBDIVISIONS = 10

__all__ = ["MAX_ELEMENTS", "icosphere", "uv_sphere", "torus", "grid", "disk", "cube", "noisy", "sample_points",
           "sphere_points", "ScanPair", "scan_pair", "PartialViews", "partial_views"]


# --- parameter checks --------------------------------------------------------------------------

def _integer(name: str, value: object, minimum: int, maximum: int = MAX_ELEMENTS) -> int:
    return _arguments.integer(value, name, minimum, maximum)


def _seed(value: object) -> int:
    return _arguments.integer(value, "seed", 0, 2 ** 64 - 1)


def _not_too_large(what: str, count: int) -> None:
    if count > MAX_ELEMENTS:
        raise InputError(f"these parameters ask for {count:,} {what}: at most "
                         f"MAX_ELEMENTS = {MAX_ELEMENTS:,} are generated")


def _positive(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not np.isfinite(float(value)) \
            or value <= 0:
        raise InputError(f"{name} must be a positive finite number, got {value!r}")
    return float(value)


def _non_negative(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not np.isfinite(float(value)) \
            or value < 0:
        raise InputError(f"{name} must be a non-negative finite number, got {value!r}")
    return float(value)


def _mesh_arrays(V: ArrayLike, F: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """(V, F) as float64 / int64 arrays, validated by the core (raises InputError)."""
    from ._core import core as _core

    _core.validate_mesh(V, F)
    return np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)


# --- closed surfaces -----------------------------------------------------------------------------

def icosphere(subdivisions: int = 3, radius: float = 1.0) -> Mesh:
    """Sphere from a regular icosahedron whose triangles are split in four ``subdivisions`` times,
    new vertices pushed onto the sphere.

    Returns 10·4^s + 2 vertices and 20·4^s faces (s = subdivisions: 3 → 1,280 faces,
    8 → 1,310,720), every vertex at distance ``radius`` from the origin.
    Raises InputError if subdivisions is not an integer in [0, 10] (10: 21M faces) or radius <= 0.
    """
    subdivisions = _integer("subdivisions", subdivisions, 0, _ICOSPHERE_MAX_SUBDIVISIONS)
    radius = _positive("radius", radius)
    t = (1.0 + 5.0 ** 0.5) / 2.0
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
                  [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                  [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], dtype=np.float64)
    F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
                  [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
                  [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
                  [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]], dtype=np.int64)
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    for _ in range(subdivisions):
        V, F = _split_in_four(V, F)
        V /= np.linalg.norm(V, axis=1, keepdims=True)
    return Mesh(V * radius, F)


def _split_in_four(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One 1-to-4 midpoint split; each edge's midpoint is created once (shared by both faces)."""
    sides = np.stack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]], axis=1).reshape(-1, 2)
    keys = np.sort(sides, axis=1)
    n = len(V)
    codes = keys[:, 0] * n + keys[:, 1]
    unique_codes, first, edge_of_side = np.unique(codes, return_index=True, return_inverse=True)
    endpoints = keys[first]
    midpoints = 0.5 * (V[endpoints[:, 0]] + V[endpoints[:, 1]])
    m = (n + edge_of_side.reshape(-1, 3)).astype(np.int64)  # m[:, k]: midpoint of side k
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    F2 = np.concatenate([np.stack([a, m[:, 0], m[:, 2]], 1), np.stack([b, m[:, 1], m[:, 0]], 1),
                         np.stack([c, m[:, 2], m[:, 1]], 1), m])
    return np.vstack([V, midpoints]), F2


def uv_sphere(n_latitude: int = 32, n_longitude: int = 64,
              radius: float = 1.0) -> Mesh:
    """Latitude-longitude sphere: two poles on the z axis and ``n_latitude - 1`` rings of
    ``n_longitude`` vertices; fans at the poles, two triangles per quad elsewhere.

    Raises InputError if n_latitude < 2, n_longitude < 3 or radius <= 0.
    """
    n_latitude = _integer("n_latitude", n_latitude, 2)
    n_longitude = _integer("n_longitude", n_longitude, 3)
    radius = _positive("radius", radius)
    _not_too_large("faces", 2 * n_latitude * n_longitude)
    theta = np.pi * np.arange(1, n_latitude) / n_latitude          # polar angle of each ring
    phi = 2.0 * np.pi * np.arange(n_longitude) / n_longitude
    ring = np.stack([np.outer(np.sin(theta), np.cos(phi)), np.outer(np.sin(theta), np.sin(phi)),
                     np.repeat(np.cos(theta)[:, None], n_longitude, axis=1)], axis=-1).reshape(-1, 3)
    V = np.vstack([[0.0, 0.0, 1.0], ring, [0.0, 0.0, -1.0]]) * radius
    south = len(V) - 1
    j = np.arange(n_longitude)
    jn = (j + 1) % n_longitude
    north_cap = np.stack([np.zeros_like(j), 1 + j, 1 + jn], axis=1)
    last = 1 + (n_latitude - 2) * n_longitude
    south_cap = np.stack([np.full_like(j, south), last + jn, last + j], axis=1)
    r = np.arange(n_latitude - 2)[:, None]
    upper_j, upper_jn = 1 + r * n_longitude + j, 1 + r * n_longitude + jn      # ring r
    lower_j, lower_jn = upper_j + n_longitude, upper_jn + n_longitude          # ring r + 1
    band = np.concatenate([np.stack([upper_j, lower_j, lower_jn], -1).reshape(-1, 3),
                           np.stack([upper_j, lower_jn, upper_jn], -1).reshape(-1, 3)])
    return Mesh(V, np.concatenate([north_cap, band, south_cap]).astype(np.int64))


def _periodic_quads(rows: int, cols: int, wrap_rows: bool, wrap_cols: bool) -> np.ndarray:
    """Two triangles per cell of a rows × cols vertex lattice indexed i * cols + j; each cell
    (i, j), (i+1, j), (i+1, j+1), (i, j+1) is counter-clockwise in the (i, j) plane."""
    i = np.arange(rows if wrap_rows else rows - 1)[:, None]
    j = np.arange(cols if wrap_cols else cols - 1)[None, :]
    i1, j1 = (i + 1) % rows, (j + 1) % cols
    v00, v10, v11, v01 = i * cols + j, i1 * cols + j, i1 * cols + j1, i * cols + j1
    return np.concatenate([np.stack([v00, v10, v11], -1).reshape(-1, 3),
                           np.stack([v00, v11, v01], -1).reshape(-1, 3)]).astype(np.int64)


def torus(major_radius: float = 1.0, minor_radius: float = 0.35, n_major: int = 64,
          n_minor: int = 32) -> Mesh:
    """Torus around the z axis: tube of radius ``minor_radius`` around a circle of radius
    ``major_radius``, ``n_major × n_minor`` vertices. Genus 1.

    Raises InputError if n_major or n_minor < 3, a radius <= 0, or minor_radius >= major_radius.
    """
    n_major = _integer("n_major", n_major, 3)
    n_minor = _integer("n_minor", n_minor, 3)
    major_radius = _positive("major_radius", major_radius)
    minor_radius = _positive("minor_radius", minor_radius)
    if minor_radius >= major_radius:
        raise InputError(f"minor_radius ({minor_radius}) must be smaller than major_radius "
                         f"({major_radius}) for the torus not to intersect itself")
    _not_too_large("faces", 2 * n_major * n_minor)
    u = 2.0 * np.pi * np.arange(n_major) / n_major
    v = 2.0 * np.pi * np.arange(n_minor) / n_minor
    U, W = np.meshgrid(u, v, indexing="ij")
    ring = major_radius + minor_radius * np.cos(W)
    V = np.stack([ring * np.cos(U), ring * np.sin(U), minor_radius * np.sin(W)], -1).reshape(-1, 3)
    # Lattice (major i, minor j): d/du × d/dv points outward, so the (i, j) order is outward.
    return Mesh(V, _periodic_quads(n_major, n_minor, True, True))


def grid(nx: int = 32, ny: int = 32, size: tuple[float, float] = (1.0, 1.0)) -> Mesh:
    """Flat rectangle [0, size[0]] × [0, size[1]] in the plane z = 0 with ``nx × ny`` cells
    ((nx+1)(ny+1) vertices, 2·nx·ny triangles), normals +z, one boundary loop.

    Raises InputError if nx or ny < 1 or a size is not positive.
    """
    nx, ny = _integer("nx", nx, 1), _integer("ny", ny, 1)
    try:
        width, height = size
    except (TypeError, ValueError):
        raise InputError(f"size must be a pair (width, height), got {size!r}") from None
    width, height = _positive("size[0]", width), _positive("size[1]", height)
    _not_too_large("faces", 2 * nx * ny)
    x, y = np.meshgrid(np.linspace(0.0, width, nx + 1), np.linspace(0.0, height, ny + 1),
                       indexing="ij")
    V = np.stack([x, y, np.zeros_like(x)], -1).reshape(-1, 3)
    return Mesh(V, _periodic_quads(nx + 1, ny + 1, False, False))


def disk(n_rings: int = 16, n_segments: int = 64, radius: float = 1.0) -> Mesh:
    """Flat disk of ``radius`` in the plane z = 0, normals +z, one boundary loop: a center vertex
    and ``n_rings`` concentric rings, ring r holding ``max(3, round(n_segments · r / n_rings))``
    vertices (so the triangles stay well shaped), neighbouring rings zipped together.

    Raises InputError if n_rings < 1, n_segments < 3 or radius <= 0.
    """
    n_rings = _integer("n_rings", n_rings, 1)
    n_segments = _integer("n_segments", n_segments, 3)
    radius = _positive("radius", radius)
    _not_too_large("faces", n_rings * (n_segments + 3))
    counts = np.maximum(3, np.rint(n_segments * np.arange(1, n_rings + 1) / n_rings).astype(int))
    starts = 1 + np.concatenate([[0], np.cumsum(counts)[:-1]])
    points = [np.zeros((1, 3))]
    for r, count in enumerate(counts, start=1):
        angle = 2.0 * np.pi * np.arange(count) / count
        points.append(np.stack([np.cos(angle), np.sin(angle), np.zeros(count)], 1) * (radius * r / n_rings))
    first = np.arange(counts[0])
    faces = [np.stack([np.zeros_like(first), starts[0] + first, starts[0] + (first + 1) % counts[0]], 1)]
    for r in range(1, n_rings):
        faces.append(_zip_rings(starts[r - 1], counts[r - 1], starts[r], counts[r]))
    return Mesh(np.vstack(points), np.concatenate(faces).astype(np.int64))


def _zip_rings(inner_start: int, inner_count: int, outer_start: int, outer_count: int) -> np.ndarray:
    """Triangles between two concentric rings whose vertices start at angle 0 and go
    counter-clockwise: walk both rings at once, always advancing the one whose next vertex has
    the smaller angle (inner_count + outer_count triangles, counter-clockwise seen from +z)."""
    steps = np.concatenate([(np.arange(inner_count) + 1) / inner_count,
                            (np.arange(outer_count) + 1) / outer_count])
    is_outer = np.concatenate([np.zeros(inner_count, bool), np.ones(outer_count, bool)])
    order = np.lexsort((~is_outer, steps))  # by angle; on ties the outer ring first
    is_outer = is_outer[order]
    i = np.concatenate([[0], np.cumsum(~is_outer)[:-1]])   # inner position before each step
    j = np.concatenate([[0], np.cumsum(is_outer)[:-1]])    # outer position before each step
    inner = inner_start + i % inner_count
    inner_next = inner_start + (i + 1) % inner_count
    outer = outer_start + j % outer_count
    outer_next = outer_start + (j + 1) % outer_count
    return np.where(is_outer[:, None], np.stack([inner, outer, outer_next], 1),
                    np.stack([inner, outer, inner_next], 1))


def cube(subdivisions: int = 8, size: float = 1.0) -> Mesh:
    """Closed axis-aligned cube [-size/2, size/2]^3, each side a ``subdivisions × subdivisions``
    grid of two-triangle cells, welded along the cube's edges (6·s² + 2 vertices, 12·s² faces).

    Raises InputError if subdivisions < 1 or size <= 0.
    """
    s = _integer("subdivisions", subdivisions, 1)
    size = _positive("size", size)
    _not_too_large("lattice points", (s + 1) ** 3)
    # Lattice points on the cube's surface, numbered through a dense (s+1)^3 lookup table.
    lattice = np.stack(np.meshgrid(*[np.arange(s + 1)] * 3, indexing="ij"), -1).reshape(-1, 3)
    on_surface = np.any((lattice == 0) | (lattice == s), axis=1)
    numbering = np.full(len(lattice), -1, dtype=np.int64)
    numbering[on_surface] = np.arange(on_surface.sum())
    index = numbering.reshape(s + 1, s + 1, s + 1)
    V = (lattice[on_surface] / s - 0.5) * size
    u_grid, v_grid = np.meshgrid(np.arange(s), np.arange(s), indexing="ij")
    u, v = u_grid.ravel(), v_grid.ravel()
    faces = []
    # (fixed axis, its value, axis of u, axis of v) with u × v pointing outward.
    for axis, level, axis_u, axis_v in [(0, s, 1, 2), (0, 0, 2, 1), (1, s, 2, 0), (1, 0, 0, 2),
                                        (2, s, 0, 1), (2, 0, 1, 0)]:
        def corner(du: int, dv: int) -> np.ndarray:
            point = np.empty((len(u), 3), dtype=np.int64)
            point[:, axis], point[:, axis_u], point[:, axis_v] = level, u + du, v + dv
            return index[point[:, 0], point[:, 1], point[:, 2]]
        c00, c10, c11, c01 = corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)
        faces += [np.stack([c00, c10, c11], 1), np.stack([c00, c11, c01], 1)]
    return Mesh(V, np.concatenate(faces).astype(np.int64))


# --- derived data ----------------------------------------------------------------------------------

def _face_normals_and_areas(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    cross = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    double_area = np.linalg.norm(cross, axis=1)
    normals = np.divide(cross, double_area[:, None], out=np.zeros_like(cross),
                        where=double_area[:, None] > 0)
    return normals, 0.5 * double_area


def _mean_edge_length(V: np.ndarray, F: np.ndarray) -> float:
    sides = np.concatenate([V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 1]], V[F[:, 0]] - V[F[:, 2]]])
    return float(np.linalg.norm(sides, axis=1).mean())


@positional_options("sigma", "seed", "direction")
def noisy(V: ArrayLike, F: ArrayLike, *, sigma: float = 0.01, seed: int = 0, direction: str = "normal") -> Mesh:
    """A noisy copy of a mesh, as a scan would give it: each vertex moves by Gaussian noise of
    standard deviation ``sigma × mean edge length``.

    direction: ``"normal"`` (default) moves each vertex along its area-weighted vertex normal
    (the surface is perturbed, the sampling is not); ``"isotropic"`` moves it in all three
    directions. V: (n, 3) float array, F: (m, 3) integer array. Returns a Mesh (V', F) with F an int64
    copy; the input is not modified. Same seed, same result.
    Raises InputError for a bad mesh, sigma < 0, or an unknown direction.
    """
    V, F = _mesh_arrays(V, F)
    sigma = _non_negative("sigma", sigma)
    if direction not in ("normal", "isotropic"):
        raise InputError(f"direction must be 'normal' or 'isotropic', got {direction!r}")
    rng = np.random.default_rng(_seed(seed))
    scale = sigma * _mean_edge_length(V, F)
    if direction == "isotropic":
        return Mesh(V + rng.normal(scale=scale, size=V.shape), F.copy())
    normals, areas = _face_normals_and_areas(V, F)
    vertex_normals = np.zeros_like(V)
    for k in range(3):
        np.add.at(vertex_normals, F[:, k], normals * areas[:, None])
    length = np.linalg.norm(vertex_normals, axis=1, keepdims=True)
    vertex_normals = np.divide(vertex_normals, length, out=np.zeros_like(V), where=length > 0)
    return Mesh(V + vertex_normals * rng.normal(scale=scale, size=(len(V), 1)), F.copy())


@positional_options("seed", "noise")
def sample_points(V: ArrayLike, F: ArrayLike, n: int, *, seed: int = 0, noise: float = 0.0) -> PointCloud:
    """``n`` points sampled uniformly by area on the surface, with the true unit normals of the
    faces they lie on.

    noise: standard deviation of isotropic Gaussian noise added to the points, relative to the
    mean edge length (0: exactly on the surface; the normals are never perturbed).
    V: (v, 3) float array, F: (m, 3) integer array. Returns a :class:`meshsmith.core.PointCloud`
    (P (n, 3) float64, N (n, 3) float64).
    Same seed, same result. Raises InputError for a bad mesh, n < 1, noise < 0, or a mesh of
    zero area.
    """
    V, F = _mesh_arrays(V, F)
    n = _integer("n", n, 1)
    _not_too_large("points", n)
    noise = _non_negative("noise", noise)
    normals, areas = _face_normals_and_areas(V, F)
    total = areas.sum()
    if not total > 0:
        raise InputError("the mesh has zero area: no point can be sampled on it")
    rng = np.random.default_rng(_seed(seed))
    faces = rng.choice(len(F), size=n, p=areas / total)
    r1, r2 = rng.random(n), rng.random(n)
    root = np.sqrt(r1)  # uniform in the triangle: (1 - √r1, √r1 (1 - r2), √r1 r2)
    weights = np.stack([1.0 - root, root * (1.0 - r2), root * r2], 1)
    P = np.einsum("nk,nkd->nd", weights, V[F[faces]])
    if noise > 0:
        P = P + rng.normal(scale=noise * _mean_edge_length(V, F), size=P.shape)
    return PointCloud(P, normals[faces].copy())


def sphere_points(n: int, seed: int = 0, radius: float = 1.0) -> PointCloud:
    """``n`` points uniformly distributed on the sphere of ``radius`` around the origin, with
    their outward unit normals. Returns a :class:`meshsmith.core.PointCloud` (P (n, 3), N (n, 3)) float64. Same seed, same result.
    Raises InputError if n < 1 or radius <= 0.
    """
    n = _integer("n", n, 1)
    _not_too_large("points", n)
    radius = _positive("radius", radius)
    rng = np.random.default_rng(_seed(seed))
    N = rng.normal(size=(n, 3))
    length = np.linalg.norm(N, axis=1, keepdims=True)
    while np.any(length == 0):  # probability zero, but never divide by it
        redraw = length[:, 0] == 0
        N[redraw] = rng.normal(size=(int(redraw.sum()), 3))
        length = np.linalg.norm(N, axis=1, keepdims=True)
    N /= length
    return PointCloud(N * radius, N)


class ScanPair(NamedTuple):
    """Result of :func:`scan_pair`; unpacks as ``source, target, target_normals, motion, ...``.

    source: (n_source + k, 3) float64, the noisy surface samples then the k outliers, all moved
    by ``motion``; target: (n_target, 3) float64 clean samples; target_normals: (n_target, 3)
    their true unit normals; motion: (4, 4) the rigid transform applied to the source (so
    ``inverse(motion)`` is what registration must recover: ``T @ motion`` is the identity for a
    perfect ``T``); n_outliers: k (the last k rows of source); diagonal: the mesh's bounding-box
    diagonal, the unit of noise, translation and margin.
    """
    source: FloatArray
    target: FloatArray
    target_normals: FloatArray
    motion: FloatArray
    n_outliers: int
    diagonal: float


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation by `angle` radians about the unit `axis` (Rodrigues' formula)."""
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def scan_pair(V: ArrayLike, F: ArrayLike, *, n_source: int = 4000, n_target: int = 8000, noise: float = 0.01,
              outliers: float = 0.2, margin: float = 0.1, angle: float = 30.0, translation: float = 0.1,
              seed: int = 0) -> ScanPair:
    """A synthetic ICP scan pair of the surface (V, F) with a known motion (§2.3.1 tests,
    benchmark and demo): the target is ``n_target`` clean samples (:func:`sample_points`) with
    their true normals; the source is ``n_source`` other samples with isotropic Gaussian noise of
    ``noise`` × the bounding-box diagonal, plus outliers uniform in the bounding box grown by
    ``margin`` diagonals on every side, as the fraction ``outliers`` of the source's rows, all moved
    by a rotation of ``angle`` degrees about a random axis and a translation of ``translation``
    diagonals in a random direction (the motion is applied about the origin: x ↦ R x + t).

    V: (v, 3) float array, F: (m, 3) integer array. Returns a :class:`ScanPair`. Same seed, same
    result. Raises InputError for a bad mesh, n_source or n_target < 1, noise, margin, angle or
    translation negative or not finite, or outliers outside [0, 1).
    """
    V, F = _mesh_arrays(V, F)
    n_source, n_target = _integer("n_source", n_source, 1), _integer("n_target", n_target, 1)
    noise, margin = _non_negative("noise", noise), _non_negative("margin", margin)
    angle, translation = _non_negative("angle", angle), _non_negative("translation", translation)
    fraction = _non_negative("outliers", outliers)
    if not fraction < 1:
        raise InputError(f"outliers must be a fraction in [0, 1), got {outliers!r}")
    n_outliers = int(round(n_source * fraction / (1.0 - fraction)))
    _not_too_large("points", n_source + n_outliers)
    rng = np.random.default_rng(_seed(seed))
    first, second = (int(x) for x in rng.integers(0, 2 ** 63 - 1, size=2))
    target, target_normals = sample_points(V, F, n_target, seed=first)
    assert target_normals is not None  # sample_points always gives the face normals
    clean, _ = sample_points(V, F, n_source, seed=second)
    low, high = V.min(axis=0), V.max(axis=0)
    diagonal = float(np.linalg.norm(high - low))
    noisy_points = clean + noise * diagonal * rng.normal(size=clean.shape)
    wrong = rng.uniform(low - margin * diagonal, high + margin * diagonal, size=(n_outliers, 3))
    motion = np.eye(4)
    motion[:3, :3] = _rotation(_unit(rng.normal(size=3)), np.radians(angle))
    motion[:3, 3] = translation * diagonal * _unit(rng.normal(size=3))
    source = np.vstack([noisy_points, wrong]) @ motion[:3, :3].T + motion[:3, 3]
    return ScanPair(source, target, target_normals, motion, n_outliers, diagonal)


class PartialViews(NamedTuple):
    """Result of :func:`partial_views`; unpacks as ``scans, poses, starts, diagonal``.

    scans: list of (n_points, 3) float64 arrays, view i in its own frame (``pose_i⁻¹ · points``);
    poses: (n_views, 4, 4) the true poses (pose 0 the identity); starts: (n_views, 4, 4) the true
    poses perturbed (start 0 the identity), the initial guesses of a multi-view registration;
    diagonal: the mesh's bounding-box diagonal, the unit of noise and shifts.
    """
    scans: list[FloatArray]
    poses: FloatArray
    starts: FloatArray
    diagonal: float


def _random_motion(rng: np.random.Generator, angle: float, shift: float) -> FloatArray:
    """A rigid motion: rotation by `angle` degrees about a random axis, translation of length `shift`."""
    T = np.eye(4)
    T[:3, :3] = _rotation(_unit(rng.normal(size=3)), np.radians(angle))
    T[:3, 3] = shift * _unit(rng.normal(size=3))
    return T


def partial_views(V: ArrayLike, F: ArrayLike, *, n_views: int = 4, n_points: int = 4000, noise: float = 0.002,
                  pose_angle: float = 25.0, pose_shift: float = 0.05, start_angle: float = 10.0,
                  start_shift: float = 0.02, n_samples: int = 30000, seed: int = 4) -> PartialViews:
    """Partial "scans" of the surface (V, F) seen from ``n_views`` directions around the y axis,
    each in its own frame, with known poses (the §2.3.1 multi-view tests and benchmark).

    ``n_samples`` surface samples (:func:`sample_points` with ``seed``); view i keeps
    ``n_points`` of those whose outward normal faces its direction (cos a, 0, sin a),
    a = 2πi/n_views (normal · direction > −0.1), adds Gaussian noise of ``noise`` diagonals, and is
    expressed in its frame: scan i = pose_i⁻¹ · points, pose_0 the identity and the others
    ``pose_angle`` degrees about a random axis and ``pose_shift`` diagonals away; start i is
    pose_i perturbed by ``start_angle`` degrees and ``start_shift`` diagonals. Views, noise and
    motions draw from ``seed + 1``: the same seed gives the same views.

    Raises InputError for a bad mesh, n_views < 1, n_points < 1, a view with fewer than n_points
    samples facing it, or a negative or non-finite noise, angle or shift.
    """
    V, F = _mesh_arrays(V, F)
    n_views, n_points = _integer("n_views", n_views, 1), _integer("n_points", n_points, 1)
    n_samples = _integer("n_samples", n_samples, 1)
    noise = _non_negative("noise", noise)
    pose_angle, pose_shift = _non_negative("pose_angle", pose_angle), _non_negative("pose_shift", pose_shift)
    start_angle, start_shift = _non_negative("start_angle", start_angle), _non_negative("start_shift", start_shift)
    diagonal = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    P, N = sample_points(V, F, n_samples, seed=_seed(seed))
    assert N is not None  # sample_points always gives the face normals
    rng = np.random.default_rng(_seed(seed) + 1)
    scans, poses, starts = [], [], []
    for k in range(n_views):
        azimuth = 2.0 * np.pi * k / n_views
        seen = np.flatnonzero(N @ np.array([np.cos(azimuth), 0.0, np.sin(azimuth)]) > -0.1)
        if len(seen) < n_points:
            raise InputError(f"view {k} sees {len(seen)} of the {n_samples} samples, fewer than n_points={n_points}")
        part = P[rng.permutation(seen)[:n_points]]
        part = part + noise * diagonal * rng.normal(size=part.shape)
        pose = np.eye(4) if k == 0 else _random_motion(rng, pose_angle, pose_shift * diagonal)
        scans.append(np.ascontiguousarray((part - pose[:3, 3]) @ pose[:3, :3]))   # pose⁻¹ · part
        poses.append(pose)
        starts.append(pose if k == 0 else pose @ _random_motion(rng, start_angle, start_shift * diagonal))
    return PartialViews(scans, np.array(poses), np.array(starts), diagonal)
