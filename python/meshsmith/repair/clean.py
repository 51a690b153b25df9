"""Cleaning (§2.4): merge close vertices, drop degenerate, duplicate and small pieces, split
non-manifold vertices and edges, orient, drop unreferenced vertices; with a report of every
change and index maps back to the input.

Every step is an existing function (meshsmith.core.mesh_defects, meshsmith.topology's split and
components, this chapter's orient_faces and remove_unreferenced); `clean` runs them in the one
order that lets no step undo another: merging can create degenerate and duplicate faces, removing
faces can create non-manifold vertices (a half-disk fan cut in two), and orientation needs the
manifold mesh.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components as _graph_components

from .. import _arguments, core, topology
from .._core import InputError
from .._results import Unpackable
from .._typing import ArrayLike
from ..points import KdTree
from .degenerate import remove_needles_and_caps
from .orient import orient_faces
from .unreferenced import remove_unreferenced

__all__ = ["CleanReport", "CleanMesh", "clean", "merge_close_vertices"]

#: The counts of a CleanReport with the words `meshsmith clean` prints for them, in pipeline order.
CLEAN_COUNTS = {
    "merged_vertices": "merged vertices",
    "degenerate_faces": "degenerate faces removed (repeated vertex)",
    "zero_area_faces": "zero-area faces removed",
    "duplicate_faces": "duplicate faces removed",
    "non_manifold_vertices": "non-manifold vertices split",
    "non_manifold_edges": "non-manifold edges split",
    "vertex_copies": "vertex copies added by the splits",
    "small_components": "small components removed",
    "small_component_faces": "faces of small components removed",
    "flipped_faces": "faces flipped to orient",
    "non_orientable_components": "non-orientable components (left as they are)",
    "needle_collapses": "needles collapsed (one vertex each)",
    "needle_faces": "faces removed by needle collapses",
    "cap_flips": "caps flipped",
    "unreferenced_vertices": "unreferenced vertices removed",
}


@dataclass(frozen=True)
class CleanReport(Unpackable):
    """What :func:`clean` changed (counts), and where each output element comes from.

    Counts (ints): merged_vertices (input vertices merged into another one), degenerate_faces
    (a repeated vertex index, after merging), zero_area_faces (distinct corners, exactly zero
    area), duplicate_faces (the same vertex set as an earlier face, either orientation; the later
    copies), non_manifold_vertices and non_manifold_edges (found before the split that fixed them),
    vertex_copies (vertices the split added), small_components and small_component_faces,
    flipped_faces, non_orientable_components (could not be oriented consistently; left as the
    walk made them), needle_collapses, needle_faces and cap_flips (with ``needles_and_caps``:
    see :func:`meshsmith.repair.remove_needles_and_caps`), unreferenced_vertices (used by no
    input face, or by none once faces were removed). So ``len(V_out) == len(V_in) -
    merged_vertices - unreferenced_vertices + vertex_copies - needle_collapses`` and
    ``len(F_out) == len(F_in) - degenerate_faces - zero_area_faces - duplicate_faces -
    small_component_faces - needle_faces``.

    Maps: vertex_map (n_out,) int64, the input vertex of each output vertex (the
    representative of a merged group: its lowest index; for a split copy: the vertex it copies),
    so ``V_out == V_in[vertex_map]``; face_map (m_out,) int64, the input face of each output
    face (whose corners changed where a needle collapse or a cap flip passed); flipped (k,) int64, the output faces that are reversed relative to their input face.
    """

    merged_vertices: int
    degenerate_faces: int
    zero_area_faces: int
    duplicate_faces: int
    non_manifold_vertices: int
    non_manifold_edges: int
    vertex_copies: int
    small_components: int
    small_component_faces: int
    flipped_faces: int
    non_orientable_components: int
    needle_collapses: int
    needle_faces: int
    cap_flips: int
    unreferenced_vertices: int
    vertex_map: np.ndarray
    face_map: np.ndarray
    flipped: np.ndarray

    def counts(self) -> dict[str, int]:
        """Every count, by field name, in pipeline order (JSON-ready)."""
        return {name: int(getattr(self, name)) for name in CLEAN_COUNTS}

    @property
    def changed(self) -> bool:
        """True when clean changed anything (a non-orientable component alone changes nothing)."""
        return any(value for name, value in self.counts().items() if name != "non_orientable_components")

    def lines(self, all_kinds: bool = False) -> list[str]:
        """One line per kind of change ("3 merged vertices"); only the non-zero ones unless
        `all_kinds`."""
        return [f"{value:,} {CLEAN_COUNTS[name]}" for name, value in self.counts().items()
                if value or all_kinds]

    def __str__(self) -> str:
        return "\n".join(self.lines()) or "nothing to change"


class CleanMesh(NamedTuple):
    """The result of :func:`clean`: ``V, F, report = clean(V, F)``."""

    V: np.ndarray
    F: np.ndarray
    report: CleanReport


def merge_close_vertices(V: ArrayLike, *, tolerance: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Groups of vertices closer than or at `tolerance`, joined transitively.

    V: (n, 3) float array; tolerance >= 0 (0: exactly equal positions; -0.0 equals 0.0).
    Exact duplicates are grouped first by sorting, then the distinct positions by a kd-tree radius
    search and union-find, so a chain of points each within `tolerance` of the next is one group
    (two output vertices are then always farther apart than `tolerance`).
    Time O(n log n + p), p the number of pairs of distinct positions within `tolerance` (so any
    number of exactly coincident points is cheap, while a tolerance far above the spacing of a
    dense cloud makes p, and the time, grow with the square of the cloud's size).
    Returns (group (n,) int64, representatives (g,) int64): group[i] is the group of vertex i,
    groups are numbered in the order of their representative, the lowest vertex index in each.
    Raises InputError for a negative or non-finite tolerance, or bad V.
    """
    tolerance = _arguments.real(tolerance, "tolerance")
    if not (np.isfinite(tolerance) and tolerance >= 0):
        raise InputError(f"merge tolerance must be a finite number >= 0, got {tolerance!r}")
    P = _arguments.finite(_arguments.real_array(V, "V", 3), "V")
    if not len(P):
        raise InputError("V is empty: expected a non-empty (n, 3) array")
    _, first, exact = np.unique(P + 0.0, axis=0, return_index=True, return_inverse=True)
    exact = exact.reshape(-1)
    label: np.ndarray = np.arange(len(first))
    if tolerance > 0 and len(first) > 1:
        distinct = P[first]
        offsets, neighbours, _ = KdTree(distinct).query_radius(distinct, np.nextafter(tolerance, np.inf))
        rows = np.repeat(np.arange(len(distinct)), np.diff(offsets))
        graph = coo_matrix((np.ones(len(rows), dtype=np.int8), (rows, neighbours)),
                           shape=(len(distinct), len(distinct)))
        _, label = _graph_components(graph, directed=False)
    cluster = label[exact]                       # a group id per vertex, in no particular order
    representative = np.full(cluster.max() + 1, len(P), dtype=np.int64)
    np.minimum.at(representative, cluster, np.arange(len(P)))
    order = np.argsort(representative, kind="stable")
    renumber = np.empty_like(order)
    renumber[order] = np.arange(len(order))
    return renumber[cluster].astype(np.int64), representative[order]


def clean(V: ArrayLike, F: ArrayLike, *, merge_tolerance: float | None = 0.0, remove_degenerate: bool = True,
          split_non_manifold: bool = True, orient: bool = True, min_component_faces: int = 0,
          needles_and_caps: bool = False) -> CleanMesh:
    """Clean a triangle mesh and say exactly what changed (§2.4).

    In this order, each step optional:
    1. merge vertices at distance <= `merge_tolerance` (0, the default: exactly coincident ones;
       None: no merging), transitively (:func:`merge_close_vertices`);
    2. `remove_degenerate`: remove faces with a repeated vertex, faces of exactly zero area and
       duplicate faces (same vertex set as an earlier face, either orientation: the later copy),
       as :func:`meshsmith.core.mesh_defects` finds them;
    3. `split_non_manifold`: give each vertex one copy per fan of faces
       (:func:`meshsmith.topology.split_non_manifold_vertices`), which separates pinches and the
       faces around non-manifold edges without moving a point;
    4. `min_component_faces`: remove the connected components with fewer faces;
    5. `orient`: orient each component consistently, closed ones outward (:func:`orient_faces`);
    6. `needles_and_caps` (off by default): collapse needles and flip caps with the defaults of
       :func:`meshsmith.repair.remove_needles_and_caps` (topology kept; skipped when a component
       is non-orientable or orientation is off);
    7. remove the vertices no face uses (always; unreferenced vertices of the input included).
    With the default options the output is manifold, without degenerate, duplicate or
    unreferenced elements, consistently oriented and closed components have positive volume
    (except non-orientable components, counted in the report). Removing a zero-area face
    opens a slit where it was (filling it is the hole-filling step's work).

    V: (n, 3) float array, F: (m, 3) integer array. Returns a :class:`CleanMesh` ``(V, F,
    report)``: V (n', 3) float64, F (m', 3) int64 (faces in input order), report a
    :class:`CleanReport` with the counts and the maps back to the input. If every face is
    removed, V and F are empty. Raises InputError for bad input or options.
    """
    min_component_faces = _arguments.integer(min_component_faces, "min_component_faces", 0, 2 ** 63 - 1)
    counts = dict.fromkeys(CLEAN_COUNTS, 0)
    V1, F1, vertex_map = remove_unreferenced(V, F)
    counts["unreferenced_vertices"] = len(np.asarray(V)) - len(V1)
    face_map = np.arange(len(F1), dtype=np.int64)

    if merge_tolerance is not None:
        merge_tolerance = _arguments.real(merge_tolerance, "merge_tolerance")
        group, representatives = merge_close_vertices(V1, tolerance=merge_tolerance)
        if len(representatives) < len(V1):
            counts["merged_vertices"] = len(V1) - len(representatives)
            V1, F1, vertex_map = V1[representatives], group[F1], vertex_map[representatives]

    if remove_degenerate:
        defects = core.mesh_defects(V1, F1)
        degenerate = set(defects.degenerate_faces.tolist())
        zero_area = set(defects.zero_area_faces.tolist()) - degenerate
        duplicate = set(defects.duplicate_faces.tolist()) - degenerate - zero_area
        counts.update(degenerate_faces=len(degenerate), zero_area_faces=len(zero_area),
                      duplicate_faces=len(duplicate))
        if degenerate or zero_area or duplicate:
            keep = np.ones(len(F1), dtype=bool)
            keep[list(degenerate | zero_area | duplicate)] = False
            F1, face_map = F1[keep], face_map[keep]

    if split_non_manifold and len(F1):
        pinched = topology.non_manifold_vertices(F1)
        if len(pinched):
            counts["non_manifold_vertices"] = len(pinched)
            counts["non_manifold_edges"] = len(topology.non_manifold_edges(F1))
            V1, F1, origin = topology.split_non_manifold_vertices(V1, F1)
            counts["vertex_copies"] = len(V1) - len(vertex_map)
            vertex_map = vertex_map[origin]

    if min_component_faces > 0 and len(F1):
        labels = topology.connected_components(F1, len(V1)).face_labels
        sizes = np.bincount(labels)
        small = sizes < min_component_faces
        if small.any():
            counts["small_components"] = int(small.sum())
            counts["small_component_faces"] = int(sizes[small].sum())
            keep = ~small[labels]
            F1, face_map = F1[keep], face_map[keep]

    flipped = np.zeros(0, dtype=np.int64)
    if orient and len(F1):
        oriented = orient_faces(V1, F1)
        F1, flipped = oriented.F, oriented.flipped
        counts["flipped_faces"] = len(flipped)
        counts["non_orientable_components"] = oriented.non_orientable_components

    if needles_and_caps and orient and len(F1) and not counts["non_orientable_components"]:
        fixed = remove_needles_and_caps(V1, F1)
        if fixed.collapses or fixed.flips:
            counts.update(needle_collapses=fixed.collapses, needle_faces=len(F1) - len(fixed.F), cap_flips=fixed.flips)
            was_flipped = np.zeros(len(F1), dtype=bool)
            was_flipped[flipped] = True
            flipped = np.flatnonzero(was_flipped[fixed.face_map]).astype(np.int64)
            V1, F1, vertex_map, face_map = fixed.V, fixed.F, vertex_map[fixed.vertex_map], face_map[fixed.face_map]

    if len(F1):
        V1, F1, used = remove_unreferenced(V1, F1)
    else:
        V1, F1, used = np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    counts["unreferenced_vertices"] += len(vertex_map) - len(used)
    vertex_map = vertex_map[used]
    report = CleanReport(**counts, vertex_map=vertex_map, face_map=face_map, flipped=flipped)
    return CleanMesh(V1, F1, report)

