"""Stitching (§2.4.1): closing cracks and T-junctions between boundary loops that run side by
side, by inserting boundary vertices into the opposite boundary edges and merging boundary
vertices closer than a tolerance."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components as _graph_components

from .. import _arguments
from .._core import InputError
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray
from ..points import KdTree
from .unreferenced import remove_unreferenced

__all__ = ["StitchedMesh", "stitch_boundaries"]


@dataclass(frozen=True)
class StitchedMesh(Unpackable):
    """The result of :func:`stitch_boundaries`; unpacks as ``V, F``.

    V: (n', 3) float64, input vertices (unmoved, ``V == V_in[vertex_map]``); F: (m', 3) int64;
    vertex_map: (n',) int64, the input vertex of each output vertex (a merged group's lowest
    index); face_map: (m',) int64, the input face each output face comes from (a split face gives
    several); split_edges: boundary edges that T-junction vertices were inserted into;
    inserted_vertices: vertices inserted into them; merged_vertices: boundary vertices merged
    into another one; removed_faces: faces left with a repeated vertex by a merge (two of their
    corners closer than the tolerance), removed; boundary_edges_before / _after.
    """

    V: FloatArray
    F: IndexArray
    vertex_map: IndexArray
    face_map: IndexArray
    split_edges: int
    inserted_vertices: int
    merged_vertices: int
    removed_faces: int
    boundary_edges_before: int
    boundary_edges_after: int

    unpacks = ("V", "F")


def boundary_sides(F: np.ndarray) -> np.ndarray:
    """(k, 2) rows (face, corner where the side starts) of the sides no other face shares: the
    boundary edges of F (m, 3). O(m log m), on one int64 key per side."""
    F = np.asarray(F, dtype=np.int64)
    if not F.size:
        return np.zeros((0, 2), dtype=np.int64)
    start, end = F.ravel(), np.roll(F, -1, axis=1).ravel()      # side 3f + c runs from corner c to c + 1
    key = np.minimum(start, end) * (int(F.max()) + 1) + np.maximum(start, end)
    _, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
    boundary = np.flatnonzero(counts[inverse] == 1)
    return np.column_stack([boundary // 3, boundary % 3])


def _insert_t_junctions(V: FloatArray, F: np.ndarray, face_map: np.ndarray,
                        tolerance: float) -> tuple[np.ndarray, np.ndarray, int, int]:
    """One pass of stitch_boundaries' step 1, at most one side per face: (F, face_map, split
    edges, inserted vertices)."""
    sides = boundary_sides(F)
    if not len(sides):
        return F, face_map, 0, 0
    starts = F[sides[:, 0], sides[:, 1]]
    ends = F[sides[:, 0], (sides[:, 1] + 1) % 3]
    opposite = F[sides[:, 0], (sides[:, 1] + 2) % 3]
    boundary_vertices = np.unique(np.concatenate([starts, ends]))
    a, b = V[starts], V[ends]
    half = np.linalg.norm(b - a, axis=1) / 2
    offsets, found, _ = KdTree(V[boundary_vertices]).query_radius((a + b) / 2, float(half.max()) + tolerance)
    edge = np.repeat(np.arange(len(sides)), np.diff(offsets))
    vertex = boundary_vertices[found]
    keep = (vertex != starts[edge]) & (vertex != ends[edge])
    edge, vertex = edge[keep], vertex[keep]
    direction = b[edge] - a[edge]
    length2 = np.einsum("ij,ij->i", direction, direction)
    t = np.einsum("ij,ij->i", V[vertex] - a[edge], direction) / np.where(length2 > 0, length2, 1)
    distance = np.linalg.norm(V[vertex] - (a[edge] + t[:, None] * direction), axis=1)
    # Inside the edge and farther than the tolerance from both ends (a vertex near an end is
    # merged with it in step 2 instead).
    chosen = np.flatnonzero((distance <= tolerance) & (t > 0) & (t < 1) &
                            (np.linalg.norm(V[vertex] - a[edge], axis=1) > tolerance) &
                            (np.linalg.norm(V[vertex] - b[edge], axis=1) > tolerance))
    if not len(chosen):
        return F, face_map, 0, 0
    # Each vertex into its nearest edge; each face along one side.
    chosen = chosen[np.lexsort((distance[chosen], vertex[chosen]))]
    first = np.ones(len(chosen), dtype=bool)
    first[1:] = vertex[chosen][1:] != vertex[chosen][:-1]
    chosen = chosen[first]
    split_sides = np.unique(edge[chosen])
    _, one_per_face = np.unique(sides[split_sides, 0], return_index=True)
    split_sides = split_sides[one_per_face]
    new_faces, new_map = [], []
    replaced = np.zeros(len(F), dtype=bool)
    count = 0
    for e in split_sides.tolist():
        on_edge = chosen[edge[chosen] == e]
        on_edge = on_edge[np.argsort(t[on_edge])]
        chain = [starts[e], *vertex[on_edge].tolist(), ends[e]]
        new_faces += [[chain[i], chain[i + 1], opposite[e]] for i in range(len(chain) - 1)]
        new_map += [face_map[sides[e, 0]]] * (len(chain) - 1)
        replaced[sides[e, 0]] = True
        count += len(on_edge)
    F = np.vstack([F[~replaced], np.asarray(new_faces, dtype=np.int64)])
    face_map = np.concatenate([face_map[~replaced], np.asarray(new_map, dtype=np.int64)])
    return F, face_map, len(split_sides), count


@_arguments.real_options
def stitch_boundaries(V: ArrayLike, F: ArrayLike, *, tolerance: float) -> StitchedMesh:
    """Close the cracks and T-junctions between boundary loops that run side by side (§2.4.1).

    1. T-junctions: a boundary vertex within ``tolerance`` of a boundary edge it is not on, whose
       projection falls inside the edge farther than ``tolerance`` from both ends, is inserted into
       that edge (its nearest such edge): the edge's face is split into a fan through it, so the
       edge gets the vertex the other side has.
    2. Cracks: boundary vertices within ``tolerance`` of each other are merged (transitively, into
       the lowest index, which keeps its position), so the two sides' edges become one.
    Faces that a merge leaves with a repeated vertex are removed (counted). Interior vertices and
    every position stay as they are; vertices no face uses any more are dropped. The result is
    manifold where the two sides matched one to one; run :func:`meshsmith.repair.clean` after it
    to orient components stitched with opposite orientations, and :func:`fill_holes` for what the
    tolerance did not close.

    V: (n, 3) float array, F: (m, 3) integer array; tolerance > 0, in the units of V (a fraction of
    the edge length: a tolerance near the edge length merges the vertices of one side with each
    other). Returns a :class:`StitchedMesh`. Raises InputError for bad input or tolerance.
    Time O((n_b + e_b) log n_b) for n_b boundary vertices and e_b boundary edges.
    """
    tolerance = float(tolerance)
    if not (np.isfinite(tolerance) and tolerance > 0):
        raise InputError(f"tolerance = {tolerance!r}: expected a finite number > 0")
    V1, F1, vertex_map = remove_unreferenced(V, F)
    face_map = np.arange(len(F1), dtype=np.int64)
    boundary_edges_before = len(boundary_sides(F1))
    split_edges = inserted = 0
    # A face with T-junctions on two of its sides is split along one per pass; the next pass finds
    # the other on one of its pieces.
    for _ in range(8):
        F1, face_map, edges, vertices = _insert_t_junctions(V1, F1, face_map, tolerance)
        split_edges += edges
        inserted += vertices
        if not edges:
            break

    # Merge boundary vertices closer than the tolerance.
    merged = removed = 0
    sides = boundary_sides(F1)
    if len(sides):
        boundary_vertices = np.unique(F1[sides[:, 0], sides[:, 1]])
        tree = KdTree(V1[boundary_vertices])
        offsets, found, _ = tree.query_radius(V1[boundary_vertices], np.nextafter(tolerance, np.inf))
        rows = np.repeat(np.arange(len(boundary_vertices)), np.diff(offsets))
        graph = coo_matrix((np.ones(len(rows), dtype=np.int8), (rows, found)),
                           shape=(len(boundary_vertices), len(boundary_vertices)))
        count, label = _graph_components(graph, directed=False)
        if count < len(boundary_vertices):
            representative = np.full(count, len(V1), dtype=np.int64)
            np.minimum.at(representative, label, boundary_vertices)
            target = np.arange(len(V1), dtype=np.int64)
            target[boundary_vertices] = representative[label]
            merged = len(boundary_vertices) - count
            F1 = target[F1]
            degenerate = (F1[:, 0] == F1[:, 1]) | (F1[:, 1] == F1[:, 2]) | (F1[:, 0] == F1[:, 2])
            removed = int(degenerate.sum())
            F1, face_map = F1[~degenerate], face_map[~degenerate]
    if not len(F1):
        raise InputError("stitch_boundaries: the tolerance merged every face away (it is near the edge length)")
    V2, F2, used = remove_unreferenced(V1, F1)
    return StitchedMesh(V=V2, F=F2, vertex_map=vertex_map[used], face_map=face_map, split_edges=split_edges,
                        inserted_vertices=inserted, merged_vertices=merged, removed_faces=removed,
                        boundary_edges_before=boundary_edges_before,
                        boundary_edges_after=len(boundary_sides(F2)))

