"""Hole filling (§2.4.1, Liepa 2003): minimal-weight triangulation of each boundary loop by
dynamic programming on a Delaunay search space, refinement to the surrounding density,
bi-Laplacian fairing; binding
cpp/python/repair_holes.cpp, C++ src/repair/fill_holes.cpp."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, NamedTuple, overload

import numpy as np

from .. import _arguments, topology
from .._core import InputError
from .._core import repair as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from .stitching import boundary_sides

__all__ = ["HolePatch", "FillHolesReport", "FilledMesh", "fill_holes"]


@dataclass(frozen=True)
class HolePatch(Unpackable):
    """One filled hole of :func:`fill_holes`; unpacks as ``loop, faces, vertices``.

    loop: the index of the loop in ``report.loops``; faces: (k,) int64 output rows of F that close
    it; vertices: (j,) int64 output rows of V that refinement added; loop_edges: its boundary edges;
    search: "delaunay" when the Delaunay search space held the triangulation, else "exact";
    max_dihedral_angle: the largest angle in degrees between the normals of two faces sharing an
    edge of the patch (its inner edges and the loop's edges, where the patch meets the mesh: 0 is
    flat, near 180 a fold-over); edge_length_ratio: the mean length of the patch's inner edges
    over the mean length of the mesh edges at the loop's vertices (its surrounding ring; the
    refinement aims at 1; with no inner edge, the patch's loop edges are used); islands: the loops
    of islands filled with it as one region (joined to its loop by bridge edges; ``islands=True``
    of :func:`fill_holes`), ascending, empty for a loop filled on its own.
    """

    loop: int
    faces: IndexArray
    vertices: IndexArray
    loop_edges: int
    search: str
    max_dihedral_angle: float
    edge_length_ratio: float
    islands: tuple[int, ...] = ()

    unpacks = ("loop", "faces", "vertices")


@dataclass(frozen=True)
class FillHolesReport(Unpackable):
    """What :func:`fill_holes` did; unpacks as ``patches, unfilled``.

    patches: a :class:`HolePatch` per filled loop (ascending loop index); unfilled: (loop, reason)
    per chosen loop left open; loops: every boundary loop of the input as an ordered (n,) int64
    vertex array (:func:`meshsmith.topology.boundary_loops`'s order, longest first); kept_borders:
    (b,) int64 loops that ``keep_border`` left open; reoriented_components: components the fill
    closed that came out inside out (negative signed volume: the open surface's faces pointed
    inward) and were reversed as a whole, so every closed component faces outward.
    """

    patches: tuple[HolePatch, ...]
    unfilled: tuple[tuple[int, str], ...]
    loops: tuple[IndexArray, ...]
    kept_borders: IndexArray
    reoriented_components: int = 0

    unpacks = ("patches", "unfilled")

    @property
    def filled(self) -> int:
        """The number of holes closed."""
        return len(self.patches)

    def counts(self) -> dict[str, int]:
        """The counts (JSON-ready): loops, filled, unfilled, islands_joined (island loops closed with
        the hole around them, not counted in filled), kept_borders, faces_added, vertices_added,
        reoriented_components."""
        return {"loops": len(self.loops), "filled": self.filled, "unfilled": len(self.unfilled),
                "islands_joined": int(sum(len(p.islands) for p in self.patches)),
                "kept_borders": len(self.kept_borders),
                "faces_added": int(sum(len(p.faces) for p in self.patches)),
                "vertices_added": int(sum(len(p.vertices) for p in self.patches)),
                "reoriented_components": int(self.reoriented_components)}

    def lines(self) -> list[str]:
        """What changed, one line per kind, then one per hole left open."""
        counts = self.counts()
        lines = [f"{counts['filled']:,} of {counts['loops']:,} holes filled "
                 f"({counts['faces_added']:,} faces, {counts['vertices_added']:,} vertices added)"]
        if counts["islands_joined"]:
            lines.append(f"{counts['islands_joined']:,} island loops filled with the hole around them")
        if self.patches:
            worst = max(p.max_dihedral_angle for p in self.patches)
            ratios = [p.edge_length_ratio for p in self.patches]
            lines.append(f"largest dihedral angle in a patch {worst:.1f} degrees; edge length / "
                         f"surrounding ring {min(ratios):.2f} to {max(ratios):.2f}")
        if self.reoriented_components:
            lines.append(f"{self.reoriented_components:,} closed components reversed to face outward "
                         "(their faces pointed inward)")
        if len(self.kept_borders):
            lines.append(f"{len(self.kept_borders):,} borders kept open (loops {self.kept_borders.tolist()})")
        lines += [f"loop {loop} left open: {reason}" for loop, reason in self.unfilled]
        return lines

    def __str__(self) -> str:
        return "\n".join(self.lines())


class FilledMesh(NamedTuple):
    """The result of :func:`fill_holes`: ``V, F, report = fill_holes(V, F)``."""

    V: FloatArray
    F: IndexArray
    report: FillHolesReport


@_arguments.real_options
def fill_holes(V: ArrayLike, F: ArrayLike, *, holes: ArrayLike | None = None, max_hole_edges: int | None = None,
               max_hole_diameter: float | None = None, keep_border: bool = False, search: str = "delaunay",
               refine: bool = True, fair: bool = True, density: float = float(np.sqrt(2.0)),
               islands: bool = True, progress: ProgressCallback = None) -> FilledMesh:
    """Close the holes of a triangle mesh (§2.4.1, Liepa 2003).

    Each chosen boundary loop is closed by the triangulation of its polygon that minimizes, in this
    order, the largest dihedral angle (between the new triangles and with the faces around the
    hole) and the total area, found by dynamic programming. ``search="delaunay"`` (the default)
    looks only at the triangles of the 3D Delaunay triangulation of the loop's vertices (Zou et
    al. 2013, as CGAL): near-linear, so holes of thousands of edges stay fast; where those hold no
    triangulation of the loop the exact search runs instead. ``search="exact"``: every triangle,
    O(n³) time and O(n²) memory (loops up to 2,000 edges). With ``refine``, each patch is then
    refined to the edge density around its hole (Liepa's rule: a triangle is split at its centroid
    while ``density`` times the centroid's distance to each corner exceeds the local edge length,
    √2 by default), with Delaunay edge flips relaxing it after every split. With ``fair`` (and
    ``refine``), the patch's new vertices then move to the solution of the bi-Laplacian equation
    Δ²x = 0 (:func:`meshsmith.smoothing.bilaplacian`) on the patch and the faces around the hole,
    every other vertex held, so the patch continues the surrounding surface with C¹ continuity
    instead of spanning the hole flat. Each step can be switched off.

    Which loops (:func:`meshsmith.topology.boundary_loops`'s order, longest first): every one by
    default, so a scan comes out watertight; ``holes``: only these loop indices;
    ``max_hole_edges``: only loops of at most this many edges; ``max_hole_diameter``: only loops
    whose vertices all lie within this distance of each other; ``keep_border``: leave open, per
    connected component, its longest loop when it is at least twice as long as each other loop of
    the component (or the only one) — the rim of a scan or the outline of an open surface. The
    filters combine.

    Islands: with ``islands`` (the default), a loop of another component that lies inside a
    chosen loop — every vertex inside its polygon projected onto the plane of its Newell normal
    and within half the square root of its projected area of that plane, oriented against it
    (as the rim of a patch floating in the hole, facing the same way, is), and shorter — is
    joined to that loop (the smallest such) by the shortest edge between their vertices, and the
    joined polygon (the loop, the bridge, the island's loop, the bridge back) is triangulated,
    refined and faired as one region: the island ends up connected to the rim and the patch
    runs around it instead of through it (``report.patches[i].islands``; the island's loop is
    not filled on its own, nor counted in ``filled``, nor kept as a border by ``keep_border``). With ``islands=False`` every loop is
    filled on its own, so an island is closed by its own patch and stays apart. A vertex where loops touch (a pinched boundary)
    is handled: no patch face repeats a vertex and no patch adds an edge the mesh already has, so
    a manifold input stays manifold. Every input face and vertex is kept, in order; the new ones
    come after them (``report.patches[i].faces`` / ``.vertices`` are their rows).

    A component that the fill closes is then oriented outward by its signed volume: if the open
    surface's faces pointed inward (so the closed one has negative volume) every face of the
    component, patches included, is reversed (``report.reoriented_components`` counts them); a
    component that stays open, or was closed before, keeps its orientation.

    V: (n, 3) float array, F: (m, 3) integer array, edge-manifold and consistently oriented (as
    :func:`meshsmith.repair.clean` returns it). Returns a :class:`FilledMesh` ``(V, F, report)``
    (float64, int64, :class:`FillHolesReport`). Raises InputError for bad input, an edge with
    more than two faces or two faces in the same direction (naming it), a loop index out of range,
    or a bad option; Cancelled from ``progress``.
    """
    if max_hole_edges is not None:
        max_hole_edges = _arguments.integer(max_hole_edges, "max_hole_edges", 3, 2 ** 31 - 1)
    diameter = 0.0
    if max_hole_diameter is not None:
        diameter = float(max_hole_diameter)
        if not (np.isfinite(diameter) and diameter > 0):
            raise InputError(f"max_hole_diameter = {max_hole_diameter!r}: expected a finite number > 0")
    density = float(density)
    if not (np.isfinite(density) and density > 0):
        raise InputError(f"density = {density!r}: expected a finite number > 0")
    if holes is not None:
        holes = _arguments.index_array(holes, "holes")
    V2, F2, raw = _core.fill_holes(V, F, holes=holes, max_hole_edges=max_hole_edges or 0,
                                   max_hole_diameter=diameter, keep_border=bool(keep_border), search=search,
                                   refine=bool(refine), fair=bool(fair), density=density,
                                   islands=bool(islands), progress=progress)
    patches = tuple(
        HolePatch(loop=loop, faces=np.arange(face_begin, face_begin + faces, dtype=np.int64),
                  vertices=np.arange(vertex_begin, vertex_begin + vertices, dtype=np.int64), loop_edges=loop_edges,
                  search="delaunay" if delaunay else "exact", max_dihedral_angle=float(angle),
                  edge_length_ratio=float(ratio), islands=tuple(int(i) for i in joined))
        for (loop, loop_edges, faces, vertices, delaunay, face_begin, vertex_begin), (angle, ratio), joined
        in zip(raw["patches"].tolist(), raw["measures"].tolist(), raw["islands"]))
    F2, reoriented = _orient_closed_outward(V2, F2, patches)
    report = FillHolesReport(patches=patches, unfilled=tuple((int(l), str(r)) for l, r in raw["unfilled"]),
                             loops=tuple(raw["loops"]), kept_borders=np.asarray(raw["kept_borders"], dtype=np.int64),
                             reoriented_components=reoriented)
    return FilledMesh(V2, F2, report)


@overload
def signed_volumes(V: FloatArray, F: IndexArray, labels: IndexArray, count: int, *,
                   with_areas: Literal[False] = ...) -> FloatArray: ...
@overload
def signed_volumes(V: FloatArray, F: IndexArray, labels: IndexArray, count: int, *,
                   with_areas: Literal[True]) -> tuple[FloatArray, FloatArray]: ...
def signed_volumes(V: FloatArray, F: IndexArray, labels: IndexArray, count: int, *,
                   with_areas: bool = False) -> FloatArray | tuple[FloatArray, FloatArray]:
    """(count,) signed volume of each group of faces (labels (m,) in [0, count)), by the divergence
    theorem about the vertices' centre, in coordinates scaled by a power of two (exact) so that
    neither 1e300 nor 1e-300 coordinates overflow or underflow: only the signs and ratios mean
    something for coordinates that far out (they are exact for coordinates of ordinary size only
    after multiplying by the scale cubed). With ``with_areas`` also each group's area, in the same
    scaled coordinates (so a round-off bound on the volume is a small multiple of area^1.5)."""
    centre = V.mean(axis=0) if len(V) else np.zeros(3)
    span = float(np.abs(V - centre).max()) if len(V) else 0.0
    P = np.ldexp(V - centre, -int(np.frexp(span)[1])) if span > 0 else V - centre
    corners = np.take(P, F, axis=0)        # (m, 3, 3); np.take is ~10x faster than P[F[:, k]] here
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    normal = np.cross(b - a, c - a)        # a · ((b − a) × (c − a)) = a · (b × c): one cross product for both
    volumes = np.asarray(np.bincount(labels, weights=np.einsum("ij,ij->i", a, normal) / 6.0,
                                     minlength=count), dtype=np.float64)
    if not with_areas:
        return volumes
    areas = np.bincount(labels, weights=np.sqrt(np.einsum("ij,ij->i", normal, normal)) / 2.0, minlength=count)
    return volumes, np.asarray(areas, dtype=np.float64)


def _orient_closed_outward(V: FloatArray, F: IndexArray, patches: tuple[HolePatch, ...]) -> tuple[IndexArray, int]:
    """F with each component that holds a patch and is closed (no boundary edge) reversed when its
    signed volume is negative; and the number reversed."""
    if not patches:
        return F, 0
    components = topology.connected_components(F, len(V), connectivity="edge")
    labels, count = components.face_labels, components.count
    patched = np.zeros(count, dtype=bool)
    patched[labels[np.concatenate([p.faces for p in patches])]] = True
    # Negative beyond round-off: a flat, two-sided piece (volume 0) keeps its orientation.
    volumes, areas = signed_volumes(V, F, labels, count, with_areas=True)
    inside_out = patched & (volumes < -1e-9 * areas ** 1.5)
    if not inside_out.any():
        return F, 0
    open_ = np.zeros(count, dtype=bool)           # only now: the boundary search is the costly part
    open_[labels[boundary_sides(F)[:, 0]]] = True
    inside_out &= ~open_
    if not inside_out.any():
        return F, 0
    F = F.copy()
    flip = inside_out[labels]
    F[flip] = F[flip][:, [0, 2, 1]]
    return F, int(inside_out.sum())
