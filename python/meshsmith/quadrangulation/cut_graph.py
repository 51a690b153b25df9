"""Cutting a surface into a disk through every singularity of a cross field, and combing the
field on it (§5.2.2 step 2); C++ src/quadrangulation/cut_graph.cpp (the cut is
parametrization.cut_to_disk's).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .._core import quadrangulation as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray
from ..parametrization.cut import CutMesh, cut_on_input_vertices
from ..repair.unreferenced import ReferencedMesh, on_referenced_vertices
from .cross_field import FieldLike, Singularities, field_angles

__all__ = ["FieldCut", "cut_graph"]


@dataclass(frozen=True)
class FieldCut(Unpackable):
    """The result of :func:`cut_graph`; unpacks as ``cut, singularities, combed_theta, seam_jumps``.

    cut: the :class:`meshsmith.parametrization.CutMesh` (a disk); singularities: the field's
    :class:`Singularities`, all on the seam or the boundary; combed_theta: (m,) float64 the field
    turned by whole quarter turns per face so that its period jump is 0 across every edge not
    cut; seam_jumps: (c,) int64 the period jump across each seam edge (``cut.seam_edges`` order),
    from the face whose side runs i → j to the other, in {−1, 0, 1, 2}.
    """

    cut: CutMesh
    singularities: Singularities
    combed_theta: FloatArray
    seam_jumps: IndexArray


def field_cut(out: dict[str, Any], mesh: ReferencedMesh, V: ArrayLike) -> FieldCut:
    """The binding's cut dictionary as a FieldCut on the input's vertex numbering."""
    cut = cut_on_input_vertices(CutMesh(out["V"], out["F"], out["vertex_origin"], out["seam_edges"]), mesh, V)
    vertices = mesh.vertex_map[out["singular_vertices"]] if mesh.removed else out["singular_vertices"]
    return FieldCut(cut=cut, singularities=Singularities(vertices, out["singular_indices"]),
                    combed_theta=out["combed_theta"], seam_jumps=out["seam_jumps"])


def cut_graph(V: ArrayLike, F: ArrayLike, field: FieldLike) -> FieldCut:
    """Cut (V, F) into a topological disk through every singular vertex of `field` and comb the
    field on the disk (§5.2.2 step 2).

    The cut is :func:`meshsmith.parametrization.cut_to_disk`'s (a dual spanning tree, pruned:
    the 2g homology loops, joined to the boundary) with each singularity joined to it by a
    shortest edge path. field: a :class:`CrossField`, (m,) angles or (m, 3) directions.
    Returns a :class:`FieldCut` (unpacks as ``cut, singularities, combed_theta, seam_jumps``).
    Raises InputError as :func:`cross_field`.
    """
    theta = field_angles(V, F, field)
    mesh = on_referenced_vertices(V, F)
    return field_cut(_core.cut_graph(mesh.V, mesh.F, theta), mesh, V)
