"""Marching cubes on a regular grid, dense or following the surface through blocks (§2.2, §3.1);
binding cpp/python/reconstruction.cpp, C++ src/reconstruction/marching_cubes.cpp."""
from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np

from .. import _arguments
from .._core import reconstruction as _core
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback

__all__ = ["ContourMesh", "marching_cubes", "marching_cubes_sparse"]


class ContourMesh(NamedTuple):
    """An iso-surface; unpacks as ``V, F, centre_vertices, blocks, evaluations``.

    V: (n, 3) float64 vertices, one per grid edge whose end values straddle the iso-value (in the
    order of those edges: grid point in C order, then the axis), followed by nothing else unless
    centre_vertices > 0 (a cell loop that needed a centre vertex; rare). F: (m, 3) int64
    triangles, counter-clockwise seen from outside (normals towards increasing values).
    blocks: blocks of cells visited; evaluations: grid values read or evaluated.
    """

    V: FloatArray
    F: IndexArray
    centre_vertices: int
    blocks: int
    evaluations: int


@_arguments.real_options
def marching_cubes(values: ArrayLike, *, origin: ArrayLike = (0.0, 0.0, 0.0), spacing: ArrayLike = (1.0, 1.0, 1.0),
                   iso: float = 0.0, progress: ProgressCallback = None) -> ContourMesh:
    """The iso-surface ``values == iso`` of a field sampled on a regular grid, as a triangle mesh.

    values: (nx, ny, nz) float array, values[i, j, k] at ``origin + (i, j, k) * spacing``
    (each of nx, ny, nz >= 2). A value below `iso` is inside, at or above it outside; the output
    has one vertex per crossed grid edge (linear interpolation: the vertex set of libigl's and
    scikit-image's marching cubes on the same grid), normals pointing outside (towards
    increasing values, e.g. outward for a signed distance that is negative inside), and no
    cracks or holes: face ambiguities are resolved by the asymptotic decider, so the mesh is
    edge-manifold and closed wherever the level set does not leave the grid.

    origin, spacing: 3 floats (spacing > 0). Returns a :class:`ContourMesh`. Raises InputError
    for a wrong shape, a NaN/Inf value or a bad origin/spacing/iso. O(nx·ny·nz), parallel.
    """
    return ContourMesh(**_core.marching_cubes(values, origin, spacing, iso, progress))


@_arguments.real_options
def marching_cubes_sparse(field: Callable[[FloatArray], ArrayLike], *, shape: ArrayLike, seeds: ArrayLike,
                          origin: ArrayLike = (0.0, 0.0, 0.0), spacing: ArrayLike = (1.0, 1.0, 1.0),
                          iso: float = 0.0, block_size: int = 8, dilation: int = 0,
                          progress: ProgressCallback = None) -> ContourMesh:
    """Marching cubes on a virtual grid, visiting only the blocks of cells the surface crosses.

    field: a function of an (m, 3) float64 array of grid positions returning m values (called
    once per wave of blocks, with the corners of up to 2048 blocks of block_size³ cells; it must
    return the same value for the same point every time). shape: the grid's 3 point counts
    (each >= 2), origin and spacing as in :func:`marching_cubes`. seeds: (s, 3) positions near
    the surface (e.g. the samples a field was fitted to): their blocks, grown by `dilation`
    rings, are contoured first, then every block sharing a crossed grid edge with a visited one,
    until the surface closes. The result equals :func:`marching_cubes` on the full grid (same
    vertices in the same order; with block_size 8 the same triangles in the same order) for the
    pieces of the level set that pass through a seed's block; the full grid is never allocated.

    Returns a :class:`ContourMesh`. Raises InputError for bad arguments, no seed inside the grid,
    a field that returns a wrong shape or a NaN, or more than 2^22 blocks visited.
    """
    return ContourMesh(**_core.marching_cubes_sparse(field, shape, origin, spacing, seeds, iso, block_size,
                                                     dilation, progress))
