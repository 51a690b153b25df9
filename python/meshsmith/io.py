"""Reading and writing meshes and point clouds: OBJ, OFF, PLY, STL and XYZ.

The parsers are C++ (``meshsmith::io``): the file is read whole into memory and parsed with
``std::from_chars`` with the GIL released. The format comes from the file extension
(case-insensitive: ``.obj .off .ply .stl .xyz``) unless ``format=`` names it.

=======  =========================================================================
format   what is read / written
=======  =========================================================================
OBJ      ``v``, ``vt``, ``vn``, ``f v/vt/vn`` (negative indices too); other statements
         (``o g s usemtl mtllib l p`` ...) ignored. Always written as text.
OFF      ASCII (``OFF``, ``COFF``, ``NOFF``, ``STOFF``...: extra per-vertex and per-face
         values ignored) and binary (``OFF BINARY``, float32 coordinates).
PLY      ASCII and binary, either endianness; ``vertex`` (x y z, nx ny nz, u v), ``face``
         (``vertex_indices`` or ``vertex_index``) and ``tristrips`` (-1 restarts a strip);
         all other elements and properties, lists included, skipped by their types.
STL      ASCII and binary; vertices with exactly equal coordinates are merged.
XYZ      points only: 3 numbers per line, or 6 with normals.
=======  =========================================================================

Every problem with a file -- missing, a directory, empty, unknown extension, truncated, counts
the file cannot hold, garbage tokens, indices out of range -- raises
:class:`meshsmith.InputError` whose message starts with the file name and gives the line
(text formats) or byte offset (binary formats).
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Literal, NamedTuple, Sequence, overload

import numpy as np

from ._core import InputError
from ._core import io as _core
from ._results import Unpackable
from ._typing import ArrayLike, FloatArray, IndexArray, PathLike
from .core import Mesh, PointCloud

__all__ = ["Polygons", "PolygonMesh", "MeshWithAttributes", "PlanarGraph", "read_mesh", "read_mesh_with_attributes",
           "write_mesh", "read_points", "write_points", "read_poly"]

_BINARY_BY_DEFAULT = {"ply": True, "stl": True, "off": False, "obj": False, "xyz": False}


@dataclass(frozen=True)
class Polygons:
    """Faces of any sizes in compressed form.

    ``offsets``: (m + 1,) int64, starting at 0; polygon ``i`` is
    ``indices[offsets[i]:offsets[i + 1]]``. ``indices``: (k,) int64 zero-based vertex indices.
    Every polygon has at least 3 corners.
    """

    offsets: IndexArray
    indices: IndexArray

    @classmethod
    def from_list(cls, faces: Sequence[Sequence[int]]) -> "Polygons":
        """Polygons from a sequence of index sequences, e.g. ``[[0, 1, 2, 3], [3, 2, 4]]``."""
        sizes = np.array([len(face) for face in faces], dtype=np.int64)
        offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
        flat = [int(i) for face in faces for i in face]
        return cls(offsets, np.asarray(flat, dtype=np.int64))

    @classmethod
    def from_triangles(cls, F: ArrayLike) -> "Polygons":
        """Polygons holding the rows of an (m, 3) triangle array."""
        faces = np.asarray(F)
        return cls(np.arange(0, 3 * len(faces) + 1, 3, dtype=np.int64),
                   faces.reshape(-1).astype(np.int64))

    def __len__(self) -> int:
        return len(self.offsets) - 1

    def __getitem__(self, i: int) -> IndexArray:
        if not -len(self) <= i < len(self):
            raise IndexError(f"polygon {i} out of range for {len(self)} polygons")
        i %= len(self)
        return self.indices[self.offsets[i]:self.offsets[i + 1]]

    @property
    def sizes(self) -> IndexArray:
        """(m,) int64 number of corners of each polygon."""
        return np.diff(self.offsets)

    def to_list(self) -> list[list[int]]:
        return [self[i].tolist() for i in range(len(self))]

    def triangulate(self) -> IndexArray:
        """(t, 3) int64 fan triangulation: polygon (v0..vk) gives (v0, vi, vi+1), in order.

        Raises InputError if the offsets are malformed or a polygon has fewer than 3 corners.
        """
        return _core.triangulate_fan(np.asarray(self.offsets).reshape(-1, 1),
                                     np.asarray(self.indices).reshape(-1, 1))


class PolygonMesh(NamedTuple):
    """A mesh with faces of any size (``read_mesh(..., triangulate=False)``); unpacks as ``V, F``."""

    V: FloatArray  #: (n, 3) positions
    F: Polygons    #: the faces


class PlanarGraph(NamedTuple):
    """A planar straight-line graph (:func:`read_poly`); unpacks as ``P, segments, holes``."""

    P: FloatArray          #: (n, 2) points
    segments: IndexArray   #: (s, 2) zero-based index pairs
    holes: FloatArray      #: (h, 2) hole seed points


@dataclass(frozen=True)
class MeshWithAttributes(Unpackable):
    """A mesh with optional texture coordinates and normals, indexed per face corner; unpacks
    in field order (``V, F, UV, F_uv, N, F_normal``).

    V: (n, 3) float64. F: (m, 3) int64 triangles, or :class:`Polygons`.
    UV: (k, 2) float64 or None. F_uv: like F (indices into UV; -1 where a face has none) or None.
    N: (l, 3) float64 or None. F_normal: like F (indices into N; -1 where none) or None.
    For PLY files UV and N are per-vertex properties and F_uv / F_normal equal F.
    """

    V: FloatArray
    F: IndexArray | Polygons
    UV: FloatArray | None = None
    F_uv: IndexArray | Polygons | None = None
    N: FloatArray | None = None
    F_normal: IndexArray | Polygons | None = None


@overload
def _format(format: None) -> None: ...
@overload
def _format(format: str) -> str: ...
def _format(format: str | None) -> str | None:
    return None if format is None else str(format).lstrip(".").lower()


def _resolved_format(path: PathLike, format: str | None) -> str:
    if format is not None:
        return _format(format)
    return os.path.splitext(os.fsdecode(path))[1].lstrip(".").lower()


def _read(path: PathLike, triangulate: bool, format: str | None, with_uv: bool, with_normals: bool
          ) -> MeshWithAttributes:
    out = _core.read_mesh(os.fsdecode(path), _format(format), bool(triangulate), with_uv,
                          with_normals)
    if triangulate:
        return MeshWithAttributes(out["V"], out["F"], out["UV"], out["F_uv"], out["N"],
                                  out["F_normal"])
    offsets = out["offsets"]

    def polygons(indices: IndexArray | None) -> Polygons | None:
        return None if indices is None else Polygons(offsets, indices)

    return MeshWithAttributes(out["V"], Polygons(offsets, out["indices"]), out["UV"],
                              polygons(out["uv_indices"]), out["N"],
                              polygons(out["normal_indices"]))


@overload
def read_mesh(path: PathLike, *, triangulate: Literal[True] = ..., format: str | None = ...) -> Mesh: ...
@overload
def read_mesh(path: PathLike, *, triangulate: Literal[False], format: str | None = ...) -> PolygonMesh: ...
@overload
def read_mesh(path: PathLike, *, triangulate: bool, format: str | None = ...) -> Mesh | PolygonMesh: ...
def read_mesh(path: PathLike, *, triangulate: bool = True, format: str | None = None) -> Mesh | PolygonMesh:
    """Read a mesh from an OBJ, OFF, PLY or STL file.

    path: str or os.PathLike. triangulate: split polygons into fans of triangles (default);
    with False the faces come back as :class:`Polygons`. format: "obj", "off", "ply" or "stl"
    to override the extension.

    Returns a :class:`meshsmith.core.Mesh` (V, F): V (n, 3) float64 with every vertex record of
    the file (unreferenced ones too; for STL the distinct corner positions in order of
    appearance); F (m, 3) int64; with triangulate=False a :class:`PolygonMesh` (V, Polygons).
    A file without faces (a PLY point cloud) gives F with 0 rows.
    Raises InputError (file name and line or byte offset in the message) for any bad file.
    """
    mesh = _read(path, triangulate, format, False, False)
    if isinstance(mesh.F, Polygons):
        return PolygonMesh(mesh.V, mesh.F)
    return Mesh(mesh.V, mesh.F)


def read_mesh_with_attributes(path: PathLike, *, triangulate: bool = True, format: str | None = None,
                              with_uv: bool = True, with_normals: bool = True
                              ) -> MeshWithAttributes:
    """Read a mesh with its texture coordinates and normals (OBJ ``vt``/``vn``; PLY u,v/nx,ny,nz).

    Same arguments as :func:`read_mesh`; with_uv / with_normals choose what to keep. Returns a
    :class:`MeshWithAttributes` whose UV / F_uv / N / F_normal are None when absent.
    """
    return _read(path, triangulate, format, bool(with_uv), bool(with_normals))


def _polygon_arrays(faces: ArrayLike | Polygons) -> tuple[ArrayLike, IndexArray | None]:
    """(flat indices (k, 1), offsets (m+1, 1) or None) for the binding."""
    if isinstance(faces, Polygons):
        return (np.asarray(faces.indices).reshape(-1, 1),
                np.asarray(faces.offsets).reshape(-1, 1))
    return faces, None


def _corner_column(indices: ArrayLike | Polygons) -> IndexArray:
    """Per-corner indices of polygons (Polygons or a flat array) as a (k, 1) array."""
    if isinstance(indices, Polygons):
        indices = indices.indices
    return np.asarray(indices).reshape(-1, 1)


def write_mesh(path: PathLike, V: ArrayLike, F: ArrayLike | Polygons, *, format: str | None = None,
               binary: bool | None = None, big_endian: bool = False, UV: ArrayLike | None = None,
               F_uv: ArrayLike | Polygons | None = None, N: ArrayLike | None = None,
               F_normal: ArrayLike | Polygons | None = None) -> None:
    """Write a mesh as OBJ, OFF, PLY or STL.

    V: (n, 3) real array. F: (m, 3) integer array of triangles, or :class:`Polygons`.
    format: overrides the extension. binary: default True for PLY and STL, False for OFF;
    OBJ is always text. Text coordinates are written in the shortest form that reads back to
    the same float64 (exact round trip); binary PLY stores float64; binary STL and binary OFF
    store float32 (as those formats prescribe). big_endian: binary PLY only.
    UV (k, 2) with F_uv (like F; for Polygons a Polygons or a flat per-corner array), N (l, 3)
    with F_normal (like F_uv): written by OBJ as
    ``f v/vt/vn``; PLY writes N as nx, ny, nz when N has n rows (F_normal may be omitted).
    STL writes the fan triangulation with facet normals.
    Raises InputError for bad arrays (shape, dtype, non-finite values, indices out of range)
    or a file that cannot be written. The arrays are not modified.
    """
    fmt = _resolved_format(path, format)
    if binary is None:
        binary = _BINARY_BY_DEFAULT.get(fmt, False)
    faces, offsets = _polygon_arrays(F)
    if offsets is not None:
        F_uv = _corner_column(F_uv) if F_uv is not None else None
        F_normal = _corner_column(F_normal) if F_normal is not None else None
    _core.write_mesh(os.fsdecode(path), V, faces, offsets, UV, F_uv, N, F_normal, _format(format),
                     bool(binary), bool(big_endian))


def read_points(path: PathLike, *, format: str | None = None) -> PointCloud:
    """Read a point cloud from an XYZ or PLY file.

    XYZ: lines of ``x y z`` or ``x y z nx ny nz`` ('#' comments allowed). PLY: the x, y, z (and
    nx, ny, nz) of the vertex element; other elements, faces included, are skipped.
    Returns a :class:`meshsmith.core.PointCloud` (P, N): P (n, 3) float64, N (n, 3) float64 or
    None when the file has no normals. Raises InputError for any bad file.
    """
    P, N = _core.read_points(os.fsdecode(path), _format(format))
    return PointCloud(P, N)


def write_points(path: PathLike, P: ArrayLike, N: ArrayLike | None = None, *, format: str | None = None,
                 binary: bool | None = None, big_endian: bool = False) -> None:
    """Write a point cloud as XYZ (text, 3 or 6 columns) or PLY (binary float64 by default).

    P: (n, 3) real array; N: (n, 3) normals or None. Text is written with exact round trip.
    Raises InputError for bad arrays or a file that cannot be written.
    """
    fmt = _resolved_format(path, format)
    if binary is None:
        binary = _BINARY_BY_DEFAULT.get(fmt, False)
    _core.write_points(os.fsdecode(path), P, N, _format(format), bool(binary), bool(big_endian))


def read_poly(path: PathLike) -> PlanarGraph:
    """Read a planar straight-line graph in Shewchuk's Triangle ``.poly`` format.

    The file holds a vertex section (``n 2 attributes markers`` then ``id x y [attributes]
    [marker]`` lines), a segment section (``s markers`` then ``id a b [marker]``) and a hole
    section (``h`` then ``id x y``); ``#`` starts a comment; vertex ids may start at 0 or 1.
    Returns a :class:`PlanarGraph` (P (n, 2) float64, segments (s, 2) int64 zero-based,
    holes (h, 2) float64).
    Raises InputError naming the file and line for a missing file, a malformed or truncated
    section, a dimension other than 2, or a segment index that names no vertex.
    """
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"{path} does not exist" if not os.path.exists(path) else f"{path} is not a file")
    with open(path, "r", encoding="utf-8", errors="replace") as stream:
        lines = [(number, text.split("#", 1)[0].split()) for number, text in enumerate(stream, 1)]
    records = iter([(number, fields) for number, fields in lines if fields])

    def take(what: str, count: int | None = None) -> tuple[int, list[str]]:
        try:
            number, fields = next(records)
        except StopIteration:
            raise InputError(f"{path}: file ends before the {what}") from None
        if count is not None and len(fields) < count:
            raise InputError(f"{path}:{number}: expected at least {count} numbers in the {what}")
        return number, fields

    def numbers(number: int, fields: list[str], kind: type, what: str) -> list[Any]:
        try:
            return [kind(field) for field in fields]
        except ValueError:
            raise InputError(f"{path}:{number}: unreadable number in the {what}: {' '.join(fields)}") from None

    number, fields = take("vertex header", 2)
    n, dimension = numbers(number, fields[:2], int, "vertex header")
    if dimension != 2:
        raise InputError(f"{path}:{number}: dimension {dimension}: .poly files here are planar (2)")
    if n < 0 or n > 100_000_000:
        raise InputError(f"{path}:{number}: vertex count {n} is out of range")
    ids, coordinates = [], []
    for _ in range(n):
        number, fields = take("vertex list", 3)
        values = numbers(number, fields[:3], float, "vertex list")
        ids.append(int(values[0]))
        coordinates.append(values[1:3])
    points = np.array(coordinates, dtype=np.float64).reshape(-1, 2)
    first = min(ids) if ids else 0
    segments, holes = np.zeros((0, 2), np.int64), np.zeros((0, 2), np.float64)

    def optional_section_count(what: str) -> int | None:
        """The count on a section's header line, or None where the file ends before it."""
        try:
            number, fields = next(records)
        except StopIteration:
            return None
        (count,) = numbers(number, fields[:1], int, what)
        if count < 0 or count > 100_000_000:
            raise InputError(f"{path}:{number}: {what.split()[0]} count {count} is out of range")
        return count

    s = optional_section_count("segment header")
    if s is None:
        return PlanarGraph(points, segments, holes)
    rows = []
    for _ in range(s):
        number, fields = take("segment list", 3)
        a, b = numbers(number, fields[1:3], int, "segment list")
        if not (first <= a < first + n and first <= b < first + n):
            raise InputError(f"{path}:{number}: segment ({a}, {b}) names a vertex outside {first}..{first + n - 1}")
        rows.append((a - first, b - first))
    segments = np.array(rows, dtype=np.int64).reshape(-1, 2)
    h = optional_section_count("hole header")
    if h is None:
        return PlanarGraph(points, segments, holes)
    holes = np.array([numbers(*take("hole list", 3), float, "hole list")[1:3] for _ in range(h)],
                     dtype=np.float64).reshape(-1, 2)
    return PlanarGraph(points, segments, holes)
