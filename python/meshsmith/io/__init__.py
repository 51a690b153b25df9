"""Reading and writing meshes and point clouds: OBJ, OFF, PLY, STL, glTF binary (GLB) and XYZ.

The OBJ, OFF, PLY, STL and XYZ parsers are C++ (``meshsmith::io``): the file is read whole into
memory and parsed with ``std::from_chars`` with the GIL released. GLB is read and written here in
Python (:mod:`meshsmith.io.gltf`: a JSON chunk and one binary buffer decoded with numpy). The
format comes from the file extension (case-insensitive: ``.obj .off .ply .stl .glb .xyz``)
unless ``format=`` names it.

Attributes. ``read_mesh(path, return_attributes=True)`` gives a :class:`MeshData`: V and F with
the normals, texture coordinates (UV, each with its own corner indices) and vertex and face
colours the file holds. ``write_mesh`` writes every attribute it is given in every format that
can hold it, and raises :class:`meshsmith.InputError` naming the attribute, the format and a
format that can hold it where the format cannot: nothing is dropped silently. What each format
holds:

=========  =============  ==============  ==============  ===============  ==============
format     normals        UV              vertex colours  face colours     written as
=========  =============  ==============  ==============  ===============  ==============
OBJ        per corner     per corner      RGB             no               text
PLY        per vertex     per corner      RGB(A)          RGB(A)           binary float64
OFF        per vertex     per vertex      RGB(A)          RGB(A)           text (binary
                                                                           float32)
GLB        per corner     per corner      RGB(A)          no               float32
STL        no             no              no              no               binary float32
=========  =============  ==============  ==============  ===============  ==============

"Per corner" attributes are indexed by their own F_normal / F_uv; "per vertex" formats take them
when every corner of a vertex has the same value (read back, they come with F_uv == F).
Per-corner UVs and normals in GLB split the vertices along seams (see :mod:`meshsmith.io.gltf`).
Colours are floats in [0, 1] (uint8 arrays are taken as 0..255); files with 8-bit colours give
k / 255.

=======  =========================================================================
format   what is read
=======  =========================================================================
OBJ      ``v`` (with ``r g b [a]`` colours after x y z), ``vt``, ``vn``, ``f v/vt/vn``
         (negative indices too); ``o g s usemtl mtllib`` and the other grouping, material and
         display statements are skipped silently; points (``p``), polylines (``l``),
         free-form geometry and unknown statements are skipped with a warning that counts them.
OFF      ASCII and binary with the ``[ST][C][N]OFF`` prefixes (texture coordinates, colours,
         normals per vertex) and colours after a face's indices (3 or 4 values; colours above
         1 anywhere in the file are read as 0..255). Binary OFF in either byte order: Geomview's
         big-endian layout with face colour counts, or the little-endian one of the PMP library
         (no colour counts); the layout whose counts and length fit the file is used.
PLY      ASCII and binary, either endianness; ``vertex`` (x y z, nx ny nz, u v / s t /
         texture_u texture_v, red green blue alpha), ``face`` (``vertex_indices`` or
         ``vertex_index``, red green blue alpha, ``texcoord`` lists of u v per corner) and
         ``tristrips`` (-1 restarts a strip); a range scan's ``range_grid`` is skipped with a
         warning (:func:`read_range_scan` meshes it); all other elements and properties, lists
         included, skipped by their types.
STL      ASCII and binary; vertices with exactly equal coordinates are merged.
GLB      glTF 2.0 binary: the triangles of every mesh of the default scene, with the nodes'
         transforms; POSITION, NORMAL, TEXCOORD_0, COLOR_0 (see :mod:`meshsmith.io.gltf`).
XYZ      points only: 3 numbers per line, or 6 with normals.
=======  =========================================================================

Every problem with a file -- missing, a directory, empty, unknown extension, truncated, counts
the file cannot hold, garbage tokens, indices out of range -- raises
:class:`meshsmith.InputError` whose message starts with the file name and gives the line
(text formats) or byte offset (binary formats). What a reader skips is reported with
:class:`SkippedDataWarning` (``warnings.warn``, once per kind, with the count).
"""
from __future__ import annotations

import os
from dataclasses import dataclass, fields
from typing import Any, Literal, NamedTuple, Sequence, overload

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import io as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, PathLike
from ..core import Mesh, PointCloud
from . import gltf
from ._skipped import SkippedDataWarning, warn_skipped
from .range_scan import RangeScan, read_range_scan

__all__ = ["Polygons", "PolygonMesh", "PlanarGraph", "MeshData", "SkippedDataWarning", "read_mesh", "write_mesh",
           "read_points", "write_points", "read_poly", "RangeScan", "read_range_scan"]

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
        faces = _arguments.index_array(F, "F", 3)
        return cls(np.arange(0, 3 * len(faces) + 1, 3, dtype=np.int64),
                   faces.reshape(-1).astype(np.int64))

    @classmethod
    def from_array(cls, F: ArrayLike) -> "Polygons":
        """Polygons holding the rows of an (m, s) integer array, s >= 3 (e.g. (k, 4) quads)."""
        faces = _arguments.numbers(F, "F", "index")
        if faces.ndim != 2 or faces.shape[1] < 3:
            raise InputError(f"F has shape {faces.shape}: expected (m, s) with s >= 3 corners per face")
        faces = _arguments.index_array(faces, "F", faces.shape[1]).astype(np.int64)
        size = faces.shape[1]
        return cls(np.arange(0, size * len(faces) + 1, size, dtype=np.int64), faces.reshape(-1))

    def to_array(self) -> IndexArray:
        """(m, s) int64 array of the polygons when they all have s corners (a quad mesh read with
        ``triangulate=False`` gives (k, 4)). Raises InputError when the sizes differ."""
        sizes = self.sizes
        if len(sizes) and (sizes != sizes[0]).any():
            bad = int(np.argmax(sizes != sizes[0]))
            raise InputError(f"polygon {bad} has {sizes[bad]} corners and polygon 0 has {sizes[0]}: "
                             "not one array (use the Polygons, or triangulate)")
        return self.indices.reshape(len(sizes), int(sizes[0]) if len(sizes) else 0).astype(np.int64)

    def fan_triangles(self) -> tuple[IndexArray, np.ndarray, IndexArray]:
        """The fan triangulation (:meth:`triangulate`) with, per triangle, a mask of which of its
        edges are polygon edges (bit k: the edge opposite corner k; the fan's diagonals are not) and
        the polygon it comes from: ((t, 3) int64, (t,) uint8, (t,) int64)."""
        triangles = self.triangulate()
        sizes = self.sizes
        polygon_of = np.repeat(np.arange(len(sizes), dtype=np.int64), sizes - 2)
        first = np.concatenate([[0], np.cumsum(sizes - 2)])[:-1]
        step = np.arange(len(triangles)) - first[polygon_of] + 1  # triangle (v0, v_step, v_step+1)
        masks = 1 + 2 * (step == sizes[polygon_of] - 2) + 4 * (step == 1)
        return triangles, masks.astype(np.uint8), polygon_of

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
        return _core.triangulate_fan(_corner_column(self.offsets, "offsets"),
                                     _corner_column(self.indices, "indices"))


class PolygonMesh(NamedTuple):
    """A mesh with faces of any size (``read_mesh(..., triangulate=False)``); unpacks as ``V, F``."""

    V: FloatArray  #: (n, 3) positions
    F: Polygons    #: the faces


class PlanarGraph(NamedTuple):
    """A planar straight-line graph (:func:`read_poly`); unpacks as ``P, segments, holes``."""

    P: FloatArray          #: (n, 2) points
    segments: IndexArray   #: (s, 2) zero-based index pairs
    holes: FloatArray      #: (h, 2) hole seed points


_ATTRIBUTES = ("normals", "F_normal", "UV", "F_uv", "colors", "face_colors")


@dataclass(frozen=True, eq=False)
class MeshData(Unpackable):
    """A mesh with the attributes its file holds (``read_mesh(path, return_attributes=True)``).

    V: (n, 3) float64. F: (m, 3) int64 triangles, or :class:`Polygons` (``triangulate=False``).
    normals: (l, 3) float64 with F_normal (like F: one index into normals per corner, -1 where
    a face has none). UV: (k, 2) float64 with F_uv (likewise). Per-vertex normals and UVs (PLY,
    OFF, GLB) come with F_normal / F_uv equal to F. colors: (n, 3) or (n, 4) float64 RGB(A) in
    [0, 1], one row per vertex; face_colors: (m, 3) or (m, 4), one row per row of F (a polygon's
    colour repeated for each of its fan triangles). Every attribute the file lacks is None.

    Unpacks as ``V, F = mesh`` (like :func:`read_mesh` without attributes); pickles to plain
    arrays; ``write_mesh(path, mesh)`` writes it with all its attributes.
    """

    V: np.ndarray
    F: np.ndarray | Polygons
    normals: np.ndarray | None = None
    F_normal: np.ndarray | Polygons | None = None
    UV: np.ndarray | None = None
    F_uv: np.ndarray | Polygons | None = None
    colors: np.ndarray | None = None
    face_colors: np.ndarray | None = None

    unpacks = ("V", "F")   # ``V, F = mesh``

    def __repr__(self) -> str:
        def shape(value: Any) -> str:
            if isinstance(value, Polygons):
                return f"Polygons({len(value)})"
            return f"{getattr(value, 'shape', '?')}"
        parts = [f"{field.name}={shape(getattr(self, field.name))}" for field in fields(self)
                 if getattr(self, field.name) is not None]
        return f"MeshData({', '.join(parts)})"

    @property
    def attributes(self) -> list[str]:
        """Names of the attributes present: among "normals", "UV", "colors", "face_colors"."""
        return [name for name in ("normals", "UV", "colors", "face_colors")
                if getattr(self, name) is not None]

    def attribute_arrays(self) -> dict[str, Any]:
        """The attributes as ``write_mesh`` keywords (only those present)."""
        return {name: getattr(self, name) for name in _ATTRIBUTES if getattr(self, name) is not None}

    def __reduce__(self) -> tuple[Any, tuple[dict[str, np.ndarray]]]:
        arrays = {}
        for field in fields(self):
            value = getattr(self, field.name)
            if isinstance(value, Polygons):
                arrays[field.name + ".offsets"], arrays[field.name + ".indices"] = value.offsets, value.indices
            elif value is not None:
                arrays[field.name] = value
        return _mesh_data_from_arrays, (arrays,)


def _mesh_data_from_arrays(arrays: dict[str, np.ndarray]) -> MeshData:
    """Inverse of MeshData.__reduce__: the dict of plain arrays back to a MeshData."""
    values: dict[str, Any] = {}
    for field in fields(MeshData):
        if field.name + ".offsets" in arrays:
            values[field.name] = Polygons(arrays[field.name + ".offsets"], arrays[field.name + ".indices"])
        else:
            values[field.name] = arrays.get(field.name)
    return MeshData(**values)


def _format(format):
    return None if format is None else str(format).lstrip(".").lower()


def _resolved_format(path: PathLike, format: str | None) -> str:
    if format is not None:
        return str(_format(format))
    return os.path.splitext(os.fsdecode(path))[1].lstrip(".").lower()


def _read_glb(path: PathLike, triangulate: bool) -> MeshData:
    arrays, skipped = gltf.read_glb(path)
    warn_skipped(path, skipped, stacklevel=4)
    mesh = MeshData(**arrays)
    if triangulate:
        return mesh

    def as_polygons(F: Any) -> Polygons | None:   # GLB meshes are triangles: never Polygons here
        return None if F is None else Polygons.from_triangles(F)

    return MeshData(mesh.V, Polygons.from_triangles(np.asarray(mesh.F)), mesh.normals, as_polygons(mesh.F_normal),
                    mesh.UV, as_polygons(mesh.F_uv), mesh.colors, mesh.face_colors)


def _read(path: PathLike, triangulate: bool, format: str | None, attributes: bool) -> MeshData:
    if _resolved_format(path, format) == "glb":
        return _read_glb(path, triangulate)
    out = _core.read_mesh(os.fsdecode(path), _format(format), bool(triangulate), attributes,
                          attributes, attributes)
    skipped = list(out["warnings"])
    if out["range_grid"] is not None:
        rows, cols = out["range_grid"].shape
        skipped.append(f"the range grid ({rows} × {cols} cells) is not meshed: meshsmith.io.read_range_scan "
                       "meshes it")
    warn_skipped(path, skipped, stacklevel=3)
    if triangulate:
        return MeshData(out["V"], out["F"], out["N"], out["F_normal"], out["UV"], out["F_uv"],
                        out["colors"], out["face_colors"])
    offsets = out["offsets"]

    def polygons(indices: IndexArray | None) -> Polygons | None:
        return None if indices is None else Polygons(offsets, indices)

    return MeshData(out["V"], Polygons(offsets, out["indices"]), out["N"],
                    polygons(out["normal_indices"]), out["UV"], polygons(out["uv_indices"]),
                    out["colors"], out["face_colors"])


@overload
def read_mesh(path: PathLike, *, triangulate: Literal[True] = ..., format: str | None = ...,
              return_attributes: Literal[False] = ...) -> Mesh: ...
@overload
def read_mesh(path: PathLike, *, triangulate: Literal[False], format: str | None = ...,
              return_attributes: Literal[False] = ...) -> PolygonMesh: ...
@overload
def read_mesh(path: PathLike, *, triangulate: bool = ..., format: str | None = ...,
              return_attributes: Literal[True]) -> MeshData: ...
@overload
def read_mesh(path: PathLike, *, triangulate: bool = ..., format: str | None = ...,
              return_attributes: bool = ...) -> Mesh | PolygonMesh | MeshData: ...
def read_mesh(path: PathLike, *, triangulate: bool = True, format: str | None = None,
              return_attributes: bool = False) -> Mesh | PolygonMesh | MeshData:
    """Read a mesh from an OBJ, OFF, PLY, STL or GLB file.

    path: str or os.PathLike. triangulate: split polygons into fans of triangles (default);
    with False the faces come back as :class:`Polygons` (``F.to_array()`` gives a quad mesh's
    (k, 4) array). format: "obj", "off", "ply", "stl" or
    "glb" to override the extension. return_attributes: return a :class:`MeshData` with the
    normals, texture coordinates and colours of the file (it still unpacks as ``V, F``).

    Returns a :class:`meshsmith.core.Mesh` (V, F): V (n, 3) float64 with every vertex record of
    the file (unreferenced ones too; for STL the distinct corner positions in order of
    appearance); F (m, 3) int64; with triangulate=False a :class:`PolygonMesh` (V, Polygons).
    A file without faces (a PLY point cloud) gives F with 0 rows.
    Raises InputError (file name and line or byte offset in the message) for any bad file;
    warns (:class:`SkippedDataWarning`) about what it skipped.
    """
    mesh = _read(path, triangulate, format, bool(return_attributes))
    if return_attributes:
        return mesh
    if isinstance(mesh.F, Polygons):
        return PolygonMesh(mesh.V, mesh.F)
    return Mesh(mesh.V, mesh.F)


def _polygon_arrays(faces: ArrayLike | Polygons) -> tuple[ArrayLike, IndexArray | None]:
    """(flat indices (k, 1), offsets (m+1, 1) or None) for the binding."""
    if not isinstance(faces, Polygons):
        array = _arguments.numbers(faces, "F", "index")
        if array.ndim == 2 and array.shape[1] > 3:
            faces = Polygons.from_array(array)  # (k, 4) quads and other equal-sized polygons
    if isinstance(faces, Polygons):
        return _corner_column(faces.indices, "faces.indices"), _corner_column(faces.offsets, "faces.offsets")
    return faces, None


def _corner_column(indices: ArrayLike | Polygons, name: str) -> IndexArray:
    """Per-corner indices of polygons (Polygons or a flat (k,) array) as a (k, 1) array."""
    if isinstance(indices, Polygons):
        indices = indices.indices
    return _arguments.index_array(indices, name).reshape(-1, 1)


def _unit_colors(colors: ArrayLike | None) -> ArrayLike | None:
    """uint8 colours (0..255) as floats in [0, 1]; anything else unchanged (checked in C++)."""
    if isinstance(colors, np.ndarray) and colors.dtype == np.uint8:
        return colors / 255.0
    return colors


def write_mesh(path: PathLike, V: ArrayLike | MeshData, F: ArrayLike | Polygons | None = None, *,
               normals: ArrayLike | None = None, F_normal: ArrayLike | Polygons | None = None,
               UV: ArrayLike | None = None, F_uv: ArrayLike | Polygons | None = None,
               colors: ArrayLike | None = None, face_colors: ArrayLike | None = None,
               format: str | None = None, binary: bool | None = None, big_endian: bool = False) -> None:
    """Write a mesh with its attributes as OBJ, OFF, PLY, STL or GLB.

    V: (n, 3) real array, or a :class:`MeshData` (then F and the attributes come from it).
    F: (m, 3) integer array of triangles, (m, s) of polygons with s corners each (e.g. (k, 4)
    quads), or :class:`Polygons`.
    normals: (l, 3) with F_normal (like F; for Polygons a Polygons or a flat per-corner array),
    or (n, 3) per vertex without F_normal. UV: (k, 2) with F_uv, or (n, 2) without.
    colors: (n, 3) or (n, 4) RGB(A) per vertex; face_colors: (m, 3) or (m, 4) per face (per
    polygon for Polygons); floats in [0, 1], or uint8 arrays of 0..255.
    format: overrides the extension. binary: default True for PLY and STL, False for OFF;
    OBJ is always text, GLB always binary. Text is written in the shortest form that reads
    back to the same float64 (exact round trip); binary PLY stores float64 (colours as uchar
    when all are multiples of 1/255); binary STL, binary OFF and GLB store float32 (as those
    formats prescribe). big_endian: binary PLY only.
    Raises InputError for bad arrays (shape, dtype, non-finite values, colours outside [0, 1],
    indices out of range), for an attribute the format cannot hold (naming the attribute and a
    format that can; see the table in this module's docstring) or a file that cannot be
    written. The arrays are not modified.
    """
    if isinstance(V, MeshData):
        given = [name for name, value in (("F", F), ("normals", normals), ("F_normal", F_normal),
                                          ("UV", UV), ("F_uv", F_uv), ("colors", colors),
                                          ("face_colors", face_colors)) if value is not None]
        if given:
            raise InputError(f"write_mesh(path, mesh): {', '.join(given)} given as well as a MeshData")
        mesh = V
        V, F = mesh.V, mesh.F
        normals, F_normal, UV, F_uv = mesh.normals, mesh.F_normal, mesh.UV, mesh.F_uv
        colors, face_colors = mesh.colors, mesh.face_colors
    if F is None:
        raise InputError("write_mesh: F (the faces) is missing")
    colors, face_colors = _unit_colors(colors), _unit_colors(face_colors)
    fmt = _resolved_format(path, format)
    faces, offsets = _polygon_arrays(F)
    if offsets is not None:
        F_uv = _corner_column(F_uv, "F_uv") if F_uv is not None else None
        F_normal = _corner_column(F_normal, "F_normal") if F_normal is not None else None
    if fmt == "glb":
        if binary is False:
            raise InputError(f"{os.fsdecode(path)}: GLB files are binary (binary=False asks for text)")
        gltf.write_glb(path, _core.checked_mesh(os.fsdecode(path), V, faces, offsets, UV, F_uv,
                                                normals, F_normal, colors, face_colors, "glb"))
        return
    if binary is None:
        binary = _BINARY_BY_DEFAULT.get(fmt, False)
    _core.write_mesh(os.fsdecode(path), V, faces, offsets, UV, F_uv, normals, F_normal, colors,
                     face_colors, _format(format), bool(binary), bool(big_endian))


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
    path = os.fsdecode(path)
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
    P = np.array(coordinates, dtype=np.float64).reshape(-1, 2)
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
        return PlanarGraph(P, segments, holes)
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
        return PlanarGraph(P, segments, holes)
    holes = np.array([numbers(*take("hole list", 3), float, "hole list")[1:3] for _ in range(h)],
                     dtype=np.float64).reshape(-1, 2)
    return PlanarGraph(P, segments, holes)
