"""Per-triangle distortion of a parametrization and exact point-to-surface, Hausdorff and mean surface distances; binding cpp/python/geometry_metrics.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, NamedTuple, overload

from .. import _arguments
from .._core import geometry as _geometry
from .._deprecation import positional_options
from .._results import Unpackable
from .._typing import ArrayLike, BoolArray, FloatArray, IndexArray, ProgressCallback

__all__ = ["TriangleDistortion", "triangle_distortion", "SurfaceDistance", "ClosestPoints", "SurfaceDistances",
           "hausdorff_distance", "mean_surface_distance"]


@dataclass(frozen=True)
class TriangleDistortion(Unpackable):
    """Distortion of the map from each parameter (UV) triangle onto its 3D triangle.

    m = number of faces, n = number of vertices. Every measure is 1 for an isometry.

    Per face:
      jacobians (m, 2, 2): J of the affine map UV -> 3D triangle, in the orthonormal frame
        (x, y) of the 3D triangle (x along v1 - v0, y = n x x), so det J < 0 iff the UV triangle
        is clockwise.
      singular_values (m, 2): sigma1 >= sigma2 >= 0 of J (J^T J is the first fundamental form).
      isometric (m,): symmetric Dirichlet energy normalised to 1 at isometries,
        (s1^2 + s2^2 + s1^-2 + s2^-2) / 4.
      conformal (m,): s1 / s2 (1 for a conformal map).
      area (m,): s1 * s2 = 3D area / UV area (1 for an equiareal map).
      stretch_l2 (m,): sqrt((s1^2 + s2^2) / 2), Sander et al.'s L2 stretch (§5's s_Delta).
      stretch_linf (m,): s1, Sander et al.'s L-infinity stretch.
      flipped (m,) bool: det J < 0 (UV triangle orientation reversed).
      surface_areas (m,): 3D triangle areas (the averaging weights).
      parameter_areas (m,): signed UV triangle areas (negative when flipped).
    Per vertex (n,), area-weighted averages over the incident faces (weights = 3D areas, §5
    s_{p_i}): vertex_isometric, vertex_conformal, vertex_area, vertex_stretch_l2,
    vertex_stretch_linf. NaN for a vertex with no incident face of positive 3D area.
    Global:
      global_stretch_l2: sqrt(sum A s^2 / sum A) (1 for an isometry).
      normalized_global_stretch_l2: global_stretch_l2 * sqrt(sum |UV area| / sum A), invariant
        to a uniform scale of UV (1 for an isometry up to scale).
      global_stretch_linf: max s1.
      (The three global values are NaN only when no face has positive 3D area;
      normalized_global_stretch_l2 is +inf when every UV triangle has zero area.)
    Index lists (int64, ascending): flipped_faces; degenerate_parameter_faces (UV area exactly 0
    with positive 3D area: J, sigma and every measure are +inf there, and so are the averages
    touching them); degenerate_surface_faces (3D area 0: sigma2 = 0, conformal and isometric
    +inf, area 0; weight 0, so left out of every average; never flipped).
    """

    jacobians: FloatArray
    singular_values: FloatArray
    isometric: FloatArray
    conformal: FloatArray
    area: FloatArray
    stretch_l2: FloatArray
    stretch_linf: FloatArray
    flipped: BoolArray
    surface_areas: FloatArray
    parameter_areas: FloatArray
    vertex_isometric: FloatArray
    vertex_conformal: FloatArray
    vertex_area: FloatArray
    vertex_stretch_l2: FloatArray
    vertex_stretch_linf: FloatArray
    global_stretch_l2: float
    normalized_global_stretch_l2: float
    global_stretch_linf: float
    flipped_faces: IndexArray
    degenerate_parameter_faces: IndexArray
    degenerate_surface_faces: IndexArray


def triangle_distortion(V: ArrayLike, F: ArrayLike, UV: ArrayLike) -> TriangleDistortion:
    """Distortion of the parametrization UV of the mesh (V, F), per triangle and per vertex.

    The map of each triangle goes from its UV triangle to its 3D triangle (§5: the Jacobian of
    that affine map, its singular values sigma1 >= sigma2 and the isometric / conformal /
    equiareal measures; §1.2.2: J^T J is the first fundamental form).

    V: (n, 3) float array of surface positions. F: (m, 3) integer array of triangles.
    UV: (n, 2) float array of parameter positions, one per vertex.
    Returns a :class:`TriangleDistortion` (see its docstring for every field and for how
    degenerate UV triangles (+inf, listed) and degenerate 3D triangles (weight 0) are reported).
    Raises InputError for a bad mesh (empty, NaN/Inf, index out of range), UV of the wrong shape,
    UV with a NaN/Inf, or UV with a number of rows other than n.
    """
    return TriangleDistortion(**_geometry.triangle_distortion(V, F, UV))


class ClosestPoints(NamedTuple):
    """Result of :meth:`SurfaceDistance.closest_points`; unpacks as ``distance, face, point``."""

    distance: FloatArray  #: (k,) Euclidean distances
    face: IndexArray      #: (k,) index of a nearest face
    point: FloatArray     #: (k, 3) closest surface points


class SurfaceDistances(NamedTuple):
    """Symmetric and one-sided distances between two surfaces (``one_sided=True`` of
    :func:`hausdorff_distance` and :func:`mean_surface_distance`); unpacks as
    ``symmetric, a_to_b, b_to_a``."""

    symmetric: float
    a_to_b: float
    b_to_a: float


class SurfaceDistance:
    """Exact point-to-surface distances to a triangle mesh, with an AABB tree built once.

    ``SurfaceDistance(V, F, *, leaf_size=4)``: V (n, 3) float array, F (m, 3) integer array (both
    copied); the tree splits the triangles at the median centroid along the longest axis, down
    to ``leaf_size`` triangles per leaf. Build once, then query many times; queries run in
    parallel and give the same result for any thread count.
    Raises InputError for a bad mesh (empty, NaN/Inf, index out of range) or leaf_size < 1.
    """

    @positional_options("leaf_size")
    def __init__(self, V: ArrayLike, F: ArrayLike, *, leaf_size: int = 4) -> None:
        self._tree = _geometry.SurfaceDistance(V, F, leaf_size)

    @property
    def face_count(self) -> int:
        """Number of triangles in the tree."""
        return int(self._tree.face_count)

    @positional_options("progress")
    def closest_points(self, Q: ArrayLike, *, progress: ProgressCallback = None) -> ClosestPoints:
        """Closest surface point of each query point.

        Q: (k, 3) float array (k may be 0). progress: optional ``(fraction, stage) -> bool``.
        Returns a :class:`ClosestPoints` ``(distance, face, point)``: (k,) float64 Euclidean distances, (k,) int64 index
        of a nearest face (the first found when several are equally near, e.g. at a shared
        vertex), (k, 3) float64 closest points. Same distances as libigl's
        ``point_mesh_squared_distance`` (which returns squared ones); where a query is equally
        near to several surface points (inside a convex corner, on a medial axis) the face and
        point may be another of them.
        Raises InputError for Q of the wrong shape or with a NaN/Inf.
        """
        distance, face, point = self._tree.closest_points(Q, progress)
        return ClosestPoints(distance, face, point)

    @positional_options("progress")
    def distances(self, Q: ArrayLike, *, progress: ProgressCallback = None) -> FloatArray:
        """(k,) float64 distances from the rows of Q (k, 3) to the surface; as closest_points."""
        return self._tree.distances(Q, progress)


def _sampling(sampled: bool, samples_per_face: object) -> int:
    if not sampled:
        return 0
    return _arguments.integer(samples_per_face, "samples_per_face", 1, 2 ** 31 - 1)  # the core bounds m * it


@overload
def hausdorff_distance(VA: ArrayLike, FA: ArrayLike, VB: ArrayLike, FB: ArrayLike, *, sampled: bool = ...,
                       samples_per_face: int = ..., seed: int = ..., one_sided: Literal[False] = ...,
                       progress: ProgressCallback = ...) -> float: ...
@overload
def hausdorff_distance(VA: ArrayLike, FA: ArrayLike, VB: ArrayLike, FB: ArrayLike, *, sampled: bool = ...,
                       samples_per_face: int = ..., seed: int = ..., one_sided: Literal[True],
                       progress: ProgressCallback = ...) -> SurfaceDistances: ...
@overload
def hausdorff_distance(VA: ArrayLike, FA: ArrayLike, VB: ArrayLike, FB: ArrayLike, *, sampled: bool = ...,
                       samples_per_face: int = ..., seed: int = ..., one_sided: bool,
                       progress: ProgressCallback = ...) -> float | SurfaceDistances: ...
def hausdorff_distance(VA: ArrayLike, FA: ArrayLike, VB: ArrayLike, FB: ArrayLike, *, sampled: bool = False,
                       samples_per_face: int = 16, seed: int = 0, one_sided: bool = False,
                       progress: ProgressCallback = None) -> float | SurfaceDistances:
    """Symmetric Hausdorff distance between the surfaces (VA, FA) and (VB, FB).

    Each one-sided distance is the maximum, over sample points of one surface, of the exact
    distance to the other surface (closest point on its triangles, AABB tree):

    - ``sampled=False`` (default): the samples are the vertices, so the result is
      ``max(max_a d(a, B), max_b d(b, A))`` over the vertex rows, exactly what libigl's
      ``hausdorff`` computes (a lower bound of the true Hausdorff distance).
    - ``sampled=True``: the vertices plus ``samples_per_face`` points per face, uniform in each
      triangle from a hash of (seed, face, sample): a tighter (larger) lower bound that tends to
      the true Hausdorff distance as samples_per_face grows. Deterministic for a given seed
      (an integer in [0, 2^64)).
      m * samples_per_face may be at most 2^27 per mesh (a bound on memory).

    VA, VB: (n, 3) float arrays; FA, FB: (m, 3) integer arrays.
    Returns the distance (float, in the mesh's length unit), or with ``one_sided=True`` a
    :class:`SurfaceDistances` ``(symmetric, a_to_b, b_to_a)``. Raises InputError for a bad mesh (the message names VA, FA,
    VB or FB for a wrong shape or dtype, "mesh A" or "mesh B" for bad values) or
    samples_per_face < 1 with sampled=True.
    """
    result = _geometry.hausdorff_distance(VA, FA, VB, FB, _sampling(sampled, samples_per_face), seed, progress)
    return SurfaceDistances(*(float(x) for x in result)) if one_sided else float(result[0])


@overload
def mean_surface_distance(VA: ArrayLike, FA: ArrayLike, VB: ArrayLike, FB: ArrayLike, *, sampled: bool = ...,
                          samples_per_face: int = ..., seed: int = ..., one_sided: Literal[False] = ...,
                          progress: ProgressCallback = ...) -> float: ...
@overload
def mean_surface_distance(VA: ArrayLike, FA: ArrayLike, VB: ArrayLike, FB: ArrayLike, *, sampled: bool = ...,
                          samples_per_face: int = ..., seed: int = ..., one_sided: Literal[True],
                          progress: ProgressCallback = ...) -> SurfaceDistances: ...
@overload
def mean_surface_distance(VA: ArrayLike, FA: ArrayLike, VB: ArrayLike, FB: ArrayLike, *, sampled: bool = ...,
                          samples_per_face: int = ..., seed: int = ..., one_sided: bool,
                          progress: ProgressCallback = ...) -> float | SurfaceDistances: ...
def mean_surface_distance(VA: ArrayLike, FA: ArrayLike, VB: ArrayLike, FB: ArrayLike, *, sampled: bool = False,
                          samples_per_face: int = 16, seed: int = 0, one_sided: bool = False,
                          progress: ProgressCallback = None) -> float | SurfaceDistances:
    """Mean distance between the surfaces (VA, FA) and (VB, FB), area-weighted.

    The one-sided value a_to_b approximates ``(1/|A|) * integral over A of d(x, B)``:

    - ``sampled=False`` (default): the vertices of A weighted by their lumped (barycentric)
      area ``sum of A_f / 3`` over the incident faces (unreferenced vertices weigh 0);
    - ``sampled=True``: ``samples_per_face`` points per face of A, uniform in the triangle
      (hash of seed, face, sample), each weighted by ``A_f / samples_per_face`` (the vertices
      are then not used): a Monte-Carlo estimate of the integral.

    The symmetric value is ``(|A| a_to_b + |B| b_to_a) / (|A| + |B|)``, the mean over both
    surfaces together. Returns that float, or with ``one_sided=True`` a
    :class:`SurfaceDistances` ``(symmetric, a_to_b, b_to_a)``. Raises InputError as :func:`hausdorff_distance`, and when a
    surface has zero total area.
    """
    result = _geometry.mean_surface_distance(VA, FA, VB, FB, _sampling(sampled, samples_per_face), seed,
                                             progress)
    return SurfaceDistances(*(float(x) for x in result)) if one_sided else float(result[0])
