"""Progressive meshes (§4.3; Hoppe 1996): a base mesh and the vertex splits that undo decimation; binding cpp/python/decimation_progressive.cpp.
"""
from __future__ import annotations

import os
import tempfile
from typing import Any, Callable, NamedTuple

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import decimation as _core
from .._typing import ArrayLike, BoolArray, FloatArray, PathLike
from ..core import Mesh
from ..repair.unreferenced import on_referenced_vertices
from .qem import decimate

__all__ = ["FaceRange", "ProgressiveMesh", "progressive_mesh"]


class FaceRange(NamedTuple):
    """:attr:`ProgressiveMesh.face_range`; unpacks as ``base, full``."""

    base: int  #: faces of the base mesh (level 0)
    full: int  #: faces of the full mesh (level n_splits)


class ProgressiveMesh:
    """A progressive mesh (§4.3; Hoppe 1996): a coarse base mesh and the vertex splits that undo,
    in reverse, the collapses of :func:`decimate`.

    Levels: ``level`` k is the mesh after k vertex splits; 0 is the base mesh, ``n_splits`` the
    full mesh, which reproduces the input without its unreferenced vertices (positions bit for
    bit, faces up to order and rotation). Every level is a valid manifold mesh. The current level moves incrementally
    (:meth:`set_level`, :meth:`refine`, :meth:`coarsen`, :meth:`at`): the cost is proportional to
    the number of splits between the two levels, not to the mesh size. Meshes come back as
    :class:`meshsmith.core.Mesh` (V (k, 3) float64, F (l, 3) int64) with their vertices in the
    order of the input mesh. Build one with :func:`progressive_mesh`, or read one with
    :meth:`ProgressiveMesh.load`. Pickles as the bytes of :meth:`save`'s file and the current level.
    """

    def __init__(self, core_mesh: Any) -> None:
        self._pm = core_mesh

    def __getstate__(self) -> dict[str, Any]:
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "mesh.pm")
            self.save(path)
            with open(path, "rb") as stream:
                return {"pm": stream.read(), "level": self.level}

    def __setstate__(self, state: dict[str, Any]) -> None:
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "mesh.pm")
            with open(path, "wb") as stream:
                stream.write(state["pm"])
            self._pm = _core.load_progressive_mesh(path)
        self.set_level(state["level"])

    @classmethod
    def load(cls, path: PathLike) -> "ProgressiveMesh":
        """Read a file written by :meth:`save` (at its full level).

        Raises InputError for a missing, foreign, newer, truncated or corrupt file (every count
        is checked against the file size, every vertex split is replayed and checked).
        """
        return cls(_core.load_progressive_mesh(os.fspath(path)))

    def save(self, path: PathLike) -> None:
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
    def face_range(self) -> FaceRange:
        """(faces of the base mesh, faces of the full mesh)."""
        return FaceRange(self._pm.face_count(0), self._pm.face_count(self._pm.split_count))

    def face_count(self, level: int) -> int:
        """Faces at ``level`` (each split adds two faces, one on the boundary)."""
        return int(self._pm.face_count(level))  # the binding checks level (an integer in [0, n_splits])

    def set_level(self, level: int) -> None:
        """Move the current level to ``level`` by applying or undoing the vertex splits in
        between. Raises InputError if level is outside [0, n_splits]."""
        self._pm.set_level(level)

    def refine(self, steps: int = 1) -> int:
        """Apply the next ``steps`` vertex splits (fewer at the full level); returns the level."""
        self._pm.set_level(min(self.n_splits, self.level + _arguments.integer(steps, "steps", 0, 2 ** 63 - 1)))
        return self.level

    def coarsen(self, steps: int = 1) -> int:
        """Undo the last ``steps`` vertex splits (fewer at the base level); returns the level."""
        self._pm.set_level(max(0, self.level - _arguments.integer(steps, "steps", 0, 2 ** 63 - 1)))
        return self.level

    def mesh(self) -> Mesh:
        """(V, F) at the current level."""
        return Mesh(*self._pm.current_mesh())

    def level_for_face_count(self, n_faces: int) -> int:
        """The finest level with at most ``n_faces`` faces.

        Raises InputError if n_faces is not an integer inside :attr:`face_range`."""
        return int(self._pm.level_for_face_count(n_faces))  # the binding checks the integer, the core the range

    def at(self, n_faces: int) -> Mesh:
        """Move to the finest level with at most ``n_faces`` faces and return its (V, F).

        Raises InputError as :meth:`level_for_face_count`."""
        self._pm.set_level(self.level_for_face_count(n_faces))
        return Mesh(*self._pm.current_mesh())

    def refine_where(self, predicate: Callable[[FloatArray], BoolArray] | None = None, *,
                     near: ArrayLike | None = None, radius: float | None = None, box: ArrayLike | None = None,
                     whole_stars: bool = False) -> Mesh:
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
            selected = _arguments.flag_array(predicate(P), "the predicate's result")
            if len(selected) != len(P):
                raise InputError(f"refine_where: the predicate must return a ({len(P)},) bool array, "
                                 f"got shape {selected.shape}")
        elif near is not None:
            point = _arguments.finite(_arguments.real_array(near, "near"), "near")
            if radius is not None:
                radius = _arguments.real(radius, "radius")
            if point.shape != (3,) or radius is None or not radius >= 0:
                raise InputError("refine_where: near must be a finite 3D point and radius >= 0")
            selected = np.linalg.norm(P - point, axis=1) <= radius
        else:
            bounds = _arguments.real_array(box, "box", 3)
            if bounds.shape != (2, 3) or np.isnan(bounds).any():
                raise InputError("refine_where: box must be ((xmin, ymin, zmin), (xmax, ymax, zmax))")
            selected = np.all((P >= bounds[0]) & (P <= bounds[1]), axis=1)
        return Mesh(*self._pm.selective_refinement(selected, bool(whole_stars)))

    def __repr__(self) -> str:
        low, high = self.face_range
        return (f"ProgressiveMesh({self.n_splits} vertex splits, {low}..{high} faces, "
                f"level {self.level}: {self.n_faces} faces)")


def progressive_mesh(V: ArrayLike, F: ArrayLike, **decimate_options: Any) -> ProgressiveMesh:
    """The progressive mesh of (V, F) (§4.3): :func:`decimate` with ``decimate_options`` (its
    stop rules and fairness criteria; without a stop rule, down to the smallest mesh the
    decimator reaches) records its collapses, stored as vertex splits
    (v_s, v_l, v_r -> position, plus v_s's position before the split: the offset of a
    full-edge collapse). Returned at its full level.

    V: (n, 3) float array, F: (m, 3) integer array, manifold and consistently oriented, without
    faces that repeat a vertex (the full level must reproduce the input). Vertices no face uses
    are left out: every level holds only vertices some face uses, in the input's order, so the
    full level is ``(V[used], F renumbered)`` (:func:`meshsmith.repair.remove_unreferenced`).
    Raises InputError for bad input or options (as :func:`decimate`), or when the input is not
    manifold or not oriented (the message names :func:`meshsmith.repair.clean`).
    """
    options = dict(decimate_options)
    if all(options.get(key) is None for key in ("target_faces", "ratio", "max_error")):
        options["target_faces"] = 1
    for key in ("record_collapses", "return_report"):
        if key in options:
            raise InputError(f"progressive_mesh: {key} is set by progressive_mesh itself")
    V, F, _ = on_referenced_vertices(V, F)
    _, _, report = decimate(V, F, record_collapses=True, return_report=True, **options)
    if report.split_vertex_origin.size:
        raise InputError("progressive_mesh: the input is not manifold or not consistently oriented (the decimator "
                         "had to split vertices): clean it first with meshsmith.repair.clean "
                         "(`meshsmith clean` on the command line)")
    c = report.collapses
    assert c is not None  # record_collapses=True
    vertices = np.column_stack([c["removed"], c["kept"], c["left"], c["right"]]) if len(c["removed"]) \
        else np.zeros((0, 4), dtype=np.int64)
    return ProgressiveMesh(_core.progressive_mesh_from_collapses(
        V, F, vertices, c["removed_position"].reshape(-1, 3), c["kept_position_before"].reshape(-1, 3),
        c["kept_position_after"].reshape(-1, 3), decimate_options.get("progress")))
