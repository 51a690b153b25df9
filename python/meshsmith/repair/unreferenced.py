"""Unreferenced vertices: removing them, and running an algorithm that needs every vertex used on
the referenced part of a mesh with its results mapped back to the caller's vertex indices (§2.4).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import core as _core
from .._results import Unpackable
from .._typing import ArrayLike, IndexArray

__all__ = ["ReferencedMesh", "remove_unreferenced", "on_referenced_vertices"]


@dataclass(frozen=True)
class ReferencedMesh(Unpackable):
    """The result of :func:`remove_unreferenced`; unpacks as ``V, F, vertex_map``.

    V: (k, 3) float64, the vertices some face uses, in their input order; F: (m, 3) int64, the
    input faces on those vertices (same order); vertex_map: (k,) int64, the input vertex of each
    output vertex (ascending), so ``V == V_in[vertex_map]`` and ``vertex_map[F] == F_in``;
    input_vertex_count: n, the number of input vertices.
    """

    V: np.ndarray
    F: np.ndarray
    vertex_map: np.ndarray
    input_vertex_count: int

    unpacks = ("V", "F", "vertex_map")

    @property
    def removed(self) -> int:
        """How many input vertices no face uses."""
        return self.input_vertex_count - len(self.vertex_map)

    def to_input_rows(self, values: ArrayLike, fill: float = np.nan) -> np.ndarray:
        """Per-vertex values of this mesh, (k, ...) -> (n, ...) on the input's vertex indices,
        `fill` (NaN by default) in the rows of the unreferenced vertices."""
        values = _arguments.numbers(values, "values")
        fill = _arguments.real(fill, "fill")
        if values.ndim == 0 or len(values) != len(self.vertex_map):
            raise InputError(f"values has shape {values.shape}: expected one row per vertex of the mesh "
                             f"({len(self.vertex_map)}, ...)")
        if self.removed == 0:
            return values
        dtype = np.result_type(values.dtype, np.asarray(fill).dtype)
        out = np.full((self.input_vertex_count,) + values.shape[1:], fill, dtype=dtype)
        out[self.vertex_map] = values
        return out

    def to_input_indices(self, indices: ArrayLike) -> IndexArray:
        """Vertex indices of this mesh -> the input's (int64, same shape)."""
        checked = _arguments.numbers(indices, "indices", "index").astype(np.int64)
        outside = (checked < 0) | (checked >= len(self.vertex_map))
        if outside.any():
            raise InputError(f"indices: vertex {int(checked[outside].flat[0])} is outside [0, {len(self.vertex_map)})")
        return self.vertex_map[checked]

    def from_input_indices(self, indices: ArrayLike, what: str = "vertex list") -> IndexArray:
        """The input's vertex indices -> this mesh's (int64, same shape).

        Raises InputError for an index outside [0, n) or a vertex no face uses (naming it)."""
        indices = _arguments.numbers(indices, what, "index").astype(np.int64, copy=False)
        if self.removed == 0:
            return indices
        outside = (indices < 0) | (indices >= self.input_vertex_count)
        if outside.any():
            raise InputError(f"{what}: vertex {int(indices[outside].flat[0])} is outside "
                             f"[0, {self.input_vertex_count})")
        position = np.searchsorted(self.vertex_map, indices)
        found = self.vertex_map[np.minimum(position, len(self.vertex_map) - 1)] == indices
        if not found.all():
            raise InputError(f"{what}: vertex {int(indices[~found].flat[0])} is used by no face")
        return position


def remove_unreferenced(V: ArrayLike, F: ArrayLike) -> ReferencedMesh:
    """Remove the vertices no face uses (§2.4), keeping the others in their order.

    V: (n, 3) float array, F: (m, 3) integer array (m >= 1). Returns a :class:`ReferencedMesh`
    (unpacks as ``V2, F2, vertex_map``; vertex_map[i] is the input vertex of output vertex i).
    A mesh without unreferenced vertices comes back as float64/int64 copies with the identity
    map. O(n + m). Raises InputError if (V, F) fails :func:`meshsmith.core.validate_mesh`.
    """
    mesh = on_referenced_vertices(V, F)
    if mesh.removed:
        return mesh
    return ReferencedMesh(mesh.V.copy(), mesh.F.astype(np.int64), mesh.vertex_map, mesh.input_vertex_count)


def on_referenced_vertices(V: ArrayLike, F: ArrayLike) -> ReferencedMesh:
    """:func:`remove_unreferenced` for algorithms that need every vertex used and map their
    results back (:meth:`ReferencedMesh.to_input_rows`, ``to_input_indices``,
    ``from_input_indices``): the same result, but without copying V and F when every vertex is
    used. Parametrization and progressive meshes call it first. Raises InputError as
    :func:`remove_unreferenced`."""
    _core.validate_mesh(V, F)
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    vertex_map, new_index = referenced_indices(F, len(V))
    if new_index is None:
        return ReferencedMesh(V, F, vertex_map, len(V))
    return ReferencedMesh(V[vertex_map], new_index[F], vertex_map, len(V))


def referenced_indices(F: np.ndarray, n_vertices: int) -> tuple[IndexArray, IndexArray | None]:
    """(vertex_map, new_index) of faces F (indices checked to be in [0, n_vertices)): vertex_map
    (k,) int64 the vertices some face uses, ascending; new_index (n,) int64 each vertex's index
    among them (-1 unused rows' values are meaningless), or None when every vertex is used (then
    vertex_map is arange(n)). The index part of on_referenced_vertices, for functions without V."""
    used = np.zeros(n_vertices, dtype=bool)
    used[np.asarray(F).ravel()] = True
    if used.all():
        return np.arange(n_vertices, dtype=np.int64), None
    return np.flatnonzero(used).astype(np.int64), np.cumsum(used, dtype=np.int64) - 1
