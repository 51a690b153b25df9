"""Topology chapter (§2, mesh definitions: the manifold conditions, Euler's formula): edges,
boundary loops, components, Euler characteristic, genus, manifoldness and orientation, and the
split that makes a non-manifold mesh manifold.

Definitions (the same in every function; see cpp/include/meshsmith/topology/manifold.h):

- An *edge* is an unordered pair of vertices joined by a side of some face; sides that join a
  vertex to itself (faces with a repeated index) are ignored.
- A *non-manifold edge* has more than two incident faces.
- The *fans* of a vertex are the groups of its faces that are connected through edges at the
  vertex with exactly two faces. A *non-manifold vertex* has more than one fan (a pinch) or is an
  end of a non-manifold edge. Unreferenced vertices are not non-manifold.
- A mesh is *manifold* when it has no non-manifold edge and no non-manifold vertex, and
  *oriented* when each edge with two faces is used once in each direction.
- Components are *vertex-connected* unless asked otherwise: faces sharing only a vertex are in
  the same component (``connected_components(..., connectivity="edge")`` separates them).

Functions that take only ``F`` infer the vertex count as ``F.max() + 1`` (and reject a largest
index of 3·m + 2^20 or more, m faces, rather than allocate for mostly unreferenced vertices). All
inputs are checked by the C++ core; bad input raises :class:`meshsmith.InputError`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal, NamedTuple, overload

import numpy as np

from . import _arguments
from ._core import core as _core
from ._core import geometry as _geometry
from ._core import topology as _topology
from ._deprecation import positional_options
from ._results import Unpackable
from ._typing import ArrayLike, FloatArray, IndexArray

if TYPE_CHECKING:
    from .io import Polygons

__all__ = [
    "edges", "boundary_loops", "connected_components", "ConnectedComponents",
    "euler_characteristic", "genus", "non_manifold_edges", "non_manifold_vertices",
    "is_manifold", "is_oriented", "split_non_manifold_vertices", "SplitMesh", "info", "MeshInfo",
]


def edges(F: ArrayLike) -> IndexArray:
    """Unique undirected edges of a triangle mesh.

    F: (m, 3) integer array of triangles. Returns an (e, 2) int64 array of edges ``(i, j)`` with
    ``i < j``, sorted lexicographically (the same set as ``igl.edges``).
    Raises InputError if F is empty, not (m, 3) integers, or has a negative index.
    """
    return _topology.edges(F)


def boundary_loops(F: ArrayLike) -> list[IndexArray]:
    """All boundary loops, longest first (ties: smaller first vertex first).

    F: (m, 3) integer array of triangles. Returns a list of int64 arrays of vertex indices. Each
    loop starts at its smallest vertex and follows the faces' orientation, as ``igl.boundary_loop``
    does (for an outward-oriented mesh: clockwise around the hole seen from outside); the first
    vertex is not repeated at the end. A closed mesh gives ``[]``.
    Raises InputError as :func:`edges`.
    """
    return list(_topology.boundary_loops(F))


@dataclass(frozen=True)
class ConnectedComponents(Unpackable):
    """Connected components of a mesh, numbered in the order of their first face.

    Unpacks as ``count, face_labels, vertex_labels``.
    """

    count: int                  # number of components
    face_labels: IndexArray     # (m,) int64, component of each face
    vertex_labels: IndexArray   # (n,) int64, component of each vertex, -1 if no face uses it


@positional_options("connectivity")
def connected_components(F: ArrayLike, n_vertices: int | None = None, *,
                         connectivity: str = "vertex") -> ConnectedComponents:
    """Connected components of a mesh.

    F: (m, 3) integer array of triangles. n_vertices: number of vertices n (default
    ``F.max() + 1``); pass ``len(V)`` to get a label (-1) for trailing unreferenced vertices.
    connectivity: ``"vertex"`` (default, as ``igl.vertex_components`` and most tools): faces
    sharing a vertex are connected, so two cubes touching at a corner are one component;
    ``"edge"`` (as ``igl.facet_components``): only faces sharing an edge are, and a vertex in
    several components is labelled with the component of its lowest-numbered face.
    Face 0 is always in component 0. Raises InputError for bad F, an index >= n_vertices or an
    unknown connectivity.
    """
    count, face_labels, vertex_labels = _topology.connected_components(F, n_vertices, connectivity)
    return ConnectedComponents(int(count), face_labels, vertex_labels)


def euler_characteristic(V_or_F: ArrayLike, F: ArrayLike | None = None) -> int:
    """Euler characteristic χ = V − E + F, V counting only the vertices some face uses.

    Call as ``euler_characteristic(F)`` or ``euler_characteristic(V, F)`` (V is then validated but
    does not change the result, since unreferenced vertices are not counted).
    Raises InputError for bad input.
    """
    if F is None:
        return int(_topology.euler_characteristic(V_or_F))
    _core.validate_mesh(V_or_F, F)
    return int(_topology.euler_characteristic(F))


@overload
def genus(F: ArrayLike, *, per_component: Literal[False] = ...) -> int: ...
@overload
def genus(F: ArrayLike, *, per_component: Literal[True]) -> IndexArray: ...
@overload
def genus(F: ArrayLike, *, per_component: bool) -> int | IndexArray: ...
@positional_options("per_component")
def genus(F: ArrayLike, *, per_component: bool = False) -> int | IndexArray:
    """Genus of an orientable manifold mesh, from χ = 2 − 2g − b per connected component.

    F: (m, 3) integer array of triangles. Returns the sum of the components' genera (the genus of
    their connected sum) as an int, or with ``per_component=True`` an int64 array with the genus
    of each component (numbered as :func:`connected_components`). b counts boundary loops, so a
    disk and a sphere both have genus 0, a torus 1.
    Raises InputError if the mesh is not manifold (naming an offending edge or vertex) or a
    component is not orientable (a Möbius strip), and for bad input.
    """
    genera = _topology.genus_per_component(F)
    return genera if per_component else int(genera.sum())


def non_manifold_edges(F: ArrayLike) -> IndexArray:
    """Edges with more than two incident faces, as an (k, 2) int64 array (i < j, sorted)."""
    return _topology.non_manifold_edges(F)


def non_manifold_vertices(F: ArrayLike) -> IndexArray:
    """Non-manifold vertices (more than one fan of faces, or on a non-manifold edge), ascending.

    F: (m, 3) integer array. Returns a (k,) int64 array. Raises InputError for bad F.
    """
    return _topology.non_manifold_vertices(F)


def is_manifold(F: ArrayLike) -> bool:
    """True when F has no non-manifold edge and no non-manifold vertex."""
    return bool(_topology.is_manifold(F))


def is_oriented(F: ArrayLike) -> bool:
    """True when every edge with exactly two faces is used once in each direction.

    Boundary and non-manifold edges are not considered.
    """
    return bool(_topology.is_oriented(F))


class SplitMesh(NamedTuple):
    """Result of :func:`split_non_manifold_vertices`; unpacks as ``V2, F2, origin``."""

    V: FloatArray          #: (n2, 3) positions, V2 == V[origin]
    F: IndexArray          #: (m, 3) faces on the split vertices
    vertex_origin: IndexArray  #: (n2,) the input vertex of each output vertex


def split_non_manifold_vertices(V: ArrayLike, F: ArrayLike) -> SplitMesh:
    """Make a mesh manifold by duplicating vertices, without moving any point.

    Each vertex gets one copy per fan of faces around it, so pinch vertices come apart; since
    fans never continue across a non-manifold edge, the faces around a non-manifold edge are
    detached too, and the result :func:`is_manifold`. Vertex i < len(V) keeps its index (its first
    fan keeps it), extra copies are appended; faces keep their order; unreferenced vertices stay.

    V: (n, 3) float array, F: (m, 3) integer array. Returns a :class:`SplitMesh`
    ``(V2, F2, origin)``: V2 (n2, 3)
    float64 with ``V2 == V[origin]``, F2 (m, 3) int64, origin (n2,) int64.
    Raises InputError for bad input.
    """
    return SplitMesh(*_topology.split_non_manifold_vertices(V, F))


@dataclass(frozen=True)
class MeshInfo(Unpackable):
    """Summary of a mesh, as printed by ``meshsmith info``; unpacks in field order."""

    n_vertices: int
    n_faces: int
    n_edges: int
    n_components: int
    n_boundary_loops: int
    n_boundary_edges: int
    euler_characteristic: int
    genus: int | None               # sum over components; None if non-manifold or non-orientable
    is_manifold: bool
    is_oriented: bool
    n_non_manifold_edges: int
    n_non_manifold_vertices: int
    n_unreferenced_vertices: int
    bounding_box: tuple[FloatArray, FloatArray]  # (min, max), each (3,) over all vertices
    surface_area: float             # +inf when beyond the double range (see notes)
    volume: float                   # signed; meaningful for closed oriented meshes; ±inf beyond the range
    notes: tuple[str, ...] = ()     # what could not be represented, e.g. a volume beyond the double range

    def as_dict(self) -> dict[str, Any]:
        """The figures as plain Python values (JSON-ready): the bounding box as two lists."""
        figures = {name: getattr(self, name) for name in self.__dataclass_fields__}
        figures["bounding_box"] = [np.asarray(corner).tolist() for corner in self.bounding_box]
        return figures

    def __str__(self) -> str:
        def count(value: int) -> str:
            return f"{value:,}"

        def amount(value: int, singular: str, plural: str) -> str:
            return f"{value:,} {singular if value == 1 else plural}"

        def point(p: FloatArray) -> str:
            return "(" + ", ".join(f"{x:.6g}" for x in p) + ")"

        lo, hi = self.bounding_box
        rows = [
            ("vertices", count(self.n_vertices)
             + (f"  ({count(self.n_unreferenced_vertices)} unreferenced)"
                if self.n_unreferenced_vertices else "")),
            ("faces", count(self.n_faces)),
            ("edges", count(self.n_edges)),
            ("components", count(self.n_components)),
            ("boundary loops", f"{count(self.n_boundary_loops)}  ({amount(self.n_boundary_edges, 'edge', 'edges')})"),
            ("Euler characteristic", str(self.euler_characteristic)),
            ("genus", "undefined (not an orientable manifold)" if self.genus is None else str(self.genus)),
            ("manifold", "yes" if self.is_manifold else
             f"no  ({amount(self.n_non_manifold_edges, 'non-manifold edge', 'non-manifold edges')}, "
             f"{amount(self.n_non_manifold_vertices, 'non-manifold vertex', 'non-manifold vertices')})"),
            ("oriented", "yes" if self.is_oriented else "no"),
            ("bounding box", f"{point(lo)} .. {point(hi)}"),
            ("size", point(hi - lo)),
            ("surface area", f"{self.surface_area:.6g}"),
            ("volume", f"{self.volume:.6g}"
             + ("" if self.n_boundary_edges == 0 and self.is_oriented
                else "  (not closed and oriented: not a true volume)")),
        ] + [("note", note) for note in self.notes]
        width = max(len(name) for name, _ in rows)
        return "\n".join(f"{name:<{width}}  {value}" for name, value in rows)


def info(V: ArrayLike, F: ArrayLike | Polygons) -> MeshInfo:
    """Topological and geometric summary of a mesh (see :class:`MeshInfo`; ``str()`` it to print).

    V: (n, 3) float array, F: (m, 3) integer array of triangles, (m, s) of polygons with s > 3
    corners (a (k, 4) quad mesh) or :class:`meshsmith.io.Polygons`. Polygons count as faces and
    their sides as edges; the rest is measured on their fan triangulation (same vertices, fans,
    boundary and χ; area and volume of the fans for non-planar polygons). Runs in O(m log m).
    The surface area and volume are computed in the normalized frame and scaled back: at
    coordinates whose area or volume exceeds the double range (a volume at 1e150) they are ±inf
    and ``notes`` says so; the call does not fail for it.
    Raises InputError for bad input (empty, out-of-range index, NaN/Inf).
    """
    from .io import Polygons
    polygons = F if isinstance(F, Polygons) else None
    if polygons is None:
        faces = _arguments.numbers(F, "F", "index")
        if faces.ndim == 2 and faces.shape[1] > 3:
            polygons = Polygons.from_array(faces)
    if polygons is not None:
        F = polygons.fan_triangles()[0]
    counts = _topology.mesh_info(V, F)
    if polygons is not None:
        # Each diagonal of a fan is one more edge than the polygon has: s - 3 per polygon.
        counts["n_faces"] = len(polygons)
        counts["n_edges"] -= int((polygons.sizes - 3).sum())
    points = np.asarray(V, dtype=np.float64)
    # Area and volume in the normalized frame (core/normalization.h: V / 2^e, exact), scaled back by
    # 2^(2e) and 2^(3e) when that fits in a double; ±inf and a note when it does not (a volume at
    # coordinates of 1e150 is ~1e450), instead of the InputError geometry.volume raises.
    exponent = _core.normalizing_exponent(points)
    normalized = np.ldexp(points, -exponent)
    notes = []
    measures = {}
    for name, function, power in (("surface area", _geometry.surface_area, 2), ("volume", _geometry.volume, 3)):
        value = float(function(normalized, F))
        try:
            measures[name] = math.ldexp(value, power * exponent)
        except OverflowError:
            measures[name] = math.copysign(math.inf, value)
            notes.append(f"the {name} is about 2^{math.frexp(value)[1] + power * exponent}, beyond the double "
                         f"range; {measures[name]} stands for it")
    return MeshInfo(
        **counts,
        bounding_box=(points.min(axis=0), points.max(axis=0)),
        surface_area=measures["surface area"],
        volume=measures["volume"],
        notes=tuple(notes),
    )
