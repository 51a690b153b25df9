"""Attributes that survive (issue 14 part 3): MeshData, normals / UVs / colours in every format
that can hold them (bit for bit; float32 formats to float32 precision), InputError naming the
attribute where a format cannot, OBJ statements skipped with counted warnings, OFF colours and
binary OFF in both byte orders, PLY files as other tools write them, and the shared spot.obj."""
from __future__ import annotations

import pickle
import re
import struct
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import meshsmith
from meshsmith import datasets, io
from meshsmith.io import MeshData, Polygons, SkippedDataWarning

F32 = 6e-8  # float32 rounding of values in [-1, 1] (and of 1 - v for the GLB's flipped V)


def sphere_with_attributes(seed=0):
    """An icosphere with per-vertex normals, UVs, RGBA colours and per-face RGB colours."""
    V, F = datasets.icosphere(2)
    rng = np.random.default_rng(seed)
    return dict(V=V, F=F, normals=V / np.linalg.norm(V, axis=1, keepdims=True),
                UV=rng.uniform(size=(len(V), 2)),
                colors=rng.integers(0, 256, size=(len(V), 4)) / 255.0,
                face_colors=rng.uniform(size=(len(F), 3)))


def seamed_mesh():
    """A cube whose UVs and normals are per corner (a UV atlas and flat-shaded faces)."""
    V, F = datasets.cube()
    UV = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float) * 0.25
    F_uv = np.tile([[0, 1, 2], [0, 2, 3]], (len(F) // 2, 1))
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    normals = np.cross(e1, e2)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    F_normal = np.repeat(np.arange(len(F)), 3).reshape(-1, 3)
    return V, F, UV, F_uv, normals, F_normal


def assert_same_mesh(back, V, F, atol=0.0):
    np.testing.assert_array_equal(back.F, F)
    np.testing.assert_allclose(back.V, V, rtol=0, atol=atol)


# Which attributes each mode writes, and with what tolerance they read back.
MODES = [("obj", {}, 0.0, {"normals", "UV", "colors"}),
         ("ply", {}, 0.0, {"normals", "UV", "colors", "face_colors"}),
         ("ply", {"binary": False}, 0.0, {"normals", "UV", "colors", "face_colors"}),
         ("ply", {"big_endian": True}, 0.0, {"normals", "UV", "colors", "face_colors"}),
         ("off", {}, 0.0, {"normals", "UV", "colors", "face_colors"}),
         ("off", {"binary": True}, F32, {"normals", "UV", "colors", "face_colors"}),
         ("glb", {}, F32, {"normals", "UV", "colors"})]


@pytest.mark.parametrize("ext,kwargs,atol,holds", MODES, ids=[f"{m[0]}-{m[1]}" for m in MODES])
def test_per_vertex_attributes_round_trip(tmp_path, ext, kwargs, atol, holds):
    mesh = sphere_with_attributes()
    if ext == "obj":
        mesh["colors"] = mesh["colors"][:, :3]  # OBJ colours are r g b
    given = {name: mesh[name] for name in holds}
    before = {name: value.copy() for name, value in mesh.items()}
    path = tmp_path / f"m.{ext}"
    io.write_mesh(path, mesh["V"], mesh["F"], **given, **kwargs)
    back = io.read_mesh(path, return_attributes=True)
    assert set(back.attributes) == holds
    assert_same_mesh(back, mesh["V"], mesh["F"], atol)
    np.testing.assert_allclose(back.normals[back.F_normal], mesh["normals"][mesh["F"]], rtol=0, atol=atol)
    np.testing.assert_allclose(back.UV[back.F_uv], mesh["UV"][mesh["F"]], rtol=0, atol=atol)
    colors = mesh["colors"]
    if ext == "off" and kwargs.get("binary"):
        assert back.colors.shape == (len(colors), 4)  # binary OFF colours are always RGBA
    np.testing.assert_allclose(back.colors[:, :colors.shape[1]], colors, rtol=0, atol=atol)
    if "face_colors" in holds:
        np.testing.assert_allclose(back.face_colors, mesh["face_colors"], rtol=0, atol=atol)
    if atol == 0.0:  # the exact formats: bit for bit
        assert np.array_equal(back.V, mesh["V"]) and np.array_equal(back.colors, colors)
    for name, value in before.items():  # the caller's arrays are untouched
        assert np.array_equal(mesh[name][..., :value.shape[-1]] if name == "colors" else mesh[name], value)


@pytest.mark.parametrize("ext,atol", [("obj", 0.0), ("ply", 0.0), ("glb", F32)])
def test_per_corner_uvs_round_trip(tmp_path, ext, atol):
    V, F, UV, F_uv, normals, F_normal = seamed_mesh()
    extra = {"normals": normals, "F_normal": F_normal} if ext != "ply" else {}
    io.write_mesh(tmp_path / f"c.{ext}", V, F, UV=UV, F_uv=F_uv, **extra)
    back = io.read_mesh(tmp_path / f"c.{ext}", return_attributes=True)
    assert_same_mesh(back, V, F, atol)  # GLB: the seams split and welded back
    np.testing.assert_allclose(back.UV[back.F_uv], UV[F_uv], rtol=0, atol=atol)
    if extra:
        np.testing.assert_allclose(back.normals[back.F_normal], normals[F_normal], rtol=0, atol=atol)
    if ext == "obj":  # OBJ keeps the indexing itself
        np.testing.assert_array_equal(back.F_uv, F_uv)
        np.testing.assert_array_equal(back.UV, UV)
    if ext == "ply":
        assert b"property list uchar double texcoord" in (tmp_path / "c.ply").read_bytes()[:600]


def test_ply_polygons_with_texcoords_and_face_colours(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0.5, 0]], float)
    polygons = Polygons.from_list([[0, 1, 2, 3], [1, 4, 2]])
    UV = np.array([[0, 0], [0.5, 0], [0.5, 0.5], [0, 0.5], [0.9, 0.1], [0.8, 0.2], [0.7, 0.3]])
    F_uv = np.array([0, 1, 2, 3, 4, 5, 6])
    face_colors = np.array([[1, 0, 0], [0, 0.5, 1]])
    for binary in (False, True):
        path = tmp_path / f"p{int(binary)}.ply"
        io.write_mesh(path, V, polygons, UV=UV, F_uv=F_uv, face_colors=face_colors, binary=binary)
        back = io.read_mesh(path, triangulate=False, return_attributes=True)
        assert back.F.to_list() == polygons.to_list()
        np.testing.assert_array_equal(back.UV[back.F_uv.indices], UV[F_uv])
        np.testing.assert_array_equal(back.face_colors, face_colors)
        tri = io.read_mesh(path, return_attributes=True)  # a polygon's colour for each fan triangle
        np.testing.assert_array_equal(tri.face_colors, face_colors[[0, 0, 1]])
        np.testing.assert_array_equal(tri.UV[tri.F_uv], UV[Polygons(polygons.offsets, F_uv).triangulate()])


@pytest.mark.parametrize("ext,attribute,message", [
    ("stl", "normals", r"cannot write normals: STL cannot hold them \(.*write OBJ"),
    ("stl", "UV", r"cannot write UV \(texture coordinates\): STL cannot hold them \(write OBJ, PLY, OFF or GLB\)"),
    ("stl", "colors", r"cannot write colors \(vertex colours\): STL"),
    ("stl", "face_colors", r"cannot write face_colors \(face colours\): STL.*PLY or OFF"),
    ("obj", "face_colors", r"cannot write face_colors \(face colours\): OBJ cannot hold them \(write PLY or OFF\)"),
    ("obj", "colors", r"cannot write colors with alpha \(row \d+ has alpha .*\): OBJ.*PLY, OFF or GLB"),
    ("glb", "face_colors", r"cannot write face_colors \(face colours\): GLB.*PLY or OFF"),
    ("ply", "corner_normals", r"cannot write normals \(per corner\): PLY cannot hold them \(.*write OBJ or GLB\)"),
    ("off", "corner_normals", r"cannot write normals \(per corner\): OFF"),
    ("off", "corner_uv", r"cannot write UV \(per-corner texture coordinates\): OFF.*write OBJ, PLY or GLB"),
])
def test_formats_refuse_what_they_cannot_hold(tmp_path, ext, attribute, message):
    mesh = sphere_with_attributes()
    V, F = mesh["V"], mesh["F"]
    if attribute == "corner_normals":
        V, F, _, _, normals, F_normal = seamed_mesh()
        given = {"normals": normals, "F_normal": F_normal}
    elif attribute == "corner_uv":
        V, F, UV, F_uv, _, _ = seamed_mesh()
        given = {"UV": UV, "F_uv": F_uv}
    else:
        given = {attribute: mesh[attribute]}
    path = tmp_path / f"m.{ext}"
    with pytest.raises(meshsmith.InputError, match=message):
        io.write_mesh(path, V, F, **given)
    assert not path.exists()  # refused before anything is written


def test_bad_attribute_arrays(tmp_path):
    mesh = sphere_with_attributes()
    V, F = mesh["V"], mesh["F"]
    cases = [({"colors": mesh["colors"] * 2}, r"colors row 0 holds .* \(colour components are in \[0, 1\]\)"),
             ({"colors": mesh["colors"][:5]}, r"colors has shape \(5, 4\); expected \(162, 3\) or \(162, 4\)"),
             ({"colors": mesh["colors"][:, :2]}, r"colors.*RGB \(n, 3\) or RGBA \(n, 4\)"),
             ({"face_colors": mesh["face_colors"][:3]}, r"face_colors has shape \(3, 3\)"),
             ({"UV": mesh["UV"][:7]}, r"UV has 7 rows and no corner indices \(F_uv\), but there are 162 vertices"),
             ({"normals": mesh["normals"][:7]}, r"N has 7 rows and no corner indices"),
             ({"UV": mesh["UV"], "F_uv": F + 1000}, r"face 0 has texture coordinate index \d+ outside")]
    for given, message in cases:
        for ext in ("ply", "obj", "glb"):
            with pytest.raises(meshsmith.InputError, match=message):
                io.write_mesh(tmp_path / f"m.{ext}", V, F, **given)
    assert not any(tmp_path.iterdir())


def test_uint8_colours_and_opaque_alpha_in_obj(tmp_path):
    mesh = sphere_with_attributes()
    colors8 = np.round(mesh["colors"] * 255).astype(np.uint8)
    colors8[:, 3] = 255  # opaque: OBJ writes r g b
    io.write_mesh(tmp_path / "c.obj", mesh["V"], mesh["F"], colors=colors8)
    back = io.read_mesh(tmp_path / "c.obj", return_attributes=True)
    np.testing.assert_array_equal(back.colors, colors8[:, :3] / 255.0)
    io.write_mesh(tmp_path / "c.ply", mesh["V"], mesh["F"], colors=colors8)
    assert b"property uchar red" in (tmp_path / "c.ply").read_bytes()[:400]
    np.testing.assert_array_equal(io.read_mesh(tmp_path / "c.ply", return_attributes=True).colors, colors8 / 255.0)
    # Colours that are not 8-bit values are written as doubles, exactly.
    io.write_mesh(tmp_path / "d.ply", mesh["V"], mesh["F"], colors=np.full((len(mesh["V"]), 3), 0.1))
    assert b"property double red" in (tmp_path / "d.ply").read_bytes()[:400]
    np.testing.assert_array_equal(io.read_mesh(tmp_path / "d.ply", return_attributes=True).colors, 0.1)


def test_mesh_data_unpacks_pickles_and_writes(tmp_path):
    mesh = sphere_with_attributes()
    io.write_mesh(tmp_path / "m.ply", mesh["V"], mesh["F"], normals=mesh["normals"], colors=mesh["colors"])
    data = io.read_mesh(tmp_path / "m.ply", return_attributes=True)
    V, F = data
    assert V is data.V and F is data.F
    assert data.attributes == ["normals", "colors"] and data.UV is None and data.face_colors is None
    function, (arrays,) = data.__reduce__()
    assert all(isinstance(value, np.ndarray) for value in arrays.values())
    back = pickle.loads(pickle.dumps(data))
    for name in ("V", "F", "normals", "F_normal", "colors"):
        np.testing.assert_array_equal(getattr(back, name), getattr(data, name))
    assert back.UV is None
    polygons = io.read_mesh(tmp_path / "m.ply", triangulate=False, return_attributes=True)
    again = pickle.loads(pickle.dumps(polygons))
    assert isinstance(again.F, Polygons) and again.F.to_list() == polygons.F.to_list()
    # write_mesh(path, MeshData) writes every attribute.
    io.write_mesh(tmp_path / "copy.off", data)
    copy = io.read_mesh(tmp_path / "copy.off", return_attributes=True)
    np.testing.assert_array_equal(copy.normals[copy.F_normal], data.normals[data.F])
    np.testing.assert_array_equal(copy.colors, data.colors)
    with pytest.raises(meshsmith.InputError, match="F given as well as a MeshData"):
        io.write_mesh(tmp_path / "x.obj", data, data.F)
    V_only, F_only = io.read_mesh(tmp_path / "m.ply")  # without attributes: a plain tuple
    np.testing.assert_array_equal(V_only, data.V)


# --------------------------------------------------------------------------------------------
# OBJ: colours, and what is skipped

def test_obj_vertex_colours_and_skipped_statements(tmp_path):
    text = ("mtllib a.mtl\no thing\ng group\ns 1\nusemtl red\n"
            "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 0 0 1 0.5 0.5 0.5\n"
            "f 1 2 3\nf 1 3 4\nl 1 2\nl 2 3\np 1\nfoo 1 2\nfoo 3\nbar\ncurv 0 1 1 2\n")
    (tmp_path / "c.obj").write_text(text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        data = io.read_mesh(tmp_path / "c.obj", return_attributes=True)
    messages = sorted(str(w.message).split(": ", 1)[1] for w in caught)
    assert all(w.category is SkippedDataWarning for w in caught)
    assert messages == ["skipped 1 'curv' statement (free-form geometry: a mesh holds faces)",
                        "skipped 1 'p' statement (points: a mesh holds faces)",
                        "skipped 1 unknown 'bar' statement",
                        "skipped 2 'l' statements (polylines: a mesh holds faces)",
                        "skipped 2 unknown 'foo' statements"]
    assert all(str(tmp_path / "c.obj") in str(w.message) for w in caught)
    np.testing.assert_array_equal(data.colors, [[1, 0, 0], [0, 1, 0], [0, 0, 1], [0.5, 0.5, 0.5]])
    np.testing.assert_array_equal(data.F, [[0, 1, 2], [0, 2, 3]])
    # o, g, s, usemtl, mtllib alone: no warning at all.
    (tmp_path / "quiet.obj").write_text("mtllib a.mtl\no x\ng y\ns off\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        io.read_mesh(tmp_path / "quiet.obj", return_attributes=True)


def test_obj_many_unknown_kinds_are_counted_not_listed(tmp_path):
    lines = ["v 0 0 0", "v 1 0 0", "v 0 1 0", "f 1 2 3"] + [f"kind{k} 1" for k in range(5000)]
    (tmp_path / "junk.obj").write_text("\n".join(lines) + "\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        V, F = io.read_mesh(tmp_path / "junk.obj")
    assert F.tolist() == [[0, 1, 2]]
    assert len(caught) == 17  # 16 kinds named, the rest counted
    assert str(caught[0].message).endswith("skipped 1 unknown 'kind0' statement")
    assert str(caught[-1].message).endswith("skipped 4984 more statements of other unknown kinds")


def test_obj_texture_w_warns(tmp_path):
    (tmp_path / "w.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nvt 1 0 0.5\nvt 0 1 0.5\nf 1/1 2/2 3/3\n")
    with pytest.warns(SkippedDataWarning, match=r"2 texture coordinates have a third component w"):
        data = io.read_mesh(tmp_path / "w.obj", return_attributes=True)
    np.testing.assert_array_equal(data.UV, [[0, 0], [1, 0], [0, 1]])
    assert repr(data) == "MeshData(V=(3, 3), F=(1, 3), UV=(3, 2), F_uv=(1, 3))"


def test_obj_partial_colours_warn_and_rgba(tmp_path):
    (tmp_path / "p.obj").write_text("v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.warns(SkippedDataWarning, match=r"only 1 of 3 vertices have colours"):
        data = io.read_mesh(tmp_path / "p.obj", return_attributes=True)
    assert data.colors is None
    (tmp_path / "a.obj").write_text("v 0 0 0 1 0 0 0.5\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1 1\nf 1 2 3\n")
    np.testing.assert_array_equal(io.read_mesh(tmp_path / "a.obj", return_attributes=True).colors,
                                  [[1, 0, 0, 0.5], [0, 1, 0, 1], [0, 0, 1, 1]])


def test_large_obj_with_colours_and_unknown_statements_in_parallel_pieces(tmp_path):
    side = 230
    x, y = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(side * side)])
    C = np.column_stack([x.ravel(), y.ravel(), np.full(side * side, 0.25)])
    lines = [f"v {p[0]!r} {p[1]!r} {p[2]!r} {c[0]!r} {c[1]!r} {c[2]!r}" for p, c in zip(V.tolist(), C.tolist())]
    lines += [f"weird {k}" for k in range(1000)]
    text = "\n".join(lines) + "\nf 1 2 3\n"
    assert len(text) > 4 << 20  # parsed in pieces on all cores
    (tmp_path / "big.obj").write_text(text)
    with pytest.warns(SkippedDataWarning, match=r"skipped 1000 unknown 'weird' statements"):
        data = io.read_mesh(tmp_path / "big.obj", return_attributes=True)
    np.testing.assert_array_equal(data.V, V)
    np.testing.assert_array_equal(data.colors, C)


# --------------------------------------------------------------------------------------------
# OFF: colours and the binary byte orders

def test_off_prefixes_and_colours(tmp_path):
    # STCNOFF order on a line: x y z, normal, colour, texture coordinates.
    text = ("STCNOFF\n3 1 0\n0 0 0  0 0 1  255 0 0  0.0 0.0\n1 0 0  0 0 1  0 255 0 255  1.0 0.0\n"
            "0 1 0  0 0 1  0 0 255  0.0 1.0\n3 0 1 2 0 128 255\n")
    (tmp_path / "a.off").write_text(text)
    data = io.read_mesh(tmp_path / "a.off", return_attributes=True)
    np.testing.assert_array_equal(data.normals, [[0, 0, 1]] * 3)
    np.testing.assert_array_equal(data.F_normal, data.F)
    np.testing.assert_array_equal(data.UV, [[0, 0], [1, 0], [0, 1]])
    np.testing.assert_array_equal(data.colors, [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1]])  # 0..255
    np.testing.assert_array_equal(data.face_colors, [[0, 128 / 255, 1]])
    (tmp_path / "f.off").write_text("COFF\n3 1 0\n0 0 0 0.5 0.25 1\n1 0 0 1 1 1\n0 1 0 0 0 0\n3 0 1 2\n")
    np.testing.assert_array_equal(io.read_mesh(tmp_path / "f.off", return_attributes=True).colors,
                                  [[0.5, 0.25, 1], [1, 1, 1], [0, 0, 0]])  # floats in [0, 1]
    (tmp_path / "bad.off").write_text("COFF\n3 1 0\n0 0 0 1 0\n1 0 0 1 1 1\n0 1 0 0 0 0\n3 0 1 2\n")
    with pytest.raises(meshsmith.InputError, match=r"line 3: vertex 0 has 2 colour values \(3 or 4 expected"):
        io.read_mesh(tmp_path / "bad.off")
    (tmp_path / "map.off").write_text("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7\n3 0 2 1 7\n")
    with pytest.warns(SkippedDataWarning, match="2 faces give a colour-map index"):
        io.read_mesh(tmp_path / "map.off")


def binary_off(V, faces, big_endian, color_counts, prefix=b"", extra=None):
    """Binary OFF bytes: Geomview's layout (big-endian, colour counts) or PMP's (little, none)."""
    e = ">" if big_endian else "<"
    out = prefix + b"OFF BINARY\n" + struct.pack(e + "3i", len(V), len(faces), 0)
    for i, p in enumerate(V):
        out += struct.pack(e + "3f", *p) + (struct.pack(e + f"{len(extra[i])}f", *extra[i]) if extra is not None else b"")
    for face in faces:
        out += struct.pack(e + "i", len(face)) + struct.pack(e + f"{len(face)}i", *face)
        if color_counts:
            out += struct.pack(e + "i", 0)
    return out


@pytest.mark.parametrize("big_endian,color_counts", [(True, True), (False, False), (False, True), (True, False)],
                         ids=["geomview-big", "pmp-little", "little-with-counts", "big-without-counts"])
def test_binary_off_in_either_byte_order(tmp_path, big_endian, color_counts):
    V, F = datasets.icosphere(1)
    V = V.astype(np.float32).astype(np.float64)
    polygons = F.tolist()[:-2] + [F[-2].tolist() + [int(F[-1][2])]]  # a quad among triangles
    path = tmp_path / "b.off"
    path.write_bytes(binary_off(V, polygons, big_endian, color_counts))
    back, faces = io.read_mesh(path, triangulate=False)
    np.testing.assert_array_equal(back, V)
    assert faces.to_list() == polygons
    # What we write (Geomview's layout) reads back the same.
    io.write_mesh(tmp_path / "ours.off", V, Polygons.from_list(polygons), binary=True)
    again, faces_again = io.read_mesh(tmp_path / "ours.off", triangulate=False)
    np.testing.assert_array_equal(again, V)
    assert faces_again.to_list() == polygons


def test_binary_off_with_normals_little_endian_and_errors(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    normals = [[0, 0, 1], [0, 0.6, 0.8], [1, 0, 0]]
    path = tmp_path / "n.off"
    path.write_bytes(binary_off(V, [[0, 1, 2]], False, False, prefix=b"N", extra=normals))
    data = io.read_mesh(path, return_attributes=True)
    np.testing.assert_array_equal(data.normals, np.array(normals, np.float32))
    # A file that fits no layout: the error of the plausible one, naming the layouts.
    whole = binary_off(V, [[0, 1, 2]], False, False)
    (tmp_path / "t.off").write_bytes(whole[:-2])
    with pytest.raises(meshsmith.InputError, match=r"t.off: byte \d+: .*little-endian float32 without face colour counts \(PMP\)"):
        io.read_mesh(tmp_path / "t.off")
    (tmp_path / "long.off").write_bytes(whole + b"\x01\x02\x03\x04\x05\x06\x07")
    with pytest.raises(meshsmith.InputError, match=r"long.off: .*bytes before the end of the file"):
        io.read_mesh(tmp_path / "long.off")


# --------------------------------------------------------------------------------------------
# PLY as other tools write it

def test_ply_as_meshlab_writes_it(tmp_path):
    """Vertex colours as uchar with alpha, face texcoord lists as float, texnumber."""
    head = ("ply\nformat binary_little_endian 1.0\ncomment TextureFile tex.png\nelement vertex 4\n"
            "property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
            "property uchar green\nproperty uchar blue\nproperty uchar alpha\nelement face 2\n"
            "property list uchar int vertex_indices\nproperty list uchar float texcoord\n"
            "property int texnumber\nend_header\n").encode()
    V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    colors = [[255, 0, 0, 255], [0, 255, 0, 128], [0, 0, 255, 0], [10, 20, 30, 40]]
    body = b"".join(struct.pack("<3f4B", *p, *c) for p, c in zip(V, colors))
    uv = [[0, 0, 0.5, 0, 0.5, 0.5], [0, 0, 0.5, 0.5, 0, 0.5]]
    for face, t in zip([[0, 1, 2], [0, 2, 3]], uv):
        body += struct.pack("<B3i", 3, *face) + struct.pack("<B6f", 6, *t) + struct.pack("<i", 0)
    (tmp_path / "m.ply").write_bytes(head + body)
    data = io.read_mesh(tmp_path / "m.ply", return_attributes=True)
    np.testing.assert_array_equal(data.colors, np.array(colors) / 255.0)
    np.testing.assert_array_equal(data.UV[data.F_uv], np.array(uv, np.float32).reshape(2, 3, 2))
    assert data.normals is None and data.face_colors is None
    bad = head + body.replace(struct.pack("<B6f", 6, *uv[1]), struct.pack("<B5f", 5, *uv[1][:5]) + b"\0\0\0\0")
    (tmp_path / "bad.ply").write_bytes(bad)
    with pytest.raises(meshsmith.InputError, match=r"face 1: texcoord list of 5 values for 3 corners"):
        io.read_mesh(tmp_path / "bad.ply")


def test_ply_colours_with_trimesh(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    mesh = sphere_with_attributes()
    colors8 = np.round(mesh["colors"] * 255).astype(np.uint8)
    loaded = trimesh.Trimesh(mesh["V"], mesh["F"], vertex_colors=colors8, process=False)
    loaded.export(tmp_path / "t.ply")
    data = io.read_mesh(tmp_path / "t.ply", return_attributes=True)
    np.testing.assert_array_equal(data.colors, colors8 / 255.0)
    io.write_mesh(tmp_path / "ours.ply", mesh["V"], mesh["F"], colors=colors8)
    theirs = trimesh.load(tmp_path / "ours.ply", process=False)
    np.testing.assert_array_equal(theirs.visual.vertex_colors, colors8)
    io.write_mesh(tmp_path / "uv.ply", mesh["V"], mesh["F"], UV=mesh["UV"])
    np.testing.assert_array_equal(trimesh.load(tmp_path / "uv.ply", process=False).visual.uv, mesh["UV"])


# --------------------------------------------------------------------------------------------
# The shared spot.obj: 3,225 texture coordinates with their own indices

def test_spot_uvs_survive_every_format_that_holds_them(tmp_path, data_dir):
    path = data_dir / "spot.obj"
    if not path.is_file():
        pytest.skip("spot.obj is not in the shared data")
    spot = io.read_mesh(path, return_attributes=True)
    assert spot.UV.shape == (3225, 2) and spot.attributes == ["UV"]
    for ext, kwargs, atol in [("obj", {}, 0.0), ("ply", {}, 0.0), ("ply", {"binary": False}, 0.0), ("glb", {}, F32)]:
        out = tmp_path / f"spot.{ext}"
        io.write_mesh(out, spot, **kwargs)
        back = io.read_mesh(out, return_attributes=True)
        assert_same_mesh(back, spot.V, spot.F, atol=atol * np.abs(spot.V).max())
        np.testing.assert_allclose(back.UV[back.F_uv], spot.UV[spot.F_uv], rtol=0, atol=atol)
    back = io.read_mesh(tmp_path / "spot.obj", return_attributes=True)
    np.testing.assert_array_equal(back.UV, spot.UV)
    np.testing.assert_array_equal(back.F_uv, spot.F_uv)
    for ext in ("off", "stl"):  # per-corner UVs: OFF is not suggested
        with pytest.raises(meshsmith.InputError, match=rf"cannot write UV .*: {ext.upper()} cannot hold them \(.*write OBJ, PLY or GLB\)"):
            io.write_mesh(tmp_path / f"spot.{ext}", spot)


# --------------------------------------------------------------------------------------------
# Any values survive: a property test over the exact formats

@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data(), mode=st.sampled_from([("obj", {}), ("ply", {}), ("ply", {"binary": False}),
                                             ("ply", {"big_endian": True}), ("off", {})]))
def test_attributes_round_trip_property(tmp_path, data, mode):
    """Any finite values, polygons, per-corner or per-vertex attributes and colours in [0, 1]
    come back exactly from every format that holds them."""
    ext, kwargs = mode
    doubles = st.floats(allow_nan=False, allow_infinity=False, width=64)
    unit = st.floats(0.0, 1.0, width=64)
    n = data.draw(st.integers(3, 9))
    V = np.array(data.draw(st.lists(st.tuples(doubles, doubles, doubles), min_size=n, max_size=n)))
    faces = data.draw(st.lists(st.lists(st.integers(0, n - 1), min_size=3, max_size=5), min_size=1, max_size=6))
    polygons = Polygons.from_list(faces)
    corners = len(polygons.indices)
    per_corner = ext in ("obj", "ply") and data.draw(st.booleans())
    k = corners if per_corner else n
    UV = np.array(data.draw(st.lists(st.tuples(doubles, doubles), min_size=k, max_size=k)))
    F_uv = np.arange(corners) if per_corner else None
    given = {"UV": UV, "F_uv": F_uv}
    normals_corner = ext == "obj" and data.draw(st.booleans())
    m = corners if normals_corner else n
    given["normals"] = np.array(data.draw(st.lists(st.tuples(doubles, doubles, doubles), min_size=m, max_size=m)))
    given["F_normal"] = np.arange(corners)[::-1].copy() if normals_corner else None
    width = 3 if ext == "obj" else data.draw(st.sampled_from([3, 4]))
    given["colors"] = np.array(data.draw(st.lists(st.lists(unit, min_size=width, max_size=width), min_size=n, max_size=n)))
    if ext != "obj":
        given["face_colors"] = np.array(data.draw(st.lists(st.lists(unit, min_size=3, max_size=3),
                                                           min_size=len(faces), max_size=len(faces))))
    io.write_mesh(tmp_path / f"p.{ext}", V, polygons, **given, **kwargs)
    back = io.read_mesh(tmp_path / f"p.{ext}", triangulate=False, return_attributes=True)
    np.testing.assert_array_equal(back.V, V)
    assert back.F.to_list() == faces
    uv_corners = given["F_uv"] if given["F_uv"] is not None else polygons.indices
    np.testing.assert_array_equal(back.UV[back.F_uv.indices], UV[uv_corners])
    normal_corners = given["F_normal"] if given["F_normal"] is not None else polygons.indices
    used = np.unique(polygons.indices)
    if normals_corner:
        np.testing.assert_array_equal(back.normals[back.F_normal.indices], given["normals"][normal_corners])
    else:
        np.testing.assert_array_equal(back.normals[used], given["normals"][used])
    np.testing.assert_array_equal(back.colors, given["colors"])
    if ext != "obj":
        np.testing.assert_array_equal(back.face_colors, given["face_colors"])
