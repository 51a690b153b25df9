"""The defects of a mesh, counted (§2.4): what `meshsmith info` lists and :func:`clean`,
:func:`fill_holes` and :func:`remove_self_intersections` fix. Every count comes from an existing
function (meshsmith.topology, meshsmith.core.mesh_defects, this chapter's orient_faces and
self_intersections)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import core, topology
from .._results import Unpackable
from .._typing import ArrayLike, ProgressCallback
from .intersections import self_intersections
from .orient import orient_faces

__all__ = ["MeshDefectCounts", "find_defects", "INTERSECTION_FACE_LIMIT"]

#: find_defects looks for self-intersections by default only up to this many faces.
INTERSECTION_FACE_LIMIT = 200_000

#: The counts of a MeshDefectCounts with the words `meshsmith info` prints for them.
DEFECT_COUNTS = {
    "boundary_loops": "boundary loops (holes and borders)",
    "boundary_edges": "boundary edges",
    "non_manifold_edges": "non-manifold edges (more than two faces)",
    "non_manifold_vertices": "non-manifold vertices (more than one fan)",
    "degenerate_faces": "degenerate faces (repeated vertex)",
    "zero_area_faces": "zero-area faces",
    "duplicate_faces": "duplicate faces",
    "unreferenced_vertices": "unreferenced vertices",
    "flipped_faces": "faces against their component's orientation",
    "flipped_components": "flipped components (inside out, or faces disagreeing)",
    "non_orientable_components": "non-orientable components",
    "self_intersecting_pairs": "self-intersecting face pairs",
}


@dataclass(frozen=True)
class MeshDefectCounts(Unpackable):
    """The defects :func:`find_defects` counted; unpacks in field order.

    boundary_loops and boundary_edges (every loop counts, a scan's rim as much as a hole; as
    :func:`meshsmith.topology.boundary_loops` finds them, so the edges of a duplicated face
    copied in reverse count too);
    non_manifold_edges and non_manifold_vertices (:func:`meshsmith.topology.non_manifold_edges`
    / ``_vertices``); degenerate_faces, zero_area_faces, duplicate_faces and unreferenced_vertices
    (:func:`meshsmith.core.mesh_defects`, each face in one kind only); flipped_faces (the faces
    :func:`orient_faces` would reverse) and flipped_components (the connected components holding
    one: a closed one inside out, or one whose faces disagree), non_orientable_components;
    self_intersecting_pairs (:func:`self_intersections`), None when not looked for.
    """

    boundary_loops: int
    boundary_edges: int
    non_manifold_edges: int
    non_manifold_vertices: int
    degenerate_faces: int
    zero_area_faces: int
    duplicate_faces: int
    unreferenced_vertices: int
    flipped_faces: int
    flipped_components: int
    non_orientable_components: int
    self_intersecting_pairs: int | None

    def counts(self) -> dict[str, int | None]:
        """Every count, by field name (JSON-ready; None: not looked for)."""
        return {name: getattr(self, name) for name in DEFECT_COUNTS}

    def has_defects(self) -> bool:
        """True when there is any defect (boundary loops count: an open surface has them)."""
        return any(self.counts().values())

    def lines(self) -> list[str]:
        """One line per kind of defect found, and one saying when self-intersections were not
        looked for; ["no defects found"] for a clean closed mesh."""
        lines = [f"{value:,} {DEFECT_COUNTS[name]}" for name, value in self.counts().items() if value]
        if self.self_intersecting_pairs is None:
            lines.append("self-intersections not looked for")
        return lines or ["no defects found"]

    def __str__(self) -> str:
        return "\n".join(self.lines())


def find_defects(V: ArrayLike, F: ArrayLike, *, intersections: bool | None = None,
                 progress: ProgressCallback = None) -> MeshDefectCounts:
    """Count the defects of a triangle mesh (§2.4): holes, non-manifold edges and vertices,
    degenerate, zero-area and duplicate faces, unreferenced vertices, flipped components and,
    with ``intersections`` (by default when the mesh has at most
    :data:`INTERSECTION_FACE_LIMIT` faces), self-intersecting face pairs.

    V: (n, 3) float array, F: (m, 3) integer array. Returns a :class:`MeshDefectCounts`. Time
    O(m log m), plus the self-intersection test's. Changes nothing (:func:`clean` fixes most of
    it). Raises InputError for bad input (:func:`meshsmith.core.validate_mesh`); Cancelled from
    ``progress``.
    """
    found = core.mesh_defects(V, F)
    faces = np.asarray(F, dtype=np.int64)
    degenerate = set(found.degenerate_faces.tolist())
    zero_area = set(found.zero_area_faces.tolist()) - degenerate
    duplicate = set(found.duplicate_faces.tolist()) - degenerate - zero_area
    loops = topology.boundary_loops(faces)
    oriented = orient_faces(V, faces)
    labels = topology.connected_components(faces, len(np.asarray(V))).face_labels
    if intersections is None:
        intersections = len(faces) <= INTERSECTION_FACE_LIMIT
    pairs = len(self_intersections(V, faces, progress=progress)) if intersections else None
    return MeshDefectCounts(
        boundary_loops=len(loops), boundary_edges=int(sum(len(loop) for loop in loops)),
        non_manifold_edges=len(topology.non_manifold_edges(faces)),
        non_manifold_vertices=len(topology.non_manifold_vertices(faces)),
        degenerate_faces=len(degenerate), zero_area_faces=len(zero_area), duplicate_faces=len(duplicate),
        unreferenced_vertices=len(found.unreferenced_vertices), flipped_faces=len(oriented.flipped),
        flipped_components=len(np.unique(labels[oriented.flipped])),
        non_orientable_components=oriented.non_orientable_components, self_intersecting_pairs=pairs)
