"""Self-intersecting face pairs (§2.4) with CGAL's exact predicates, and their removal by cutting
the intersecting faces out and filling the holes this leaves; binding
cpp/python/repair_intersections.cpp, C++ src/repair/self_intersections_cgal.cpp."""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .. import _arguments, topology
from .._core import InputError
from .._core import repair as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from .holes import fill_holes
from .unreferenced import remove_unreferenced

__all__ = ["self_intersections", "remove_self_intersections", "IntersectionRemoval", "IntersectionFreeMesh"]


def self_intersections(V: ArrayLike, F: ArrayLike, *, progress: ProgressCallback = None) -> IndexArray:
    """The pairs of faces that intersect other than along what they share (§2.4).

    Two faces with no common vertex that touch or cross; two faces with one common vertex that
    meet elsewhere; two faces with a common edge folded onto each other (coplanar, on the same
    side of it); two faces on the same three vertices. Candidates are the pairs whose bounding
    boxes meet (CGAL's box intersection), decided with CGAL's exact predicates, so the answer
    does not depend on rounding or on the thread count. Degenerate faces (collinear or repeated
    corners, which :func:`meshsmith.repair.clean` removes) take no part.

    V: (n, 3) float array, F: (m, 3) integer array. Returns (k, 2) int64 face pairs, f < g in each
    row, rows sorted. O(m log m + candidates). Raises InputError for bad input; Cancelled from
    ``progress``.
    """
    return _core.self_intersections(V, F, progress=progress)


#: The counts of an IntersectionRemoval with the words `meshsmith repair` prints for them.
REMOVAL_COUNTS = {
    "initial_pairs": "self-intersecting face pairs found",
    "rounds": "rounds of removal and filling",
    "removed_faces": "faces removed",
    "filled_holes": "holes filled",
    "added_faces": "faces added by the fills",
    "unfilled_holes": "holes left open (the fill failed)",
    "remaining_pairs": "self-intersecting face pairs left",
}


@dataclass(frozen=True)
class IntersectionRemoval(Unpackable):
    """What :func:`remove_self_intersections` did; unpacks as ``initial_pairs, remaining_pairs``.

    Counts (ints): initial_pairs (self-intersecting pairs of the input), rounds (rounds that
    removed faces), removed_faces (faces cut out over all rounds, patch faces of earlier rounds
    included), filled_holes and unfilled_holes (loops the fills closed / left open), added_faces
    (patch faces in the output), remaining_pairs (self-intersecting pairs of the output: 0 unless
    ``max_rounds`` ran out, e.g. on two closed components that overlap, which only a boolean or
    volumetric repair resolves). face_origin: (m',) int64, the input face of each output face, -1
    for a patch face; vertex_map: (n',) int64, the input vertex of each output vertex, -1 for a
    vertex a fill added.
    """

    initial_pairs: int
    remaining_pairs: int
    rounds: int
    removed_faces: int
    filled_holes: int
    unfilled_holes: int
    added_faces: int
    face_origin: IndexArray
    vertex_map: IndexArray

    unpacks = ("initial_pairs", "remaining_pairs")

    def counts(self) -> dict[str, int]:
        """Every count, by field name (JSON-ready)."""
        return {name: int(getattr(self, name)) for name in REMOVAL_COUNTS}

    def lines(self) -> list[str]:
        """One line per count, the zero ones too (a clean input says "0 ... found")."""
        return [f"{value:,} {REMOVAL_COUNTS[name]}" for name, value in self.counts().items()]

    def __str__(self) -> str:
        return "\n".join(self.lines())


class IntersectionFreeMesh(NamedTuple):
    """The result of :func:`remove_self_intersections`: ``V, F, report = remove_self_intersections(V, F)``."""

    V: FloatArray
    F: IndexArray
    report: IntersectionRemoval


def _face_rings(F: np.ndarray, faces: np.ndarray, rings: int) -> np.ndarray:
    """`faces` (a boolean mask over F) grown by `rings` rings of faces sharing a vertex."""
    for _ in range(rings):
        touched = np.zeros(int(F.max()) + 1, dtype=bool)
        touched[F[faces].ravel()] = True
        faces = touched[F].any(axis=1)
    return faces


def remove_self_intersections(V: ArrayLike, F: ArrayLike, *, max_rounds: int = 6, refine: bool = True,
                              fair: bool = True, faces: ArrayLike | None = None,
                              progress: ProgressCallback = None) -> IntersectionFreeMesh:
    """Cut out the self-intersecting faces and fill the holes this leaves, until none intersect (§2.4).

    Each round finds the intersecting pairs (:func:`self_intersections`), removes every face of
    a pair, grown by one ring of faces (sharing a vertex) per earlier round so that a fill that
    failed to clear an intersection gets more room, then fills exactly the boundary loops that
    the removal opened (:func:`meshsmith.repair.fill_holes` with ``refine`` and ``fair``; the
    input's own borders stay open). Rounds stop when no pair is left or after ``max_rounds``;
    the report says how many pairs remain. Vertices no face uses any more are removed. A local
    fold or a poke-through is resolved in a round or two; two closed components that overlap are
    not (any closed fill of one still crosses the other): their pairs are left, counted.

    ``faces``: a (m,) boolean mask of the faces that may be removed (with the patches of the
    fills, which always may): only the pairs with at least one such face are resolved (counted,
    in initial_pairs and remaining_pairs), by removing those faces and rings grown within the
    mask; every other face is kept, so the pairs among them stay, uncounted. E.g. the faces a
    seam made, so that what was there before is left as it was.

    V: (n, 3) float array, F: (m, 3) integer array, edge-manifold and consistently oriented (as
    :func:`meshsmith.repair.clean` returns it). Returns an :class:`IntersectionFreeMesh` ``(V,
    F, report)``: V (n', 3) float64, F (m', 3) int64 (the kept input faces first, in order, then
    the patches), report an :class:`IntersectionRemoval`. A mesh without self-intersection comes
    back unchanged (its unreferenced vertices removed). Raises InputError for bad input or
    options, and as fill_holes does for a non-manifold or inconsistently oriented mesh;
    Cancelled from ``progress``.
    """
    max_rounds = _arguments.integer(max_rounds, "max_rounds", 1, 1000)
    V1, F1, vertex_map = remove_unreferenced(V, F)
    face_origin = np.arange(len(F1), dtype=np.int64)
    removable = np.ones(len(F1), dtype=bool)
    if faces is not None:
        removable = _arguments.flag_array(faces, "faces")
        if removable.shape != (len(F1),):
            raise InputError(f"faces: a mask of {len(removable)} entries for {len(F1)} faces")

    def chosen_pairs() -> IndexArray:
        found = self_intersections(V1, F1, progress=progress)
        allowed = (face_origin < 0) | removable[np.maximum(face_origin, 0)]
        return found[allowed[found].any(axis=1)] if len(found) else found

    pairs = chosen_pairs()
    initial, rounds, removed, filled, unfilled = len(pairs), 0, 0, 0, 0
    while len(pairs) and rounds < max_rounds and len(F1):
        allowed = (face_origin < 0) | removable[np.maximum(face_origin, 0)]
        cut = np.zeros(len(F1), dtype=bool)
        cut[pairs.ravel()] = True
        cut = _face_rings(F1, cut & allowed, rounds) & allowed
        rounds += 1
        removed += int(cut.sum())
        opened = np.zeros(len(V1), dtype=bool)
        opened[F1[cut].ravel()] = True
        F1, face_origin = F1[~cut], face_origin[~cut]
        if not len(F1):
            break
        loops = topology.boundary_loops(F1)
        chosen = [i for i, loop in enumerate(loops) if opened[loop].any()]
        if chosen:
            n_before, m_before = len(V1), len(F1)
            V1, F1, fills = fill_holes(V1, F1, holes=chosen, refine=refine, fair=fair, progress=progress)
            filled += fills.filled
            unfilled += len(fills.unfilled)
            vertex_map = np.concatenate([vertex_map, np.full(len(V1) - n_before, -1, dtype=np.int64)])
            face_origin = np.concatenate([face_origin, np.full(len(F1) - m_before, -1, dtype=np.int64)])
        V1, F1, used = remove_unreferenced(V1, F1)
        vertex_map = vertex_map[used]
        pairs = chosen_pairs()
    if not len(F1):
        V1, F1, vertex_map = np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    report = IntersectionRemoval(initial_pairs=initial, remaining_pairs=len(pairs) if len(F1) else 0,
                                 rounds=rounds, removed_faces=removed, filled_holes=filled, unfilled_holes=unfilled,
                                 added_faces=int((face_origin < 0).sum()), face_origin=face_origin,
                                 vertex_map=vertex_map)
    return IntersectionFreeMesh(V1, F1, report)
