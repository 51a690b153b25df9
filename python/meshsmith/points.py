"""Points chapter: nearest neighbours, PCA normals and normal orientation of point clouds.

§2.2 steps 1 and 2 of the curriculum ("Regression Line (Normal Estimation)" in §1): each point
gets the normal of the least-squares plane of its neighbourhood (unoriented), then the normals
are oriented consistently by propagation along a minimum spanning tree (Hoppe et al. 1992).

Points are float64 arrays of shape (n, 3). Neighbour indices come back as int64. The kd-tree
(nanoflann) runs its queries in parallel; results do not depend on the number of threads.
"""
from __future__ import annotations

from typing import Literal, NamedTuple, overload

from . import _arguments
from ._core import InputError
from ._core import points as _core
from ._deprecation import positional_options
from ._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback

__all__ = ["KdTree", "knn", "Neighbours", "RadiusNeighbours", "NormalEstimate", "estimate_normals",
           "orient_normals"]


class Neighbours(NamedTuple):
    """Result of :func:`knn` and :meth:`KdTree.query`; unpacks as ``indices, distances``."""

    indices: IndexArray    #: (m, k) indices into the points, nearest first
    distances: FloatArray  #: (m, k) Euclidean distances


class RadiusNeighbours(NamedTuple):
    """Result of :meth:`KdTree.query_radius` in compressed-row form; unpacks as
    ``offsets, indices, distances``: the neighbours of query i are
    ``indices[offsets[i]:offsets[i + 1]]``."""

    offsets: IndexArray    #: (m + 1,)
    indices: IndexArray    #: (total,) nearest first within each query
    distances: FloatArray  #: (total,)


class NormalEstimate(NamedTuple):
    """Result of :func:`estimate_normals` with ``return_variation=True``; unpacks as
    ``normals, variation``."""

    normals: FloatArray    #: (n, 3) unoriented unit normals
    variation: FloatArray  #: (n,) surface variation λ0 / (λ0 + λ1 + λ2), in [0, 1/3]


class KdTree:
    """A kd-tree over a copy of n points: build once, query many times.

    ``KdTree(P, *, leaf_size=10)``: P (n, 3) real array, finite, n >= 1; leaf_size: points per
    leaf (default 10).
    Raises InputError for empty input, NaN/Inf or leaf_size < 1.

    Ties: points at exactly the same distance from a query come in an unspecified (but
    deterministic) order, so with ties the last neighbour may differ from scipy's cKDTree
    while the distances agree.
    """

    @positional_options("leaf_size")
    def __init__(self, P: ArrayLike, *, leaf_size: int = 10) -> None:
        self._tree = _core.KdTree(P, leaf_size)

    def __len__(self) -> int:
        return len(self._tree)

    @property
    def points(self) -> FloatArray:
        """(n, 3) copy of the points the tree was built on."""
        return self._tree.points

    def query(self, k: int, Q: ArrayLike | None = None, *, progress: ProgressCallback = None) -> Neighbours:
        """k nearest tree points of each query point.

        k: number of neighbours. Q: (m, 3) query points, or None to query the tree's own points,
        in which case each point's own index is excluded (a duplicate point at distance 0 is
        another point and is listed).
        Returns a :class:`Neighbours` (indices, distances): (m, k) int64 and (m, k) float64,
        nearest first.
        Raises InputError if k < 1, k > n (Q given) or k >= n (Q None), or Q holds NaN/Inf.
        """
        return Neighbours(*self._tree.query(k, Q, progress))

    def query_radius(self, Q: ArrayLike, radius: float, *, progress: ProgressCallback = None) -> RadiusNeighbours:
        """All tree points at distance < radius (strictly) of each query point, nearest first.

        Q: (m, 3) query points. Returns a :class:`RadiusNeighbours` (offsets, indices,
        distances) in compressed-row form:
        the neighbours of query i are indices[offsets[i]:offsets[i + 1]] (int64), with their
        distances. offsets has m + 1 entries. Raises InputError for radius <= 0, NaN/Inf.
        """
        return RadiusNeighbours(*self._tree.query_radius(Q, _arguments.real(radius, "radius"), progress))

    @overload
    def estimate_normals(self, *, k: int = ..., radius: float | None = ..., return_variation: Literal[False] = ...,
                         progress: ProgressCallback = ...) -> FloatArray: ...
    @overload
    def estimate_normals(self, *, k: int = ..., radius: float | None = ..., return_variation: Literal[True],
                         progress: ProgressCallback = ...) -> NormalEstimate: ...
    @overload
    def estimate_normals(self, *, k: int = ..., radius: float | None = ..., return_variation: bool,
                         progress: ProgressCallback = ...) -> FloatArray | NormalEstimate: ...
    @positional_options("k", "radius")
    def estimate_normals(self, *, k: int = 16, radius: float | None = None, return_variation: bool = False,
                         progress: ProgressCallback = None) -> FloatArray | NormalEstimate:
        """:func:`estimate_normals` on the tree's points, reusing the tree."""
        normals, variation = self._tree.estimate_normals(k, _radius(radius), progress)
        return NormalEstimate(normals, variation) if return_variation else normals


def knn(P: ArrayLike, k: int, Q: ArrayLike | None = None, *, progress: ProgressCallback = None) -> Neighbours:
    """k nearest neighbours in P of each row of Q (or of each point of P).

    P: (n, 3) points. k: number of neighbours. Q: (m, 3) query points, or None: then the
    queries are the points of P themselves and each point's own index is excluded from its
    list (a duplicate point at distance 0 is another point and is listed), so k <= n - 1.
    Returns a :class:`Neighbours` (indices, distances): (m, k) int64 indices into P and (m, k)
    float64 Euclidean distances, nearest first. Ties at equal distance come in an unspecified order.
    Raises InputError if k < 1, k is too large for n, or P/Q are empty or hold NaN/Inf.
    """
    return Neighbours(*_core.knn(P, k, Q, progress))


def _radius(radius: float | None) -> float:
    if radius is None:
        return 0.0
    radius = _arguments.real(radius, "radius")
    if not radius > 0.0:  # 0 would silently mean "use k" in the core
        raise InputError(f"radius = {radius} must be positive and finite")
    return radius


@overload
def estimate_normals(P: ArrayLike, *, k: int = ..., radius: float | None = ..., return_variation: Literal[False] = ...,
                     progress: ProgressCallback = ...) -> FloatArray: ...
@overload
def estimate_normals(P: ArrayLike, *, k: int = ..., radius: float | None = ..., return_variation: Literal[True],
                     progress: ProgressCallback = ...) -> NormalEstimate: ...
@overload
def estimate_normals(P: ArrayLike, *, k: int = ..., radius: float | None = ..., return_variation: bool,
                     progress: ProgressCallback = ...) -> FloatArray | NormalEstimate: ...
@positional_options("k", "radius")
def estimate_normals(P: ArrayLike, *, k: int = 16, radius: float | None = None, return_variation: bool = False,
                     progress: ProgressCallback = None) -> FloatArray | NormalEstimate:
    """Unoriented unit normals by PCA of each point's neighbourhood (§2.2 step 1).

    P: (n, 3) points. The neighbourhood of point i is i itself and its k nearest other points
    (k + 1 points), or, when `radius` is given, every point at distance < radius from i
    (i included; a ball with fewer than 3 points is replaced by i's 3 nearest points).
    The normal is the eigenvector of the smallest eigenvalue of the centred covariance of the
    neighbourhood; its sign is arbitrary (see :func:`orient_normals`).

    Returns N, (n, 3) float64 unit normals, or with return_variation=True a
    :class:`NormalEstimate` (N, variation):
    variation (n,) is the surface variation λ0 / (λ0 + λ1 + λ2) (0 on a plane, at most 1/3),
    a per-point quality measure. Degenerate neighbourhoods (all points coincide) get the
    fallback normal (0, 0, 1) and variation 1/3; no normal is ever NaN.
    Raises InputError if k < 3, n <= k (kNN) or n < 3 (radius), radius <= 0, or NaN/Inf.
    """
    normals, variation = _core.estimate_normals(P, k, _radius(radius), progress)
    return NormalEstimate(normals, variation) if return_variation else normals


@positional_options("k")
def orient_normals(P: ArrayLike, N: ArrayLike, *, k: int = 16, alpha: float = 0.1, beta: float = 0.9, axis: int = 2,
                   progress: ProgressCallback = None) -> FloatArray:
    """Orient normals consistently by minimum-spanning-tree propagation (§2.2 step 2).

    P: (n, 3) points, N: (n, 3) unoriented normals (nonzero; e.g. from estimate_normals).
    Builds the graph joining each point to its k nearest others (symmetrised) with edge cost
    alpha * |p_i - p_j| / h + beta * (1 - |<n_i, n_j>|), h the mean kNN edge length (so alpha
    is scale-free; only the ratio alpha : beta matters). In each connected component the point
    with the largest coordinate along `axis` (0, 1, 2 = x, y, z) is the seed, its normal is
    pointed towards +axis (outward for a closed surface), and Prim's minimum spanning tree is
    grown from it, flipping each normal to agree with its parent in the tree.

    Returns an (n, 3) copy of N with some rows negated. Raises InputError if shapes differ,
    a normal is zero, k < 1 or k >= n, axis is not 0/1/2, alpha/beta < 0 or both 0, or NaN/Inf.
    """
    return _core.orient_normals(P, N, k, _arguments.real(alpha, "alpha"), _arguments.real(beta, "beta"), axis, progress)
