"""Decimation chapter (curriculum §4.1–4.3): vertex clustering, incremental decimation by error
quadrics, and progressive meshes.

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3); results come back as float64 and
int64 arrays. Bad input raises :class:`meshsmith.InputError`.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._core import InputError
from ._core import decimation as _core

__all__: list[str] = []

# ---------------------------------------------------------------------------------------------
# Vertex clustering (§4.1)
# ---------------------------------------------------------------------------------------------

__all__ += ["ClusteredMesh", "cluster"]

CLUSTER_REPRESENTATIVES = ("center", "centroid", "median", "quadric")


class ClusteredMesh(NamedTuple):
    """Result of :func:`cluster`.

    V: (k, 3) float64 representatives; F: (l, 3) int64 surviving triangles; vertex_cluster: (n,)
    int64, the output vertex of each input vertex (-1: unreferenced, or its cell lost all its
    triangles); is_manifold: whether F is manifold (clustering does not guarantee it);
    cell_size: the edge length of the grid cells used.
    """
    V: np.ndarray
    F: np.ndarray
    vertex_cluster: np.ndarray
    is_manifold: bool
    cell_size: float


def cluster(V, F, *, cell_size: float | None = None, target_vertices: int | None = None,
            representative: str = "quadric", progress=None) -> ClusteredMesh:
    """Decimate by vertex clustering on a uniform grid (§4.1; Rossignac & Borrel 1993).

    Every referenced vertex falls into a cube of edge ``cell_size`` (the grid starts at the
    minimum corner of the vertices); each occupied cell becomes one vertex; a triangle survives
    iff its corners lie in three different cells; duplicate triangles (same three cells) are
    kept once. Fast, but the result need not be manifold: check ``is_manifold``.

    V: (n, 3) float array, F: (m, 3) integer array. Give exactly one of
    cell_size: the cells' edge length (> 0), or
    target_vertices: the wanted number of occupied cells; the cell size is found by bisection
    (the output can have a few vertices less: cells whose triangles all vanish are dropped).
    representative: where a cell's vertex goes: "center" (of the cell), "centroid" (mean of its
    vertices), "median" (per-coordinate median, as ``np.median``) or "quadric" (default: the
    minimiser of the squared distances to the planes of the triangles at its vertices, through
    the pseudo-inverse of §4.1.1, so flat cells stay at their centroid and feature corners are
    kept; the centroid if the minimiser falls outside the cell).
    progress: optional ``(fraction, stage) -> bool`` callback.

    Returns a :class:`ClusteredMesh`. Raises InputError for bad input, when both or neither of
    cell_size and target_vertices are given, for a cell size that is not positive or so small
    that an axis needs 2**21 cells or more, or an unknown representative.
    """
    if (cell_size is None) == (target_vertices is None):
        raise InputError("cluster: give exactly one of cell_size and target_vertices")
    if target_vertices is not None:
        if isinstance(target_vertices, bool) or not isinstance(target_vertices, (int, np.integer)):
            raise InputError(f"cluster: target_vertices must be an integer, got {target_vertices!r}")
        cell_size = _core.cell_size_for_vertex_count(V, F, int(target_vertices))
    V_out, F_out, vertex_cluster, is_manifold, size = _core.cluster_vertices(
        V, F, float(cell_size), representative, progress)
    return ClusteredMesh(V_out, F_out, vertex_cluster.reshape(-1), bool(is_manifold), float(size))



# ---------------------------------------------------------------------------------------------
# Incremental decimation with error quadrics (§4.2)
# ---------------------------------------------------------------------------------------------

from dataclasses import dataclass  # noqa: E402  (kept in this section: the sections are edited apart)

__all__ += ["decimate", "DecimationReport"]


@dataclass
class DecimationReport:
    """What :func:`decimate` did (``return_report=True``).

    vertex_origin: (n',) int64, the input vertex each output vertex was (output vertices are
    input vertices that survived, possibly moved). max_error: the largest cost of a performed
    collapse (for ``cost="quadric"`` in length² units: a sum of squared distances to the planes of
    the merged input faces, each weighted by its area over the mean face area). target_reached:
    whether ``target_faces`` was reached (False when ``max_error`` stopped it first or no further
    collapse was admissible). collapse_count: collapses performed. split_vertex_origin: empty, or
    when the input had non-manifold or inconsistently oriented vertices, the input vertex of each
    working vertex (the input's followed by the copies made to split them). collapses: with
    ``record_collapses=True``, the collapses in order as arrays ``removed, kept, left, right``
    (k,) int64 (−1 where a side is boundary; indices of working vertices) and
    ``removed_position, kept_position_before, kept_position_after`` (k, 3) float64 — the vertex
    splits of a progressive mesh read backwards (§4.3); else None.
    """

    vertex_origin: np.ndarray
    max_error: float
    target_reached: bool
    collapse_count: int
    split_vertex_origin: np.ndarray
    collapses: dict | None = None


def decimate(V, F, *, target_faces=None, ratio=None, max_error=None, operator="edge",
             cost="quadric", candidates=None, prevent_normal_flips=True,
             max_normal_deviation=None, min_quality=None, max_valence=None, keep_boundary=True,
             seed=0, record_collapses=False, return_report=False, parallel=True, progress=None):
    """Decimate a triangle mesh by greedy edge collapses ordered by error quadrics (§4.2).

    V: (n, 3) float array of vertex positions. F: (m, 3) int array of triangles.
    Stop rules (at least one): ``target_faces`` (int >= 1) or ``ratio`` (in (0, 1]: target
    ``round(ratio·m)`` faces, at least 1), not both; ``max_error`` (> 0, units of the cost: for
    the quadric, length², see :class:`DecimationReport`) stops when the cheapest collapse costs
    more. operator: ``"edge"`` (merged vertex at the quadric's optimal point, pseudo-inverse when
    singular) or ``"halfedge"`` (merged into one endpoint, positions are a subset of the input).
    cost: ``"quadric"`` (Garland–Heckbert), ``"plane_distance"`` (distance to the least-squares
    plane of the two one-rings) or ``"volume_change"`` (|swept volume|). candidates: k >= 1 for
    multiple-choice decimation (best of k random edges per step, Wu & Kobbelt), None for the full
    priority queue; seed: its random stream.
    Fairness criteria (§4.2.3): prevent_normal_flips (default True); max_normal_deviation
    (degrees a face normal may turn per collapse); min_quality (reject collapses that make a
    face's 4√3·area/Σedge² lower than this and lower than before); max_valence; keep_boundary
    (boundary vertices only slide along the boundary; default True). The link condition always
    holds: a manifold mesh stays manifold with the same Euler characteristic.
    parallel: on meshes of 100,000 faces or more (quadric cost, full queue), the first 95% of the
    collapses, down to no fewer than 20,000 faces, run on four spatial parts at once, in rounds
    under a common cost ceiling, and a serial greedy run does the part borders and the rest
    (1.3–1.4× faster on 2 cores at 1.3M faces; the result does not depend on the thread
    count). False: one serial greedy run, the strict cheapest-first order.
    Faces with a repeated index are dropped; non-manifold or inconsistently oriented vertices
    are split into one copy per fan first (nothing is torn further). Unreferenced vertices are
    dropped. progress: optional callable ``(fraction, stage) -> bool | None``; returning False
    raises :class:`meshsmith.Cancelled`.

    Returns (V', F'): (n', 3) float64 and (m', 3) int64; with ``return_report=True``
    (V', F', :class:`DecimationReport`).
    Raises InputError for bad input or an impossible request (no stop rule, target 0, ratio
    outside (0, 1], both target_faces and ratio, an unknown operator or cost, a negative option,
    no face without a repeated index).
    """
    if target_faces is not None and ratio is not None:
        raise InputError("decimate: give target_faces or ratio, not both")
    target = 0
    if ratio is not None:
        if not 0 < ratio <= 1:
            raise InputError(f"decimate: ratio must be in (0, 1], got {ratio}")
        target = max(1, int(round(ratio * len(np.asarray(F)))))
    elif target_faces is not None:
        if int(target_faces) != target_faces or target_faces < 1:
            raise InputError(f"decimate: target_faces must be an integer >= 1, got {target_faces}")
        target = int(target_faces)
    if max_error is not None and not max_error > 0:
        raise InputError(f"decimate: max_error must be > 0, got {max_error}")
    if target == 0 and max_error is None:
        raise InputError("decimate: no stop rule: give target_faces, ratio or max_error")
    if candidates is not None and candidates < 1:
        raise InputError(f"decimate: candidates must be >= 1 (None: full priority queue), got {candidates}")
    V2, F2, report = _core.decimate_qem(
        V, F, target_faces=target, max_error=max_error or 0.0, operator=operator, cost=cost,
        candidates=candidates or 0, seed=seed, prevent_normal_flips=prevent_normal_flips,
        max_normal_deviation_deg=max_normal_deviation or 0.0, min_triangle_quality=min_quality or 0.0,
        max_valence=max_valence or 0, keep_boundary=keep_boundary,
        record_collapses=record_collapses, parallel=parallel, progress=progress)
    if not return_report:
        return V2, F2
    return V2, F2, DecimationReport(
        vertex_origin=report["vertex_origin"], max_error=report["max_error"],
        target_reached=report["target_reached"], collapse_count=report["collapse_count"],
        split_vertex_origin=report["split_vertex_origin"], collapses=report.get("collapses"))



# ---------------------------------------------------------------------------------------------
# Progressive meshes (§4.3)
# ---------------------------------------------------------------------------------------------

import os  # noqa: E402  (kept in this section: the sections are edited apart)

__all__ += ["ProgressiveMesh", "progressive_mesh"]


class ProgressiveMesh:
    """A progressive mesh (§4.3; Hoppe 1996): a coarse base mesh and the vertex splits that undo,
    in reverse, the collapses of :func:`decimate`.

    Levels: ``level`` k is the mesh after k vertex splits; 0 is the base mesh, ``n_splits`` the
    full mesh, which reproduces the input (positions bit for bit, faces up to order and
    rotation). Every level is a valid manifold mesh. The current level moves incrementally
    (:meth:`set_level`, :meth:`refine`, :meth:`coarsen`, :meth:`at`): the cost is proportional to
    the number of splits between the two levels, not to the mesh size. Meshes come back as
    (V (k, 3) float64, F (l, 3) int64) with their vertices in the order of the input mesh.
    Build one with :func:`progressive_mesh`, or read one with :meth:`ProgressiveMesh.load`.
    """

    def __init__(self, core_mesh):
        self._pm = core_mesh

    @classmethod
    def load(cls, path) -> "ProgressiveMesh":
        """Read a file written by :meth:`save` (at its full level).

        Raises InputError for a missing, foreign, newer, truncated or corrupt file (every count
        is checked against the file size, every vertex split is replayed and checked).
        """
        return cls(_core.load_progressive_mesh(os.fspath(path)))

    def save(self, path) -> None:
        """Write the mesh in transmission order (§4.3): a header (magic ``MSPM``, format
        version, counts), the base mesh, then the vertex splits coarse to fine. Little-endian
        binary, 64 bytes per split. Raises InputError if the file cannot be written."""
        self._pm.save(os.fspath(path))

    @property
    def n_splits(self) -> int:
        """Number of vertex splits: the levels are 0 .. n_splits."""
        return self._pm.split_count

    @property
    def level(self) -> int:
        """The current level (vertex splits applied)."""
        return self._pm.level

    @property
    def n_faces(self) -> int:
        """Faces at the current level."""
        return self._pm.face_count(self._pm.level)

    @property
    def face_range(self) -> tuple[int, int]:
        """(faces of the base mesh, faces of the full mesh)."""
        return self._pm.face_count(0), self._pm.face_count(self._pm.split_count)

    def face_count(self, level: int) -> int:
        """Faces at ``level`` (each split adds two faces, one on the boundary)."""
        self._check_level(level)
        return self._pm.face_count(level)

    def _check_level(self, level) -> int:
        if isinstance(level, bool) or not isinstance(level, (int, np.integer)) \
                or not 0 <= level <= self.n_splits:
            raise InputError(f"progressive mesh: level must be an integer in [0, {self.n_splits}], got {level!r}")
        return int(level)

    def set_level(self, level: int) -> None:
        """Move the current level to ``level`` by applying or undoing the vertex splits in
        between. Raises InputError if level is outside [0, n_splits]."""
        self._pm.set_level(self._check_level(level))

    def refine(self, steps: int = 1) -> int:
        """Apply the next ``steps`` vertex splits (fewer at the full level); returns the level."""
        self._pm.set_level(min(self.n_splits, self.level + max(0, int(steps))))
        return self.level

    def coarsen(self, steps: int = 1) -> int:
        """Undo the last ``steps`` vertex splits (fewer at the base level); returns the level."""
        self._pm.set_level(max(0, self.level - max(0, int(steps))))
        return self.level

    def mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """(V, F) at the current level."""
        return self._pm.current_mesh()

    def level_for_face_count(self, n_faces: int) -> int:
        """The finest level with at most ``n_faces`` faces.

        Raises InputError if n_faces is not an integer inside :attr:`face_range`."""
        if isinstance(n_faces, bool) or not isinstance(n_faces, (int, np.integer)):
            raise InputError(f"progressive mesh: n_faces must be an integer, got {n_faces!r}")
        return self._pm.level_for_face_count(int(n_faces))

    def at(self, n_faces: int) -> tuple[np.ndarray, np.ndarray]:
        """Move to the finest level with at most ``n_faces`` faces and return its (V, F).

        Raises InputError as :meth:`level_for_face_count`."""
        self._pm.set_level(self.level_for_face_count(n_faces))
        return self._pm.current_mesh()

    def refine_where(self, predicate=None, *, near=None, radius=None, box=None,
                     whole_stars: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Selective refinement (§4.3): full detail where asked, the base mesh elsewhere.

        The region is given by exactly one of
        predicate: a vectorized callable, (n, 3) float array of vertex positions (those of the
        full mesh, i.e. the input) -> (n,) bool;
        near, radius: the vertices within ``radius`` of the point ``near``;
        box: ((xmin, ymin, zmin), (xmax, ymax, zmax)), the vertices inside the box.
        Every vertex split that involves a selected vertex is applied, together with the
        splits it depends on. By default these follow the legality test of §4.3 (Hoppe 1997): a
        split needs its vertex v_s active and the faces beside its edges to v_l and v_r present;
        v_l and v_r are the fundamental cut vertices, found as whatever vertices sit at their
        place, so few splits are forced. ``whole_stars=True`` forces instead the splits that
        created every vertex and face around the split edge (each split then meets exactly its
        recorded neighbourhood; more refinement around the region); it is also the fallback
        should a legal split ever fail the manifold check. Either way the result is a valid
        manifold mesh and every selected vertex is present at its input position.
        Independent of (and not changing) the current level. Returns (V, F).
        Raises InputError for a bad region or a predicate that does not return (n,) booleans.
        """
        given = sum(x is not None for x in (predicate, near, box))
        if given != 1 or (near is None) != (radius is None):
            raise InputError("refine_where: give exactly one of predicate, near with radius, or box")
        P = self._pm.full_positions
        if predicate is not None:
            selected = np.asarray(predicate(P))
            if selected.shape != (len(P),) or selected.dtype != bool:
                raise InputError(f"refine_where: the predicate must return a ({len(P)},) bool array, "
                                 f"got {selected.dtype} {selected.shape}")
        elif near is not None:
            point = np.asarray(near, dtype=float)
            if point.shape != (3,) or not np.isfinite(point).all() or not radius >= 0:
                raise InputError("refine_where: near must be a finite 3D point and radius >= 0")
            selected = np.linalg.norm(P - point, axis=1) <= radius
        else:
            bounds = np.asarray(box, dtype=float)
            if bounds.shape != (2, 3) or np.isnan(bounds).any():
                raise InputError("refine_where: box must be ((xmin, ymin, zmin), (xmax, ymax, zmax))")
            selected = np.all((P >= bounds[0]) & (P <= bounds[1]), axis=1)
        return self._pm.selective_refinement(selected, bool(whole_stars))

    def __repr__(self) -> str:
        low, high = self.face_range
        return (f"ProgressiveMesh({self.n_splits} vertex splits, {low}..{high} faces, "
                f"level {self.level}: {self.n_faces} faces)")


def progressive_mesh(V, F, **decimate_options) -> ProgressiveMesh:
    """The progressive mesh of (V, F) (§4.3): :func:`decimate` with ``decimate_options`` (its
    stop rules and fairness criteria; without a stop rule, down to the smallest mesh the
    decimator reaches) records its collapses, stored as vertex splits
    (v_s, v_l, v_r -> position, plus v_s's position before the split: the offset of a
    full-edge collapse). Returned at its full level.

    V: (n, 3) float array, F: (m, 3) integer array, manifold and consistently oriented, without
    faces that repeat a vertex (the full level must reproduce the input).
    Raises InputError for bad input or options (as :func:`decimate`), or when the input is not
    manifold or not oriented.
    """
    options = dict(decimate_options)
    if all(options.get(key) is None for key in ("target_faces", "ratio", "max_error")):
        options["target_faces"] = 1
    for key in ("record_collapses", "return_report"):
        if key in options:
            raise InputError(f"progressive_mesh: {key} is set by progressive_mesh itself")
    _, _, report = decimate(V, F, record_collapses=True, return_report=True, **options)
    if report.split_vertex_origin.size:
        raise InputError("progressive_mesh: the input is not manifold or not consistently oriented (the decimator "
                         "had to split vertices); run topology.split_non_manifold_vertices or repair first")
    c = report.collapses
    vertices = np.column_stack([c["removed"], c["kept"], c["left"], c["right"]]) if len(c["removed"]) \
        else np.zeros((0, 4), dtype=np.int64)
    return ProgressiveMesh(_core.progressive_mesh_from_collapses(
        V, F, vertices, c["removed_position"].reshape(-1, 3), c["kept_position_before"].reshape(-1, 3),
        c["kept_position_after"].reshape(-1, 3)))
