"""Vertex clustering (§4.1): one representative per occupied grid cell; binding cpp/python/decimation_clustering.cpp.
"""
from __future__ import annotations

from typing import NamedTuple

from .._core import InputError
from .._core import decimation as _core
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback

__all__ = ["CLUSTER_REPRESENTATIVES", "ClusteredMesh", "cluster"]


CLUSTER_REPRESENTATIVES = ("center", "centroid", "median", "quadric")


class ClusteredMesh(NamedTuple):
    """Result of :func:`cluster`.

    V: (k, 3) float64 representatives; F: (l, 3) int64 surviving triangles; vertex_cluster: (n,)
    int64, the output vertex of each input vertex (-1: unreferenced, or its cell lost all its
    triangles); is_manifold: whether F is manifold (clustering does not guarantee it);
    cell_size: the edge length of the grid cells used.
    """
    V: FloatArray
    F: IndexArray
    vertex_cluster: IndexArray
    is_manifold: bool
    cell_size: float


def cluster(V: ArrayLike, F: ArrayLike, *, cell_size: float | None = None, target_vertices: int | None = None,
            representative: str = "quadric", progress: ProgressCallback = None) -> ClusteredMesh:
    """Decimate by vertex clustering on a uniform grid (§4.1; Rossignac & Borrel 1993).

    Every referenced vertex falls into a cube of edge ``cell_size`` (the grid starts at the
    minimum corner of the vertices); each occupied cell becomes one vertex; a triangle survives
    iff its corners lie in three different cells; duplicate triangles (same three cells) are
    kept once. Fast, but the result need not be manifold: check ``is_manifold``.

    V: (n, 3) float array, F: (m, 3) integer array. Give exactly one of
    cell_size: the cells' edge length (> 0), or
    target_vertices: the wanted number of occupied cells; the cell size is found by bisection
    (the output can have a few vertices less: cells whose triangles all vanish are dropped).
    representative: where a cell's vertex goes: "center" (of the cell), "centroid" (mean of its
    vertices), "median" (per-coordinate median, as ``np.median``) or "quadric" (default: the
    minimiser of the squared distances to the planes of the triangles at its vertices, through
    the pseudo-inverse of §4.1.1, so flat cells stay at their centroid and feature corners are
    kept; the centroid if the minimiser falls outside the cell).
    progress: optional ``(fraction, stage) -> bool`` callback.

    Returns a :class:`ClusteredMesh`. Raises InputError for bad input, when both or neither of
    cell_size and target_vertices are given, for a cell size that is not positive or so small
    that an axis needs 2**21 cells or more, or an unknown representative.
    """
    if (cell_size is None) == (target_vertices is None):
        raise InputError("cluster: give exactly one of cell_size and target_vertices")
    if target_vertices is not None:
        size = _core.cell_size_for_vertex_count(V, F, target_vertices)  # the binding checks the integer
    else:
        size = cell_size
    V_out, F_out, vertex_cluster, is_manifold, size = _core.cluster_vertices(
        V, F, float(size), representative, progress)
    return ClusteredMesh(V_out, F_out, vertex_cluster.reshape(-1), bool(is_manifold), float(size))
