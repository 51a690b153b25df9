"""Cutting a closed or higher-genus mesh into a topological disk (§5.2.2 step 2); C++ src/parametrization/cut_to_disk.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _arguments
from .._core import parametrization as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray
from ..repair.unreferenced import ReferencedMesh, on_referenced_vertices

__all__ = ["CutMesh", "cut_to_disk", "cut_on_input_vertices"]


@dataclass(frozen=True)
class CutMesh(Unpackable):
    """A mesh cut open into a topological disk (:func:`cut_to_disk`); unpacks as
    ``V_cut, F_cut, vertex_origin, seam_edges``.

    V: (k, 3) float64 positions, V[i] == input V[vertex_origin[i]]; F: (m, 3) int64, face f is
    the input face f on the copies of its corners; vertex_origin: (k,) int64, the input vertex of
    each output vertex (the first n entries are 0..n-1; seam copies are appended);
    seam_edges: (c, 2) int64 input edges (i < j) cut open (empty for a disk).
    """

    V: FloatArray
    F: IndexArray
    vertex_origin: IndexArray
    seam_edges: IndexArray


def cut_to_disk(V: ArrayLike, F: ArrayLike, *, through: ArrayLike | None = None) -> CutMesh:
    """Cut a closed or higher-genus surface into one topological disk (§5.2.2 step 2).

    A breadth-first spanning tree of the triangles (across edges) is grown from face 0; the edges
    it never crosses, pruned of dangling branches, are the 2g handle loops plus the paths joining
    the boundary loops: the seam. A closed genus-0 mesh is cut along the shortest edge path
    between two far-apart vertices. A disk comes back unchanged.
    through: optional (k,) input vertex indices the seam must also pass through (the
    singularities of a cross field, for :func:`meshsmith.quadrangulation.miq`): each is joined
    to the seam or the boundary by its shortest edge path (a disk is cut for an interior one).

    V: (n, 3) float array, F: (m, 3) integer array.
    Returns a :class:`CutMesh`; it unpacks as ``V_cut, F_cut, vertex_origin, seam_edges``.
    Vertices no face uses stay in V, unreferenced (the cut runs on the others).
    Raises InputError for a mesh that is non-manifold or not oriented (clean it first with
    :func:`meshsmith.repair.clean`), has several components or zero-area / repeated-index faces.
    """
    mesh = on_referenced_vertices(V, F)
    if through is not None and mesh.removed:
        through = mesh.from_input_indices(_arguments.index_array(through, "through"))
    return cut_on_input_vertices(CutMesh(**_core.cut_to_disk(mesh.V, mesh.F, through=through)), mesh, V)


def cut_on_input_vertices(cut: CutMesh, mesh: ReferencedMesh, V: ArrayLike) -> CutMesh:
    """A cut of the referenced part `mesh` of the input (V, F), renumbered onto the input: its
    first n vertices are V's (the unreferenced ones stay unused), the seam copies appended."""
    if not mesh.removed:
        return cut
    n, kept = mesh.input_vertex_count, len(mesh.vertex_map)
    renumber = np.concatenate([mesh.vertex_map, n + np.arange(len(cut.V) - kept, dtype=np.int64)])
    return CutMesh(V=np.concatenate([np.asarray(V, dtype=np.float64), cut.V[kept:]]), F=renumber[cut.F],
                   vertex_origin=np.concatenate([np.arange(n, dtype=np.int64), renumber[cut.vertex_origin[kept:]]]),
                   seam_edges=mesh.vertex_map[cut.seam_edges])
