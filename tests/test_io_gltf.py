"""glTF binary (.glb) reading and writing (meshsmith.io.gltf): round trips, agreement with trimesh
in both directions, the other primitive modes and layouts, and malformed files."""
from __future__ import annotations

import base64
import json
import struct

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import meshsmith
from meshsmith import datasets, io
from meshsmith.io import Polygons, SkippedDataWarning

F32 = 6e-8


def attributes(seed=0):
    V, F = datasets.icosphere(2)
    rng = np.random.default_rng(seed)
    return V, F, V / np.linalg.norm(V, axis=1, keepdims=True), rng.uniform(size=(len(V), 2)), \
        rng.integers(0, 256, size=(len(V), 4)).astype(np.uint8)


def glb(document: dict, blob: bytes = b"") -> bytes:
    """A GLB file of `document` and the binary chunk `blob`."""
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    blob += b"\0" * (-len(blob) % 4)
    chunks = struct.pack("<2I", len(text), 0x4E4F534A) + text
    if blob:
        chunks += struct.pack("<2I", len(blob), 0x004E4942) + blob
    return struct.pack("<3I", 0x46546C67, 2, 12 + len(chunks)) + chunks


def triangle_document(mode=4, indices=True, extra=None):
    """Four vertices in a strip-friendly order, as POSITION (+ indices 0 1 2 3 as uint16)."""
    P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], np.float32)
    blob = P.tobytes()
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 48}]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"}]
    primitive = {"attributes": {"POSITION": 0}, "mode": mode}
    if indices:
        index_data = np.array([0, 1, 2, 3, 0, 0], np.uint16).tobytes()  # 4 used, padded
        views.append({"buffer": 0, "byteOffset": 48, "byteLength": 12})
        accessors.append({"bufferView": 1, "componentType": 5123, "count": 4 if mode != 4 else 3, "type": "SCALAR"})
        primitive["indices"] = 1
        blob += index_data
    document = {"asset": {"version": "2.0"}, "meshes": [{"primitives": [primitive]}],
                "accessors": accessors, "bufferViews": views, "buffers": [{"byteLength": len(blob)}]}
    document.update(extra or {})
    return document, blob


def test_round_trip_per_vertex_is_the_same_mesh(tmp_path):
    V, F, N, UV, C = attributes()
    io.write_mesh(tmp_path / "m.glb", V, F, normals=N, UV=UV, colors=C)
    back = io.read_mesh(tmp_path / "m.glb", return_attributes=True)
    np.testing.assert_array_equal(back.F, F)
    np.testing.assert_array_equal(back.V, V.astype(np.float32))  # float32, as glTF stores
    np.testing.assert_array_equal(back.normals, N.astype(np.float32))
    np.testing.assert_array_equal(back.F_normal, F)
    np.testing.assert_allclose(back.UV, UV, rtol=0, atol=F32)
    np.testing.assert_array_equal(back.colors, C / 255.0)  # 8-bit colours stored as normalized uint8
    document = json.loads((tmp_path / "m.glb").read_bytes()[20:20 + struct.unpack_from("<I", (tmp_path / "m.glb").read_bytes(), 12)[0]])
    color = document["accessors"][document["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"]]
    assert color["componentType"] == 5121 and color["normalized"] and color["type"] == "VEC4"
    position = document["accessors"][0]
    np.testing.assert_allclose(position["min"], V.min(axis=0), atol=F32)
    np.testing.assert_allclose(position["max"], V.max(axis=0), atol=F32)


def test_unreferenced_vertices_and_polygons(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [5, 5, 5]], float)  # vertex 4 unused
    io.write_mesh(tmp_path / "q.glb", V, Polygons.from_list([[0, 1, 2, 3]]))
    back_V, back_F = io.read_mesh(tmp_path / "q.glb")
    np.testing.assert_array_equal(back_V, V)
    np.testing.assert_array_equal(back_F, [[0, 1, 2], [0, 2, 3]])  # fan
    _, polygons = io.read_mesh(tmp_path / "q.glb", triangulate=False)
    assert polygons.to_list() == [[0, 1, 2], [0, 2, 3]]
    io.write_mesh(tmp_path / "p.glb", V, np.zeros((0, 3), int))  # no faces: POINTS
    back_V, back_F = io.read_mesh(tmp_path / "p.glb")
    np.testing.assert_array_equal(back_V, V)
    assert back_F.shape == (0, 3)


def test_seams_split_for_other_readers_and_weld_for_ours(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    V, F = datasets.cube()
    UV = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float) * 0.5
    F_uv = np.tile([[0, 1, 2], [0, 2, 3]], (len(F) // 2, 1))
    io.write_mesh(tmp_path / "c.glb", V, F, UV=UV, F_uv=F_uv)
    ours = io.read_mesh(tmp_path / "c.glb", return_attributes=True)
    np.testing.assert_array_equal(ours.V, V)
    np.testing.assert_array_equal(ours.F, F)
    np.testing.assert_allclose(ours.UV[ours.F_uv], UV[F_uv], rtol=0, atol=F32)
    theirs = next(iter(trimesh.load(tmp_path / "c.glb", process=False).geometry.values()))
    assert len(theirs.vertices) > len(V)  # split along the seams
    np.testing.assert_array_equal(theirs.vertices[theirs.faces], V[F])
    np.testing.assert_allclose(theirs.visual.uv[theirs.faces], UV[F_uv], rtol=0, atol=F32)


def test_trimesh_reads_ours(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    V, F, N, UV, C = attributes()
    io.write_mesh(tmp_path / "uv.glb", V, F, normals=N, UV=UV)
    theirs = next(iter(trimesh.load(tmp_path / "uv.glb", process=False).geometry.values()))
    np.testing.assert_array_equal(theirs.vertices, V.astype(np.float32))
    np.testing.assert_array_equal(theirs.faces, F)
    np.testing.assert_array_equal(theirs.vertex_normals, N.astype(np.float32))
    np.testing.assert_allclose(theirs.visual.uv, UV, rtol=0, atol=F32)
    io.write_mesh(tmp_path / "c.glb", V, F, colors=C)
    theirs = next(iter(trimesh.load(tmp_path / "c.glb", process=False).geometry.values()))
    np.testing.assert_array_equal(theirs.visual.vertex_colors, C)


def test_we_read_trimesh_exports(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    V, F, N, UV, C = attributes()
    mesh = trimesh.Trimesh(V, F, vertex_normals=N, visual=trimesh.visual.TextureVisuals(uv=UV), process=False)
    mesh.export(tmp_path / "t.glb")
    ours = io.read_mesh(tmp_path / "t.glb", return_attributes=True)
    np.testing.assert_array_equal(ours.V, V.astype(np.float32))
    np.testing.assert_array_equal(ours.F, F)
    np.testing.assert_array_equal(ours.normals[ours.F_normal], N.astype(np.float32)[F])
    np.testing.assert_allclose(ours.UV[ours.F_uv], UV[F], rtol=0, atol=F32)
    trimesh.Trimesh(V, F, vertex_colors=C, process=False).export(tmp_path / "c.glb")
    np.testing.assert_array_equal(io.read_mesh(tmp_path / "c.glb", return_attributes=True).colors, C / 255.0)


def test_scene_with_node_transforms_agrees_with_trimesh(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    V, F = datasets.icosphere(1)
    scene = trimesh.Scene()
    move = trimesh.transformations.rotation_matrix(0.7, [0, 1, 1]) @ trimesh.transformations.translation_matrix([1, 2, 3])
    scene.add_geometry(trimesh.Trimesh(V, F, process=False), transform=move)
    scene.add_geometry(trimesh.Trimesh(2 * V, F, process=False), transform=trimesh.transformations.scale_matrix(0.25))
    scene.export(tmp_path / "s.glb")
    ours_V, ours_F = io.read_mesh(tmp_path / "s.glb")
    assert ours_F.shape == (2 * len(F), 3)
    world = trimesh.load(tmp_path / "s.glb", process=False)
    expected = np.concatenate([g.vertices @ world.graph[name][0][:3, :3].T + world.graph[name][0][:3, 3]
                               for name in world.graph.nodes_geometry
                               for g in [world.geometry[world.graph[name][1]]]])
    key = lambda rows: rows[np.lexsort(np.round(rows, 5).T)]
    np.testing.assert_allclose(key(ours_V), key(expected), rtol=0, atol=1e-6)


@pytest.mark.parametrize("mode,expected", [(5, [[0, 1, 2], [2, 1, 3]]), (6, [[0, 1, 2], [0, 2, 3]])])
def test_strips_and_fans(tmp_path, mode, expected):
    document, blob = triangle_document(mode)
    (tmp_path / "s.glb").write_bytes(glb(document, blob))
    np.testing.assert_array_equal(io.read_mesh(tmp_path / "s.glb")[1], expected)


def test_lines_warn_and_data_uris(tmp_path):
    document, blob = triangle_document(4)
    lines = dict(document["meshes"][0]["primitives"][0], mode=1)
    document["meshes"][0]["primitives"].append(lines)
    (tmp_path / "l.glb").write_bytes(glb(document, blob))
    with pytest.warns(SkippedDataWarning, match="skipped 1 line primitives"):
        V, F = io.read_mesh(tmp_path / "l.glb")
    assert len(V) == 8 and F.tolist() == [[0, 1, 2]]
    document, blob = triangle_document(4, indices=False)
    document["accessors"][0]["count"] = 3
    document["buffers"] = [{"byteLength": len(blob),
                            "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}]
    (tmp_path / "u.glb").write_bytes(glb(document))
    np.testing.assert_array_equal(io.read_mesh(tmp_path / "u.glb")[1], [[0, 1, 2]])


def test_malformed_files(tmp_path):
    V, F, N, UV, C = attributes()
    io.write_mesh(tmp_path / "good.glb", V, F, UV=UV)
    good = (tmp_path / "good.glb").read_bytes()
    document, blob = triangle_document()
    draco = dict(document, extensionsRequired=["KHR_draco_mesh_compression"])
    sparse = json.loads(json.dumps(document))
    sparse["accessors"][0]["sparse"] = {"count": 1}
    far = json.loads(json.dumps(document))
    far["accessors"][0]["count"] = 400
    cases = [(good[:10], r"byte 0: 10 bytes, too short"), (b"glTX" + good[4:], "no 'glTF' magic"),
             (good[:4] + struct.pack("<I", 1) + good[8:], "glTF version 1"),
             (good[:-100], "byte 8: the header announces"),
             (glb(draco, blob), "needs the glTF extensions KHR_draco_mesh_compression"),
             (glb(sparse, blob), r"accessors\[0\]: sparse accessors are not supported"),
             (glb(far, blob), r"accessors\[0\]: 400 elements run past the end"),
             (glb({"asset": {"version": "2.0"}}), "holds no mesh primitive"),
             (glb({"asset": {}, "meshes": [{"primitives": [{"attributes": {"POSITION": 3}}]}]}), r"accessors index 3 out of range"),
             (struct.pack("<3I", 0x46546C67, 2, 24) + struct.pack("<2I", 4, 0x4E4F534A) + b"{{{{",
              "the JSON chunk does not parse")]
    for k, (contents, message) in enumerate(cases):
        path = tmp_path / f"bad{k}.glb"
        path.write_bytes(contents)
        with pytest.raises(meshsmith.InputError, match=message) as caught:
            io.read_mesh(path)
        assert str(path) in str(caught.value)
    with pytest.raises(meshsmith.InputError, match="GLB stores float32 and V holds"):
        io.write_mesh(tmp_path / "huge.glb", V * 1e300, F)
    with pytest.raises(meshsmith.InputError, match="face_colors"):
        io.write_mesh(tmp_path / "fc.glb", V, F, face_colors=np.ones((len(F), 3)))


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_fuzz_mutated_glb(tmp_path, data):
    """Mutated GLB files give InputError or a valid mesh, never another exception."""
    V, F = datasets.icosphere(0)
    path = tmp_path / "seed.glb"
    io.write_mesh(path, V, F, UV=V[:, :2], colors=np.abs(V))
    contents = bytearray(path.read_bytes())
    for _ in range(data.draw(st.integers(1, 6))):
        position = data.draw(st.integers(0, len(contents) - 1))
        contents[position] = data.draw(st.integers(0, 255))
    if data.draw(st.booleans()):
        contents = contents[:data.draw(st.integers(0, len(contents)))]
    mutated = tmp_path / "mutated.glb"
    mutated.write_bytes(bytes(contents))
    try:
        mesh = io.read_mesh(mutated, return_attributes=True)
    except meshsmith.InputError as error:
        assert str(mutated) in str(error)
        return
    assert np.all(np.isfinite(mesh.V)) and mesh.F.shape[1] == 3
    assert len(mesh.F) == 0 or (mesh.F.min() >= 0 and mesh.F.max() < len(mesh.V))


def test_interleaved_strided_buffer_view_and_normalized_uvs(tmp_path):
    """Positions and normals interleaved in one strided view (as Blender writes), uint16 UVs."""
    P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    N = np.array([[0, 0, 1], [0, 0.6, 0.8], [1, 0, 0]], np.float32)
    interleaved = np.hstack([P, N]).astype(np.float32).tobytes()  # 24-byte records
    uv = np.array([[0, 65535], [65535, 65535], [0, 0]], np.uint16).tobytes()  # 12 bytes
    blob = interleaved + uv
    document = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}}]}],
                "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 72, "byteStride": 24},
                                {"buffer": 0, "byteOffset": 72, "byteLength": 12}],
                "accessors": [{"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                              {"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 3, "type": "VEC3"},
                              {"bufferView": 1, "componentType": 5123, "normalized": True, "count": 3, "type": "VEC2"}],
                "buffers": [{"byteLength": len(blob)}]}
    (tmp_path / "i.glb").write_bytes(glb(document, blob))
    data = io.read_mesh(tmp_path / "i.glb", return_attributes=True)
    np.testing.assert_array_equal(data.V, P)
    np.testing.assert_array_equal(data.F, [[0, 1, 2]])  # no indices: consecutive triangles
    np.testing.assert_array_equal(data.normals, N)
    np.testing.assert_array_equal(data.UV, [[0, 0], [1, 0], [0, 1]])  # v flipped back to OBJ's
