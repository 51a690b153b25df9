"""Watertight reconstruction from unoriented samples by an s–t minimum cut of a voxel grid, and the
Boykov–Kolmogorov max-flow it runs on (§2.2, §3.2); binding cpp/python/reconstruction_graph_cut.cpp,
C++ src/reconstruction/graph_cut.cpp."""
from __future__ import annotations

from typing import NamedTuple

from .. import _arguments
from .._core import reconstruction as _core
from .._typing import ArrayLike, BoolArray, FloatArray, IndexArray, ProgressCallback

__all__ = ["GraphCutMesh", "MinimumCut", "graph_cut", "max_flow"]


class GraphCutMesh(NamedTuple):
    """The result of :func:`graph_cut`; unpacks as ``V, F, ...``.

    V: (n, 3) float64, F: (m, 3) int64 (outward). shape: grid points per axis; origin: position
    of grid point (0, 0, 0); voxel_size: the grid spacing; cut: the minimum cut's value (Σ of
    the cut edges' weights); free_voxels: grid points whose side the cut decided (the graph's
    nodes); inside_voxels: grid points inside after the cut.
    """

    V: FloatArray
    F: IndexArray
    shape: tuple[int, int, int]
    origin: tuple[float, float, float]
    voxel_size: float
    cut: float
    free_voxels: int
    inside_voxels: int


class MinimumCut(NamedTuple):
    """The result of :func:`max_flow`; unpacks as ``flow, source_side``.

    flow: the maximum flow (= the minimum cut's capacity); source_side: (n,) bool, the nodes
    reachable from the source in the residual graph (the source side of a minimum cut).
    """

    flow: float
    source_side: BoolArray


def max_flow(node_count: int, edges: ArrayLike, capacities: ArrayLike, reverse_capacities: ArrayLike,
             source: ArrayLike, sink: ArrayLike) -> MinimumCut:
    """Maximum s–t flow and minimum cut by Boykov & Kolmogorov's algorithm (2004).

    node_count: n; edges: (m, 2) int node pairs (u != v, in [0, n)); capacities: (m,) from u to
    v, reverse_capacities: (m,) from v to u; source: (n,) capacity from the source to each node,
    sink: (n,) from each node to the sink. Capacities are finite reals >= 0. Returns a
    :class:`MinimumCut`. Raises InputError for a wrong shape, a node out of range, a self-loop or a
    negative, NaN or infinite capacity.
    """
    flow, side = _core.max_flow(node_count, edges, capacities, reverse_capacities, source, sink)
    return MinimumCut(float(flow), side)


@_arguments.real_options
def graph_cut(P: ArrayLike, *, resolution: int = 64, crust: float = 2.0, exponent: float = 4.0,
              inside: ArrayLike | None = None, progress: ProgressCallback = None) -> GraphCutMesh:
    """A watertight surface through unoriented samples by a minimum cut (Hornung & Kobbelt 2006).

    P: (n, 3) samples of a closed surface, n >= 4, no normals needed. On a grid of cubic cells
    (`resolution` cells along the samples' longest bounding-box edge, padded) the unsigned
    distance d to the nearest sample is computed at each grid point; the crust is where d < w =
    `crust` · max(cell, median sample spacing). The outside seed is the grid points outside the
    crust reachable from the box's border, the inside seed those it encloses (a fill that leaked
    through a gap between samples encloses only pockets near them, so until an enclosed point is 2w
    from the samples, w grows by 1.5 and the fill is redone; or, with `inside`,
    an (s, 3) array of positions, the box's border and the seeds' grid points). Every other grid
    point is a node of a 6-connected graph with edge weights ((d_a + d_b) / 2w)^exponent + 1e-4, cut
    by Boykov–Kolmogorov max-flow (:func:`max_flow`), and the surface is the zero set of d
    signed by the cut, extracted by :func:`marching_cubes`: closed, edge-manifold, outward.

    Returns a :class:`GraphCutMesh`. Raises InputError for fewer than 4 samples, a NaN, samples on
    one line, resolution outside [2, 1024], crust outside [0.5, 16], exponent outside [1, 16], a
    grid above 2^26 points, an inside seed outside the box, or no enclosed grid point (a gap in
    the samples wider than the crust: raise `crust`, or give `inside`). Time: the distance
    queries (grid points · log n) and the max-flow on the crust; memory about 20 bytes per grid point.
    """
    return GraphCutMesh(**_core.graph_cut(P, resolution, _arguments.real(crust, "crust"),
                                          _arguments.real(exponent, "exponent"), inside, progress))
