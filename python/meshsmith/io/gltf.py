"""glTF 2.0 binary (.glb): read and write triangle meshes with normals, UVs and colours.

A GLB file is a 12-byte header, a JSON chunk that describes the scene, and a binary chunk that
holds the arrays; both are decoded here with ``struct``, ``json`` and numpy (no dependency).
Reached through :func:`meshsmith.io.read_mesh` / :func:`meshsmith.io.write_mesh` on ``.glb``
paths; the functions here work on plain arrays (this module imports nothing else of meshsmith.io).

What is written: one scene, one node, one mesh with one primitive of triangles (polygons are
fan-triangulated, a mesh without faces becomes a POINTS primitive): POSITION (float32, with the
min / max the specification requires), indices (uint32), NORMAL (float32), TEXCOORD_0 (float32,
with a plain white material so that readers such as trimesh keep them) and COLOR_0 (normalized uint8 when every component is a multiple of 1/255, else float32). glTF
texture coordinates start at the top left of the image: V is written as 1 - v and read back as
1 - v, as trimesh and Blender do, so UVs agree with OBJ's to float32 precision.

Vertices and seams. glTF attributes are per vertex. When the normals and UVs are per vertex
(every corner of a vertex has the same value) the file holds the vertices as they are, in
order, unreferenced ones included, and reads back with the same V and F. When they are per
corner (seams of a UV atlas, sharp edges), every distinct (vertex, UV, normal) combination
becomes one glTF vertex: the first n are the input vertices (with their first corner's
attributes) and the copies follow, and an application attribute ``_VERTEX_ORIGIN`` (float32,
exact below 2**24 vertices) gives the input vertex of each. meshsmith's reader uses it to give
back the input V and F, with the UVs and normals per corner; other readers see the split mesh,
which renders the same.

What is read: the triangles (modes 4, 5, 6) of every mesh primitive of the default scene (or of
all meshes when the file has no scene), with each node's transform applied to positions and
normals; POINTS primitives add vertices without faces; lines are skipped with a warning.
Accessors of any component type (normalized integers scaled to [0, 1] or [-1, 1]), strided
buffer views, the binary chunk, data: URIs and external .bin files next to the .glb are read.
Sparse accessors and required extensions other than KHR_mesh_quantization (Draco, meshopt...)
raise InputError.
"""
from __future__ import annotations

import base64
import json
import os
import struct
from typing import Any, NoReturn

import numpy as np

from .._core import InputError
from .._core import io as _core
from .._typing import PathLike

__all__ = ["read_glb", "write_glb"]

_MAGIC, _JSON, _BIN = 0x46546C67, 0x4E4F534A, 0x004E4942
_COMPONENTS = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32,
               5126: np.float32}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_FLOAT32_MAX = float(np.finfo(np.float32).max)
_ORIGIN = "_VERTEX_ORIGIN"


# ----------------------------------------------------------------------------------------------
# Reading

class _File:
    """The parsed JSON and the buffers of a GLB file, with checked access to accessors."""

    def __init__(self, path):
        self.path = os.fsdecode(path)
        if not os.path.exists(self.path):
            self.fail("file does not exist")
        if os.path.isdir(self.path):
            self.fail("is a directory, not a file")
        with open(self.path, "rb") as stream:
            data = stream.read()
        if not data:
            self.fail("file is empty")
        if len(data) < 12:
            self.fail(f"byte 0: {len(data)} bytes, too short for a GLB header (12)")
        magic, version, length = struct.unpack_from("<3I", data)
        if magic != _MAGIC:
            self.fail("byte 0: not a GLB file (no 'glTF' magic)")
        if version != 2:
            self.fail(f"byte 4: glTF version {version} (only 2 is supported)")
        if length > len(data):
            self.fail(f"byte 8: the header announces {length} bytes but the file has {len(data)}")
        chunks, offset = [], 12
        while offset + 8 <= length:
            size, kind = struct.unpack_from("<2I", data, offset)
            if offset + 8 + size > length:
                self.fail(f"byte {offset}: a chunk of {size} bytes runs past the end of the file")
            chunks.append((kind, data[offset + 8:offset + 8 + size], offset + 8))
            offset += 8 + size
        if not chunks or chunks[0][0] != _JSON:
            self.fail("byte 12: the first chunk is not JSON")
        try:
            self.json = json.loads(chunks[0][1].decode("utf-8"))
        except (UnicodeDecodeError, ValueError) as error:
            self.fail(f"byte 20: the JSON chunk does not parse ({error})")
        if not isinstance(self.json, dict):
            self.fail("byte 20: the JSON chunk is not an object")
        self.binary = next((chunk for kind, chunk, _ in chunks[1:] if kind == _BIN), None)
        unsupported = sorted(set(self.list("extensionsRequired")) - {"KHR_mesh_quantization"})
        if unsupported:
            self.fail(f"needs the glTF extensions {', '.join(map(str, unsupported))}, which are not supported")
        self.buffers = [self.load_buffer(i, buffer) for i, buffer in enumerate(self.list("buffers"))]
        self.skipped: dict[str, int] = {}

    def fail(self, message: str) -> NoReturn:
        raise InputError(f"{self.path}: {message}")

    def list(self, key, container=None):
        value = (self.json if container is None else container).get(key, [])
        if not isinstance(value, list):
            self.fail(f"'{key}' is not a list")
        return value

    def item(self, key, index):
        items = self.list(key)
        if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < len(items):
            self.fail(f"{key} index {index!r} out of range (the file has {len(items)})")
        if not isinstance(items[index], dict):
            self.fail(f"{key}[{index}] is not an object")
        return items[index]

    def load_buffer(self, index, buffer):
        if not isinstance(buffer, dict):
            self.fail(f"buffers[{index}] is not an object")
        uri = buffer.get("uri")
        if uri is None:
            if self.binary is None:
                self.fail(f"buffers[{index}] refers to the binary chunk, which the file lacks")
            data = self.binary
        elif isinstance(uri, str) and uri.startswith("data:"):
            try:
                data = base64.b64decode(uri.split(",", 1)[1])
            except (IndexError, ValueError):
                self.fail(f"buffers[{index}]: unreadable data URI")
        elif isinstance(uri, str):
            external = os.path.join(os.path.dirname(self.path), uri)
            if not os.path.isfile(external):
                self.fail(f"buffers[{index}]: the file {uri} does not exist")
            with open(external, "rb") as stream:
                data = stream.read()
        else:
            self.fail(f"buffers[{index}]: 'uri' is not a string")
        length = buffer.get("byteLength")
        if not isinstance(length, int) or length > len(data):
            self.fail(f"buffers[{index}]: byteLength {length!r} but {len(data)} bytes are there")
        return data

    def accessor(self, index, types):
        """Accessor `index` as a float64 (count, width) array (uint32 for indices)."""
        accessor = self.item("accessors", index)
        where = f"accessors[{index}]"
        if "sparse" in accessor:
            self.fail(f"{where}: sparse accessors are not supported")
        kind, component = accessor.get("type"), accessor.get("componentType")
        if kind not in types:
            self.fail(f"{where}: type {kind!r} where {' or '.join(types)} is expected")
        if component not in _COMPONENTS:
            self.fail(f"{where}: unknown componentType {component!r}")
        dtype = np.dtype(_COMPONENTS[component]).newbyteorder("<")
        width, count = _WIDTH[kind], accessor.get("count")
        if not isinstance(count, int) or count < 1:
            self.fail(f"{where}: count {count!r} is not a positive integer")
        if "bufferView" not in accessor:  # all zeros, as the specification says
            return np.zeros((count, width))
        view = self.item("bufferViews", accessor["bufferView"])
        self.item("buffers", view.get("buffer"))  # checks the index
        buffer = self.buffers[view["buffer"]]
        start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
        element = dtype.itemsize * width
        stride = view.get("byteStride") or element
        if not all(isinstance(v, int) and v >= 0 for v in (start, stride)) or stride < element:
            self.fail(f"{where}: bad byteOffset or byteStride")
        end = start + stride * (count - 1) + element
        if end > view.get("byteOffset", 0) + view.get("byteLength", 0) or end > len(buffer):
            self.fail(f"{where}: {count} elements run past the end of their buffer view")
        raw = np.ndarray((count, width), dtype=dtype, buffer=buffer, offset=start,
                         strides=(stride, dtype.itemsize))
        if kind == "SCALAR" and "SCALAR" in types and component in (5121, 5123, 5125) \
                and not accessor.get("normalized"):
            return raw.astype(np.int64)
        values = raw.astype(np.float64)
        if accessor.get("normalized") and dtype.kind in "iu":
            values /= np.iinfo(dtype).max
            np.maximum(values, -1.0, out=values)
        if not np.all(np.isfinite(values)):
            self.fail(f"{where}: non-finite values")
        return values

    def skip(self, what):
        self.skipped[what] = self.skipped.get(what, 0) + 1


def _node_matrix(node):
    """The 4x4 local transform of a node: its matrix, or translation * rotation * scale."""
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
    matrix = np.eye(4)
    x, y, z, w = node.get("rotation", (0.0, 0.0, 0.0, 1.0))
    rotation = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    matrix[:3, :3] = rotation * np.array(node.get("scale", (1.0, 1.0, 1.0)), dtype=np.float64)
    matrix[:3, 3] = node.get("translation", (0.0, 0.0, 0.0))
    return matrix


def _mesh_instances(file):
    """(mesh index, world matrix) of every mesh the default scene shows."""
    scenes = file.list("scenes")
    if not scenes:
        return [(index, np.eye(4)) for index in range(len(file.list("meshes")))]
    scene = file.item("scenes", file.json.get("scene", 0))
    instances, stack = [], [(node, np.eye(4), 0) for node in file.list("nodes", scene)]
    while stack:
        index, parent, depth = stack.pop()
        if depth > 64:
            file.fail("the node hierarchy is deeper than 64 levels (a cycle?)")
        node = file.item("nodes", index)
        try:
            world = parent @ _node_matrix(node)
        except (TypeError, ValueError):
            file.fail(f"nodes[{index}]: unreadable transform")
        if "mesh" in node:
            instances.append((node["mesh"], world))
        stack.extend((child, world, depth + 1) for child in reversed(file.list("children", node)))
    return instances


def _triangles(file, primitive, count):
    """(t, 3) int64 triangles of a primitive (modes 4, 5, 6), or None for points and lines."""
    mode = primitive.get("mode", 4)
    if "indices" in primitive:
        indices = file.accessor(primitive["indices"], ("SCALAR",)).reshape(-1)
        if indices.dtype.kind == "f":
            file.fail("primitive indices are not integers")
    else:
        indices = np.arange(count, dtype=np.int64)
    if len(indices) and (indices.min() < 0 or indices.max() >= count):
        file.fail(f"a primitive index is outside [0, {count})")
    if mode == 0:
        return np.zeros((0, 3), np.int64)
    if mode in (1, 2, 3):
        file.skip("line primitives")
        return np.zeros((0, 3), np.int64)
    if mode == 4:
        if len(indices) % 3:
            file.fail(f"a triangle primitive has {len(indices)} indices, not a multiple of 3")
        return indices.reshape(-1, 3).astype(np.int64)
    if mode not in (5, 6) or len(indices) < 3:
        if mode not in (5, 6):
            file.fail(f"unknown primitive mode {mode!r}")
        return np.zeros((0, 3), np.int64)
    k = np.arange(len(indices) - 2)
    if mode == 5:  # strip: odd triangles swap their first two corners to keep the orientation
        first = np.where(k % 2 == 0, indices[k], indices[k + 1])
        second = np.where(k % 2 == 0, indices[k + 1], indices[k])
        triangles = np.column_stack([first, second, indices[k + 2]])
    else:  # fan
        triangles = np.column_stack([np.full(len(k), indices[0]), indices[k + 1], indices[k + 2]])
    degenerate = ((triangles[:, 0] == triangles[:, 1]) | (triangles[:, 1] == triangles[:, 2])
                  | (triangles[:, 0] == triangles[:, 2]))
    return triangles[~degenerate].astype(np.int64)


def read_glb(path: PathLike) -> tuple[dict[str, Any], list[str]]:
    """Read a GLB file (see the module docstring).

    Returns (fields, warnings): fields holds the :class:`meshsmith.io.MeshData` fields the file
    has (V, F; normals with F_normal, UV with F_uv, colors), warnings what was skipped.
    Raises InputError naming the file (and the byte or JSON element) for anything malformed.
    """
    path = os.fsdecode(path)
    try:
        return _read_glb(path)
    except InputError:
        raise
    except (KeyError, TypeError, ValueError, IndexError, AttributeError, OverflowError,
            struct.error, np.linalg.LinAlgError) as error:
        raise InputError(f"{path}: malformed glTF ({type(error).__name__}: {error})") from None


def _read_glb(path):
    file = _File(path)
    parts = []
    for mesh_index, world in _mesh_instances(file):
        mesh = file.item("meshes", mesh_index)
        for primitive in file.list("primitives", mesh):
            if not isinstance(primitive, dict) or not isinstance(primitive.get("attributes"), dict):
                file.fail(f"meshes[{mesh_index}]: a primitive without attributes")
            attributes = primitive["attributes"]
            if "POSITION" not in attributes:
                file.fail(f"meshes[{mesh_index}]: a primitive without POSITION")
            P = file.accessor(attributes["POSITION"], ("VEC3",))
            part = {"V": P, "F": _triangles(file, primitive, len(P))}
            for name, key, types in (("normals", "NORMAL", ("VEC3",)), ("UV", "TEXCOORD_0", ("VEC2",)),
                                     ("colors", "COLOR_0", ("VEC3", "VEC4")),
                                     ("origin", _ORIGIN, ("SCALAR",))):
                if key in attributes:
                    values = file.accessor(attributes[key], types)
                    if len(values) != len(P):
                        file.fail(f"meshes[{mesh_index}]: {key} has {len(values)} rows, POSITION {len(P)}")
                    part[name] = values
            if "UV" in part:
                part["UV"] = np.column_stack([part["UV"][:, 0], 1.0 - part["UV"][:, 1]])
            if not np.array_equal(world, np.eye(4)):
                part["V"] = P @ world[:3, :3].T + world[:3, 3]
                if "normals" in part:
                    normals = part["normals"] @ np.linalg.inv(world[:3, :3])
                    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
                    part["normals"] = np.divide(normals, lengths, out=normals, where=lengths > 0)
            parts.append(part)
    skipped = [f"skipped {count} {what} (a mesh holds triangles)" for what, count in file.skipped.items()]
    if not parts:
        file.fail("the file holds no mesh primitive")
    if len(parts) == 1 and "origin" in parts[0]:
        welded = _weld(parts[0])
        if welded is not None:
            return welded, skipped
    return _concatenate(parts), skipped


def _weld(part):
    """The input mesh of a file that meshsmith wrote with split seams: V and F of the input
    vertices, UVs and normals per corner. None when `_VERTEX_ORIGIN` does not describe a split
    (then the split mesh is returned as it is)."""
    origin = part["origin"].reshape(-1)
    n = int(origin.max()) + 1 if len(origin) else 0
    if not (np.all(origin == np.round(origin)) and origin.min() >= 0 and n <= len(origin)
            and np.array_equal(origin[:n], np.arange(n))):
        return None
    origin = origin.astype(np.int64)
    V = part["V"]
    if not np.array_equal(V[origin], V):
        return None
    F = part["F"]
    welded = {"V": V[:n], "F": origin[F]}
    for name, corners in (("normals", "F_normal"), ("UV", "F_uv")):
        if name in part:
            welded[name], welded[corners] = part[name], F
    if "colors" in part:
        welded["colors"] = part["colors"][:n]
    return welded


def _concatenate(parts):
    """One MeshData's fields from the primitives: vertices stacked, attributes per vertex
    (corners of a primitive without one get -1; missing colours are white, glTF's default)."""
    starts = np.cumsum([0] + [len(part["V"]) for part in parts])
    mesh = {"V": np.concatenate([part["V"] for part in parts]),
            "F": np.concatenate([part["F"] + start for part, start in zip(parts, starts)])}
    for name, corners, width in (("normals", "F_normal", 3), ("UV", "F_uv", 2)):
        if any(name in part for part in parts):
            mesh[name] = np.concatenate([part.get(name, np.zeros((len(part["V"]), width)))
                                         for part in parts])
            mesh[corners] = np.concatenate([part["F"] + start if name in part
                                            else np.full_like(part["F"], -1)
                                            for part, start in zip(parts, starts)])
    if any("colors" in part for part in parts):
        width = max(part["colors"].shape[1] for part in parts if "colors" in part)
        mesh["colors"] = np.concatenate([
            np.column_stack([part["colors"], np.ones((len(part["V"]), width - part["colors"].shape[1]))])
            if "colors" in part else np.ones((len(part["V"]), width)) for part in parts])
    return mesh


# ----------------------------------------------------------------------------------------------
# Writing

def _per_vertex(n, F, values, F_values):
    """values indexed per vertex (n rows) when the corners of each vertex agree, else None."""
    out = np.zeros((n, values.shape[1]))
    chosen = np.full(n, -1, dtype=np.int64)
    corners, indices = F.reshape(-1), F_values.reshape(-1)
    chosen[corners[::-1]] = indices[::-1]  # the first corner of each vertex wins
    used = chosen >= 0
    out[used] = values[chosen[used]]
    return out if np.array_equal(out[corners], values[indices]) else None


def write_glb(path: PathLike, mesh: dict[str, Any]) -> None:
    """Write a GLB file (see the module docstring).

    mesh: the arrays of ``meshsmith._core.io.checked_mesh(..., format="glb")``, which has made
    the checks of every writer (shapes, finite values, index ranges, colours in [0, 1]) and
    refused what GLB cannot hold (face colours, attributes on only some corners): V, offsets
    and indices of the polygons, UV / N with their flat corner indices (or None), colors.
    Raises InputError for values beyond float32 or a file that cannot be written.
    """
    path = os.fsdecode(path)
    V = mesh["V"]
    if len(V) == 0:
        raise InputError(f"{path}: cannot write: a GLB file needs at least one vertex")
    for name in ("V", "N", "UV"):
        if mesh[name] is not None and len(mesh[name]) and np.abs(mesh[name]).max() > _FLOAT32_MAX:
            raise InputError(f"{path}: cannot write: GLB stores float32 and {name} holds "
                             f"{np.abs(mesh[name]).max():g}")
    offsets = mesh["offsets"].reshape(-1, 1)

    def triangles(indices):
        return _core.triangulate_fan(offsets, indices.reshape(-1, 1))

    T = triangles(mesh["indices"])

    n = len(V)
    attributes = {}  # name: (values per glTF vertex, triangles into them)
    for name, key, indices in (("NORMAL", "N", "normal_indices"), ("TEXCOORD_0", "UV", "uv_indices")):
        if mesh[key] is not None:
            T_values = triangles(mesh[indices]) if mesh[indices] is not None else T
            attributes[name] = (mesh[key], T_values)
    per_vertex = {name: _per_vertex(n, T, values, T_values) for name, (values, T_values) in attributes.items()}
    origin = None
    if all(values is not None for values in per_vertex.values()):
        columns = per_vertex
    else:  # split: one glTF vertex per distinct (vertex, uv, normal) of the corners
        keys = np.column_stack([T.reshape(-1)] + [T_values.reshape(-1) for _, T_values in attributes.values()])
        unique, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
        # The input vertices keep their places (with their first corner's attributes); the
        # copies follow in the order of their first corner.
        by_first = np.argsort(first, kind="stable")
        primary = by_first[np.unique(unique[by_first, 0], return_index=True)[1]]
        is_primary = np.zeros(len(unique), bool)
        is_primary[primary] = True
        copies = by_first[~is_primary[by_first]]
        count = n + len(copies)
        if count > 2 ** 24:
            raise InputError(f"{path}: cannot write: splitting the seams gives {count} vertices, "
                             "more than GLB's float32 vertex origins can number (2**24)")
        slot = np.empty(len(unique), np.int64)
        slot[primary] = unique[primary, 0]
        slot[copies] = n + np.arange(len(copies))
        origin = np.concatenate([np.arange(n, dtype=np.int64), unique[copies, 0]])
        columns = {}
        for k, (name, (values, _)) in enumerate(attributes.items()):
            column = np.zeros((count, values.shape[1]))
            column[slot] = values[unique[:, k + 1]]
            columns[name] = column
        T = slot[np.asarray(inverse).reshape(-1)].reshape(-1, 3)
        V = V[origin]
        if mesh["colors"] is not None:
            mesh["colors"] = mesh["colors"][origin]
    if "TEXCOORD_0" in columns:
        uv = columns["TEXCOORD_0"]
        columns["TEXCOORD_0"] = np.column_stack([uv[:, 0], 1.0 - uv[:, 1]])
    _write(path, V, T, columns, mesh["colors"], origin)


def _write(path, V, T, columns, colors, origin):
    """Lays out the buffer and the JSON of one primitive and writes the file."""
    blob, views, accessors = bytearray(), [], []

    def add(array, component, kind, target=None, normalized=False, bounds=False):
        data = np.ascontiguousarray(array, dtype=_COMPONENTS[component]).tobytes()
        while len(blob) % 4:
            blob.append(0)
        view = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)}
        if target:
            view["target"] = target
        blob.extend(data)
        views.append(view)
        accessor = {"bufferView": len(views) - 1, "componentType": component,
                    "count": int(len(array)), "type": kind}
        if normalized:
            accessor["normalized"] = True
        if bounds:
            values = np.asarray(array, dtype=np.float32).reshape(len(array), -1)
            accessor["min"] = values.min(axis=0).astype(float).tolist()
            accessor["max"] = values.max(axis=0).astype(float).tolist()
        accessors.append(accessor)
        return len(accessors) - 1

    attributes = {"POSITION": add(V, 5126, "VEC3", 34962, bounds=True)}
    if "NORMAL" in columns:
        attributes["NORMAL"] = add(columns["NORMAL"], 5126, "VEC3", 34962)
    if "TEXCOORD_0" in columns:
        attributes["TEXCOORD_0"] = add(columns["TEXCOORD_0"], 5126, "VEC2", 34962)
    if colors is not None:
        kind = "VEC3" if colors.shape[1] == 3 else "VEC4"
        bytes_ = np.round(colors * 255.0)
        if np.array_equal(bytes_ / 255.0, colors):
            attributes["COLOR_0"] = add(bytes_, 5121, kind, 34962, normalized=True)
        else:
            attributes["COLOR_0"] = add(colors, 5126, kind, 34962)
    if origin is not None:
        attributes[_ORIGIN] = add(origin, 5126, "SCALAR", 34962)
    primitive: dict[str, Any] = {"attributes": attributes}
    document = {"asset": {"version": "2.0", "generator": "meshsmith"}, "scene": 0,
                "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                "meshes": [{"primitives": [primitive]}]}
    if "TEXCOORD_0" in columns:  # a plain material, so that readers (trimesh) keep the UVs
        document["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0]}}]
        primitive["material"] = 0
    if len(T):
        primitive["indices"] = add(T.reshape(-1), 5125, "SCALAR", 34963)
        primitive["mode"] = 4
    else:
        primitive["mode"] = 0  # no faces: the vertices as points
    while len(blob) % 4:
        blob.append(0)
    document.update(accessors=accessors, bufferViews=views, buffers=[{"byteLength": len(blob)}])
    text = json.dumps(document, separators=(",", ":")).encode("utf-8")
    text += b" " * (-len(text) % 4)
    length = 12 + 8 + len(text) + 8 + len(blob)
    contents = (struct.pack("<3I", _MAGIC, 2, length) + struct.pack("<2I", len(text), _JSON) + text
                + struct.pack("<2I", len(blob), _BIN) + bytes(blob))
    try:
        with open(path, "wb") as stream:
            stream.write(contents)
    except OSError as error:
        raise InputError(f"{path}: cannot open file for writing: {error.strerror}") from None
