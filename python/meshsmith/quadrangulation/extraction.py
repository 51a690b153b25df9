"""Quad extraction: the integer grid of a seamless parametrization as a quad mesh (§5.2.2 step 4)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import topology
from .._core import quadrangulation as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback

__all__ = ["QuadExtractionReport", "QuadExtraction", "extract_quads"]


@dataclass(frozen=True)
class QuadExtractionReport(Unpackable):
    """What :func:`extract_quads` found in the parametrization and what it left out.

    flipped_triangles, degenerate_triangles: faces whose (u, v) triangle is clockwise / has zero
    area. non_seamless_edges: interior edges whose two sides are not related by a quarter-turn
    rotation and an integer translation. non_integer_singularities: singular vertices not on an
    integer point. untangled_vertices: free vertices of clockwise triangles that were moved, in
    (u, v), to the mean of their ring because that left fewer bad triangles (flipped_triangles
    counts those left). singular_vertices (s,) int64 and singular_indices (s,) int64: the interior
    vertices of non-zero index, in quarter turns (+1 for valence 3, -1 for valence 5).
    squares_cut_by_boundary: unit squares that a boundary edge crosses (left out);
    squares_inconsistent: squares whose pieces do not fit together (left out); quads_non_manifold:
    quads removed so the rest is manifold. euler_input, euler_output: χ of the triangle and quad
    meshes. mirrored: the map was clockwise overall and was read as (u, -v). complete: nothing was
    left out and χ is preserved. holes: boundary loops of the quad mesh beyond the input's (where
    squares were left out; 0 when complete).
    """

    flipped_triangles: int
    degenerate_triangles: int
    non_seamless_edges: int
    non_integer_singularities: int
    untangled_vertices: int
    singular_vertices: IndexArray
    singular_indices: IndexArray
    squares_cut_by_boundary: int
    squares_inconsistent: int
    quads_non_manifold: int
    euler_input: int
    euler_output: int
    mirrored: bool
    complete: bool
    holes: int


@dataclass(frozen=True)
class QuadExtraction(Unpackable):
    """The result of :func:`extract_quads`; unpacks as ``V, Q``.

    V: (k, 3) float64 grid nodes on the surface; Q: (q, 4) int64 quads, counter-clockwise like the
    input's faces; node_uv: (k, 2) float64, each node's integer (u, v) in the chart of node_face (k,)
    int64, the input face it lies in (or on the boundary of); report: a :class:`QuadExtractionReport`.
    """

    unpacks = ("V", "Q")
    V: FloatArray
    Q: IndexArray
    node_uv: FloatArray
    node_face: IndexArray
    report: QuadExtractionReport


def extract_quads(V: ArrayLike, F: ArrayLike, UV: ArrayLike, *, progress: ProgressCallback = None) -> QuadExtraction:
    """Extract the quad mesh of the integer grid of a seamless parametrization (§5.2.2 step 4; the
    setting of QEx, Ebke et al. 2013).

    Every unit square [i, i+1] × [j, j+1] of the (u, v) plane whose preimage on the surface is a
    complete disk becomes one quad, with its corners at the preimages of the integer points.
    Predicates are exact (the map is first made exactly seamless on a dyadic grid), so grid points
    on edges and at vertices, and iso-lines along edges, get the same answer from both sides of
    every seam.

    V: (n, 3) float array; F: (m, 3) integer array, a manifold triangle mesh; UV: (m, 3, 2) float
    array of per-corner (u, v), seamless (across each interior edge the two sides differ by a
    rotation k·π/2 and an integer translation), singular vertices on integer points, boundaries on
    integer iso-lines. progress: optional callback (fraction, stage) -> bool (False cancels).

    Returns a :class:`QuadExtraction` (unpacks as ``V, Q``): always a manifold, consistently
    oriented pure quad mesh. Where the map is degenerate (flipped or zero-area triangles, seams that
    do not match, non-integer singularities, boundaries across squares) the squares concerned are
    left out and ``result.report`` counts them; ``report.complete`` says the result covers the
    surface with the input's Euler characteristic. Raises InputError for bad input (shapes, NaN,
    non-manifold meshes, faces repeating a vertex, |uv| >= 2^40, a grid of more than 2^26 unit
    squares over the triangles' bounding boxes).
    """
    Vq, Q, node_uv, node_face, report = _core.extract_quads(V, F, UV, progress)
    loops_out = len(topology.boundary_loops(np.concatenate([Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]]))) if len(Q) else 0
    report["holes"] = max(0, loops_out - len(topology.boundary_loops(F)))
    report["singular_vertices"] = np.asarray(report["singular_vertices"], dtype=np.int64)
    report["singular_indices"] = np.asarray(report["singular_indices"], dtype=np.int64)
    return QuadExtraction(Vq, Q, node_uv, node_face, QuadExtractionReport(**report))
