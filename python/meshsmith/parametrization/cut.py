"""Cutting a closed or higher-genus mesh into a topological disk (§5.2.2 step 2); C++ src/parametrization/cut_to_disk.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core import parametrization as _core

__all__ = ["CutMesh", "cut_to_disk"]


@dataclass(frozen=True)
class CutMesh:
    """A mesh cut open into a topological disk (:func:`cut_to_disk`).

    V: (k, 3) float64 positions, V[i] == input V[vertex_origin[i]]; F: (m, 3) int64, face f is
    the input face f on the copies of its corners; vertex_origin: (k,) int64, the input vertex of
    each output vertex (the first n entries are 0..n-1; seam copies are appended);
    seam_edges: (c, 2) int64 input edges (i < j) cut open (empty for a disk).
    """

    V: np.ndarray
    F: np.ndarray
    vertex_origin: np.ndarray
    seam_edges: np.ndarray

    def __iter__(self):
        """Unpacks as ``V_cut, F_cut, seam = cut_to_disk(V, F)`` (seam: this object)."""
        return iter((self.V, self.F, self))


def cut_to_disk(V, F) -> CutMesh:
    """Cut a closed or higher-genus surface into one topological disk (§5.2.2 step 2).

    A breadth-first spanning tree of the triangles (across edges) is grown from face 0; the edges
    it never crosses, pruned of dangling branches, are the 2g handle loops plus the paths joining
    the boundary loops: the seam. A closed genus-0 mesh is cut along the shortest edge path
    between two far-apart vertices. A disk comes back unchanged.

    V: (n, 3) float array, F: (m, 3) integer array.
    Returns a :class:`CutMesh`; it unpacks as ``V_cut, F_cut, seam`` (``seam.seam_edges``,
    ``seam.vertex_origin``).
    Raises InputError for a mesh that is non-manifold, not oriented, has several components,
    isolated vertices or zero-area / repeated-index faces.
    """
    return CutMesh(**_core.cut_to_disk(V, F))
