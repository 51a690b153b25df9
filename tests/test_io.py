"""Tests of meshsmith.io: shared-data counts, agreement with libigl / trimesh, exact round trips
in every format and mode, every malformed-input case, and a hypothesis fuzz of the readers."""
from __future__ import annotations

import hashlib
import os
import re
import struct
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import meshsmith
from meshsmith import io
from meshsmith.io import Polygons

# --------------------------------------------------------------------------------------------
# Shared data: counts from /work/shared/data/README.md

MESH_COUNTS = {  # file: (V, F as face records, triangles after fan triangulation)
    "armadillo.obj": (14587, 29170, 29170),
    "bob_tri.obj": (5344, 10688, 10688),
    "bumpy-cube.obj": (19970, 39936, 39936),
    "bunny.off": (3485, 6966, 6966),
    "camelhead.off": (11381, 22704, 22704),
    "cheburashka.off": (6669, 13334, 13334),
    "cubes_complex_edge.obj": (14, 12, 24),
    "cubes_complex_vertex.obj": (15, 12, 24),
    "decimated-knight.off": (502, 1000, 1000),
    "decimated-max.obj": (5272, 10540, 10540),
    "fandisk.obj": (6475, 12946, 12946),
    "fertility.off": (4494, 9000, 9000),
    "hand_lowres.obj": (810, 1602, 1602),
    "kitten.off": (2500, 5000, 5000),
    "nefertiti-lowres.obj": (35002, 70000, 70000),
    "plane_holes.obj": (8519, 16747, 16747),
    "pmp-bunny.off": (34835, 69666, 69666),
    "rocker-arm.obj": (10044, 20088, 20088),
    "spot.obj": (2930, 5856, 5856),
    "stanford-bunny.obj": (35947, 69451, 69451),
    "torus.obj": (2304, 4608, 4608),
}
POINT_COUNTS = {  # file: (points, has normals)
    "pmp-bunny.xyz": (34835, True),
    "armadillo_low.xyz": (12267, True),
    "bun000.ply": (40256, False),
    "bun045.ply": (40097, False),
}


def sha256(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


@pytest.mark.parametrize("name", sorted(MESH_COUNTS))
def test_shared_mesh_counts(data_dir, name):
    n, faces, triangles = MESH_COUNTS[name]
    path = data_dir / name
    before = sha256(path)
    V, F = io.read_mesh(path)
    assert V.shape == (n, 3) and V.dtype == np.float64
    assert F.shape == (triangles, 3) and F.dtype == np.int64
    assert F.min() >= 0 and F.max() < n
    V2, polygons = io.read_mesh(path, triangulate=False)
    assert len(polygons) == faces
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(polygons.triangulate(), F)
    assert sha256(path) == before  # reading never modifies the file


def test_quad_cubes_are_quads(data_dir):
    V, polygons = io.read_mesh(data_dir / "cubes_complex_edge.obj", triangulate=False)
    assert np.all(polygons.sizes == 4)
    assert polygons.to_list()[0] == [0, 1, 2, 3]  # "f 1 2 3 4"
    _, F = io.read_mesh(data_dir / "cubes_complex_edge.obj")
    np.testing.assert_array_equal(F[:2], [[0, 1, 2], [0, 2, 3]])  # fan


@pytest.mark.parametrize("name", sorted(POINT_COUNTS))
def test_shared_point_counts(data_dir, name):
    count, has_normals = POINT_COUNTS[name]
    P, N = io.read_points(data_dir / name)
    assert P.shape == (count, 3)
    if has_normals:
        assert N.shape == (count, 3)
        np.testing.assert_allclose(np.linalg.norm(N, axis=1), 1.0, atol=1e-3)
    else:
        assert N is None


def test_range_scan_ply_matches_numpy_parse(data_dir):
    # bun000.ply: ASCII vertex element followed by a range_grid list element.
    P, _ = io.read_points(data_dir / "bun000.ply")
    lines = (data_dir / "bun000.ply").read_text().splitlines()
    start = lines.index("end_header") + 1
    expected = np.array([[float(t) for t in line.split()] for line in lines[start:start + 40256]])
    np.testing.assert_array_equal(P, expected)
    # As a mesh it is the same vertices and no faces, with a warning that names the reader that
    # meshes its range grid (tests/test_io_range_scan.py).
    with pytest.warns(io.SkippedDataWarning, match="range grid"):
        V, F = io.read_mesh(data_dir / "bun000.ply")
    np.testing.assert_array_equal(V, P)
    assert F.shape == (0, 3)


def test_xyz_points_match_off_vertices(data_dir):
    P, N = io.read_points(data_dir / "pmp-bunny.xyz")
    V, _ = io.read_mesh(data_dir / "pmp-bunny.off")
    np.testing.assert_allclose(P, V, atol=1e-8)


@pytest.mark.parametrize("name", ["bunny.off", "decimated-knight.off", "fandisk.obj",
                                  "spot.obj", "hand_lowres.obj", "cubes_complex_edge.obj"])
def test_agrees_with_libigl(data_dir, name):
    igl = pytest.importorskip("igl")
    V_igl, F_igl = igl.read_triangle_mesh(str(data_dir / name))
    V, F = io.read_mesh(data_dir / name)
    np.testing.assert_array_equal(V, V_igl)
    np.testing.assert_array_equal(F, F_igl)


@pytest.mark.parametrize("name", ["spot.obj", "bob_tri.obj"])
def test_obj_attributes_agree_with_libigl(data_dir, name):
    igl = pytest.importorskip("igl")
    V, TC, N, F, FTC, FN = igl.readOBJ(str(data_dir / name))
    mesh = io.read_mesh(data_dir / name, return_attributes=True)
    np.testing.assert_array_equal(mesh.V, V)
    np.testing.assert_array_equal(mesh.F, F)
    np.testing.assert_array_equal(mesh.UV, TC)
    np.testing.assert_array_equal(mesh.F_uv, FTC)
    if name == "bob_tri.obj":
        np.testing.assert_array_equal(mesh.normals, N)
        np.testing.assert_array_equal(mesh.F_normal, FN)
    else:
        assert mesh.normals is None and mesh.F_normal is None
    assert mesh.UV.shape == ((3225, 2) if name == "spot.obj" else (5647, 2))


@pytest.mark.parametrize("name", ["armadillo.obj", "kitten.off", "torus.obj"])
def test_agrees_with_trimesh(data_dir, name):
    trimesh = pytest.importorskip("trimesh")
    loaded = trimesh.load(data_dir / name, process=False, maintain_order=True)
    V, F = io.read_mesh(data_dir / name)
    np.testing.assert_allclose(V, loaded.vertices, rtol=0, atol=0)
    np.testing.assert_array_equal(F, loaded.faces)


# --------------------------------------------------------------------------------------------
# Round trips

def random_mesh(seed=0, n=40, m=70):
    rng = np.random.default_rng(seed)
    V = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-8, 8, size=(n, 1))
    V[0] = [0.1, -0.0, 1e-300]  # awkward decimals, negative zero, tiny values
    F = rng.integers(0, n, size=(m, 3))
    F[:, 1] = (F[:, 0] + 1 + rng.integers(0, n - 2, size=m)) % n
    F[:, 2] = (F[:, 1] + 1 + rng.integers(0, n - 2, size=m)) % n
    F = F[(F[:, 0] != F[:, 2])]
    F[0] = [0, 1, 2]
    return V, F


def random_polygons(seed=1, n=30, m=20):
    rng = np.random.default_rng(seed)
    faces = [list(rng.choice(n, size=int(rng.integers(3, 8)), replace=False)) for _ in range(m)]
    return rng.uniform(-1, 1, size=(n, 3)), Polygons.from_list(faces)


EXACT_MODES = [("obj", {}), ("off", {"binary": False}), ("ply", {"binary": False}),
               ("ply", {"binary": True}), ("ply", {"binary": True, "big_endian": True})]


@pytest.mark.parametrize("ext,kwargs", EXACT_MODES)
def test_round_trip_exact(tmp_path, ext, kwargs):
    V, F = random_mesh()
    V0, F0 = V.copy(), F.copy()
    path = tmp_path / f"mesh.{ext}"
    io.write_mesh(path, V, F, **kwargs)
    V2, F2 = io.read_mesh(path)
    np.testing.assert_array_equal(V2, V)  # bit-exact, text included
    np.testing.assert_array_equal(F2, F)
    assert np.array_equal(V, V0) and np.array_equal(F, F0)  # inputs untouched
    if ext == "ply":
        header = path.read_bytes()[:200]
        if kwargs.get("binary"):
            assert (b"binary_big_endian" if kwargs.get("big_endian") else b"binary_little_endian") in header
        else:
            assert b"format ascii" in header


def test_text_output_is_shortest_exact(tmp_path):
    V = np.array([[0.1, 1 / 3, -2.5], [1e-17, 123456789.125, 5e-324], [0, 1, 2]])
    io.write_mesh(tmp_path / "m.obj", V, [[0, 1, 2]])
    text = (tmp_path / "m.obj").read_text()
    assert "v 0.1 0.3333333333333333 -2.5" in text
    np.testing.assert_array_equal(io.read_mesh(tmp_path / "m.obj")[0], V)


@pytest.mark.parametrize("binary", [False, True])
def test_off_round_trip(tmp_path, binary):
    V, F = random_mesh(seed=3)
    if binary:  # binary OFF stores float32
        V = V.astype(np.float32).astype(np.float64)
    io.write_mesh(tmp_path / "m.off", V, F, binary=binary)
    assert (tmp_path / "m.off").read_bytes().startswith(b"OFF BINARY\n" if binary else b"OFF\n")
    V2, F2 = io.read_mesh(tmp_path / "m.off")
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)


def closed_octahedron():
    V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1.5]])
    F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4],
                  [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return V, F


@pytest.mark.parametrize("binary", [False, True])
def test_stl_round_trip_merges_vertices(tmp_path, binary):
    V, F = closed_octahedron()
    V = V + np.array([0.1, 0.2, 0.3])  # not float32-exact: binary rounds
    io.write_mesh(tmp_path / "m.stl", V, F, binary=binary)
    size = (tmp_path / "m.stl").stat().st_size
    if binary:
        assert size == 84 + 50 * len(F)
    V2, F2 = io.read_mesh(tmp_path / "m.stl")
    assert V2.shape == V.shape and F2.shape == F.shape  # 24 corners merged into 6 vertices
    expected = V.astype(np.float32).astype(np.float64) if binary else V
    # Vertices come in order of first appearance; the corner positions are what must agree.
    np.testing.assert_array_equal(V2[F2], expected[F])
    trimesh = pytest.importorskip("trimesh")
    loaded = trimesh.load(tmp_path / "m.stl")
    assert loaded.is_watertight and len(loaded.faces) == len(F)
    np.testing.assert_allclose(loaded.face_normals, trimesh.Trimesh(V, F).face_normals, atol=1e-6)


def test_stl_merges_only_exactly_equal_points(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0], [1, 1e-12, 0], [0, 1, 0]], float)
    io.write_mesh(tmp_path / "m.stl", V, [[0, 1, 2], [3, 4, 5]], binary=False)
    V2, F2 = io.read_mesh(tmp_path / "m.stl")
    np.testing.assert_array_equal(V2, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1e-12, 0]])
    np.testing.assert_array_equal(F2, [[0, 1, 2], [0, 3, 2]])


@pytest.mark.parametrize("ext,kwargs", [("obj", {}), ("off", {"binary": False}),
                                        ("off", {"binary": True}), ("ply", {"binary": False}),
                                        ("ply", {"binary": True, "big_endian": True})])
def test_polygon_round_trip(tmp_path, ext, kwargs):
    V, polygons = random_polygons()
    V = V.astype(np.float32).astype(np.float64)
    io.write_mesh(tmp_path / f"p.{ext}", V, polygons, **kwargs)
    V2, polygons2 = io.read_mesh(tmp_path / f"p.{ext}", triangulate=False)
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(polygons2.offsets, polygons.offsets)
    np.testing.assert_array_equal(polygons2.indices, polygons.indices)
    _, F = io.read_mesh(tmp_path / f"p.{ext}")
    assert len(F) == int(np.sum(polygons.sizes - 2))


def test_large_polygon_uses_wide_ply_counts(tmp_path):
    n = 300
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
    V = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(n)])
    polygons = Polygons.from_list([list(range(n))])
    io.write_mesh(tmp_path / "big.ply", V, polygons)
    assert b"property list int int vertex_indices" in (tmp_path / "big.ply").read_bytes()[:300]
    _, back = io.read_mesh(tmp_path / "big.ply", triangulate=False)
    assert back.to_list() == [list(range(n))]


def test_obj_uv_normals_round_trip(tmp_path, data_dir):
    mesh = io.read_mesh(data_dir / "bob_tri.obj", return_attributes=True)
    io.write_mesh(tmp_path / "bob.obj", mesh.V, mesh.F, UV=mesh.UV, F_uv=mesh.F_uv, normals=mesh.normals,
                  F_normal=mesh.F_normal)
    back = io.read_mesh(tmp_path / "bob.obj", return_attributes=True)
    for field in ("V", "F", "UV", "F_uv", "normals", "F_normal"):
        np.testing.assert_array_equal(getattr(back, field), getattr(mesh, field), err_msg=field)
    # The same with only normals: "f v//vn".
    io.write_mesh(tmp_path / "n.obj", mesh.V, mesh.F, normals=mesh.normals, F_normal=mesh.F_normal)
    assert re.search(r"^f \d+//\d+ ", (tmp_path / "n.obj").read_text(), re.M)
    back = io.read_mesh(tmp_path / "n.obj", return_attributes=True)
    assert back.UV is None and back.F_uv is None
    np.testing.assert_array_equal(back.F_normal, mesh.F_normal)


def test_obj_polygon_attributes_and_negative_indices(tmp_path):
    text = """# quad with vt/vn, relative indices, and ignored statements
mtllib x.mtl
o thing
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0 1.0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
usemtl red
s off
g group
f -4/-4/-1 -3/-3/-1 -2/-2/-1 -1/-1/-1
f 1 2 3
l 1 2
"""
    (tmp_path / "q.obj").write_text(text)
    with pytest.warns(io.SkippedDataWarning, match=r"skipped 1 'l' statement \(polylines"):
        mesh = io.read_mesh(tmp_path / "q.obj", triangulate=False, return_attributes=True)
    assert mesh.F.to_list() == [[0, 1, 2, 3], [0, 1, 2]]
    assert mesh.F_uv.to_list() == [[0, 1, 2, 3], [-1, -1, -1]]
    assert mesh.F_normal.to_list() == [[0, 0, 0, 0], [-1, -1, -1]]
    with pytest.warns(io.SkippedDataWarning):
        tri = io.read_mesh(tmp_path / "q.obj", return_attributes=True)
    np.testing.assert_array_equal(tri.F_uv, [[0, 1, 2], [0, 2, 3], [-1, -1, -1]])
    # Written back: the face without vt/vn is written plain, the other with both.
    io.write_mesh(tmp_path / "q2.obj", mesh.V, mesh.F, UV=mesh.UV, F_uv=mesh.F_uv, normals=mesh.normals,
                  F_normal=mesh.F_normal)
    faces = [l for l in (tmp_path / "q2.obj").read_text().splitlines() if l.startswith("f ")]
    assert faces == ["f 1/1/1 2/2/1 3/3/1 4/4/1", "f 1 2 3"]


@pytest.mark.parametrize("ext,kwargs", [("xyz", {}), ("ply", {}), ("ply", {"binary": False}),
                                        ("ply", {"big_endian": True})])
@pytest.mark.parametrize("with_normals", [False, True])
def test_points_round_trip(tmp_path, ext, kwargs, with_normals):
    rng = np.random.default_rng(5)
    P = rng.normal(size=(100, 3)) * 1e3
    N = rng.normal(size=(100, 3)) if with_normals else None
    io.write_points(tmp_path / f"p.{ext}", P, N, **kwargs)
    P2, N2 = io.read_points(tmp_path / f"p.{ext}")
    np.testing.assert_array_equal(P2, P)
    if with_normals:
        np.testing.assert_array_equal(N2, N)
    else:
        assert N2 is None


def test_ply_mesh_read_as_points_and_normals(tmp_path):
    V, F = closed_octahedron()
    N = V / np.linalg.norm(V, axis=1, keepdims=True)
    io.write_mesh(tmp_path / "o.ply", V, F, normals=N)
    P, N2 = io.read_points(tmp_path / "o.ply")
    np.testing.assert_array_equal(P, V)
    np.testing.assert_array_equal(N2, N)
    mesh = io.read_mesh(tmp_path / "o.ply", return_attributes=True)
    np.testing.assert_array_equal(mesh.normals, N)
    np.testing.assert_array_equal(mesh.F_normal, F)


def test_format_override_and_case_insensitive_extension(tmp_path):
    V, F = closed_octahedron()
    io.write_mesh(tmp_path / "m.PLY", V, F)
    assert (tmp_path / "m.PLY").read_bytes().startswith(b"ply\nformat binary_little_endian")
    io.write_mesh(tmp_path / "m.dat", V, F, format="off")
    V2, F2 = io.read_mesh(tmp_path / "m.dat", format="OFF")
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_array_equal(io.read_mesh(tmp_path / "m.PLY")[1], F)
    with pytest.raises(meshsmith.InputError, match="m.dat.*extension"):
        io.read_mesh(tmp_path / "m.dat")
    with pytest.raises(meshsmith.InputError, match="unknown file format 'abc'"):
        io.read_mesh(tmp_path / "m.dat", format="abc")


# --------------------------------------------------------------------------------------------
# PLY features: every scalar type, skipped list properties, both endiannesses, tristrips

PLY_TYPES = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I",
             "float": "f", "double": "d"}


def build_ply(encoding, vertices, faces, strips=None, extra_elements=True):
    """A PLY with x y z as float, an extra property of every type, a list property on the
    vertices, faces with a leading uchar flag and a trailing float list, an 'edge' element."""
    big = encoding == "binary_big_endian"
    endian = ">" if big else "<"
    lines = ["ply", f"format {encoding} 1.0", "comment test file", "obj_info nothing",
             f"element vertex {len(vertices)}", "property float x"]
    lines += [f"property {t} extra_{t}" for t in PLY_TYPES]
    lines += ["property list uchar short vertex_list", "property double y", "property float z"]
    lines += [f"element face {len(faces)}", "property uchar flag",
              "property list uchar int vertex_indices", "property list ushort float weights"]
    if strips is not None:
        lines += [f"element tristrips {len(strips)}", "property list int int vertex_indices"]
    if extra_elements:
        lines += ["element edge 2", "property int vertex1", "property list uint uchar data"]
    lines.append("end_header")
    head = ("\n".join(lines) + "\n").encode()
    values = [7, 200, -300, 60000, -70000, 4000000000, 0.5, 1.25]
    if encoding == "ascii":
        body = []
        for x, y, z in vertices:
            body.append(" ".join([repr(float(np.float32(x)))] + [str(v) for v in values]
                                 + ["2 -5 6", repr(float(y)), repr(float(np.float32(z)))]))
        for face in faces:
            body.append(" ".join(["1", str(len(face))] + [str(i) for i in face] + ["2 0.5 0.25"]))
        for strip in strips or []:
            body.append(" ".join([str(len(strip))] + [str(i) for i in strip]))
        if extra_elements:
            body += ["1 3 1 2 3", "2 0"]
        return head + ("\n".join(body) + "\n").encode()
    body = b""
    for x, y, z in vertices:
        body += struct.pack(endian + "f", x) + struct.pack(endian + "bBhHiIfd", *values)
        body += struct.pack(endian + "Bhh", 2, -5, 6) + struct.pack(endian + "df", y, z)
    for face in faces:
        body += struct.pack(endian + "BB", 1, len(face)) + struct.pack(endian + "i" * len(face), *face)
        body += struct.pack(endian + "Hff", 2, 0.5, 0.25)
    for strip in strips or []:
        body += struct.pack(endian + "i", len(strip)) + struct.pack(endian + "i" * len(strip), *strip)
    if extra_elements:
        body += struct.pack(endian + "iI3B", 1, 3, 1, 2, 3) + struct.pack(endian + "iI", 2, 0)
    return head + body


@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian", "binary_big_endian"])
def test_ply_skips_unknown_properties_of_every_type(tmp_path, encoding):
    V = np.array([[0.5, 0.1, 2.0], [1.5, -0.3, 0.25], [2.5, 1e-7, -1.0], [3.0, 4.0, 5.0]])
    faces = [[0, 1, 2], [0, 2, 3, 1]]
    path = tmp_path / "typed.ply"
    path.write_bytes(build_ply(encoding, V, faces))
    V2, polygons = io.read_mesh(path, triangulate=False)
    expected = V.copy()
    expected[:, [0, 2]] = V[:, [0, 2]].astype(np.float32)
    np.testing.assert_array_equal(V2, expected)
    assert polygons.to_list() == faces
    _, F = io.read_mesh(path)
    np.testing.assert_array_equal(F, [[0, 1, 2], [0, 2, 3], [0, 3, 1]])


@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian", "binary_big_endian"])
def test_ply_tristrips(tmp_path, encoding):
    V = np.arange(24, dtype=float).reshape(8, 3)
    # Strip 0 1 2 3 4 → (0,1,2) (2,1,3) (2,3,4); restart; 5 6 7 → (5,6,7); a degenerate one dropped.
    strips = [[0, 1, 2, 3, 4, -1, 5, 6, 7], [1, 1, 2]]
    path = tmp_path / "strips.ply"
    path.write_bytes(build_ply(encoding, V, [[0, 1, 2]], strips=strips))
    _, F = io.read_mesh(path)
    np.testing.assert_array_equal(F, [[0, 1, 2], [0, 1, 2], [2, 1, 3], [2, 3, 4], [5, 6, 7]])


def test_ply_written_by_trimesh_and_meshio(tmp_path, data_dir):
    trimesh = pytest.importorskip("trimesh")
    meshio = pytest.importorskip("meshio")
    V, F = io.read_mesh(data_dir / "fandisk.obj")
    mesh = trimesh.Trimesh(V, F, process=False)
    mesh.visual.vertex_colors = np.tile([255, 0, 0, 255], (len(V), 1))
    mesh.export(tmp_path / "t.ply")
    V2, F2 = io.read_mesh(tmp_path / "t.ply")
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_allclose(V2, mesh.vertices, rtol=1e-6)  # trimesh writes what it stores
    meshio.write(tmp_path / "m.ply", meshio.Mesh(V, [("triangle", F)]), binary=False)
    V3, F3 = io.read_mesh(tmp_path / "m.ply")
    np.testing.assert_allclose(V3, V, rtol=1e-12)
    np.testing.assert_array_equal(F3, F)
    # And the other way: trimesh and meshio read what we write.
    io.write_mesh(tmp_path / "ours.ply", V, F)
    np.testing.assert_array_equal(trimesh.load(tmp_path / "ours.ply", process=False).faces, F)
    np.testing.assert_array_equal(meshio.read(tmp_path / "ours.ply").points, V)


# --------------------------------------------------------------------------------------------
# Malformed input: InputError naming the file and the line or byte

def expect_error(path, pattern, reader=io.read_mesh, **kwargs):
    with pytest.raises(meshsmith.InputError) as caught:
        reader(path, **kwargs)
    message = str(caught.value)
    assert str(path) in message, message
    assert re.search(pattern, message), message
    return message


OBJ_TEXT = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n"
OFF_TEXT = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 2 3\n"
PLY_ASCII = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
             "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
             "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 2 3\n")
STL_ASCII = ("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
             "endloop\nendfacet\nendsolid t\n")


def binary_ply(count_line="element vertex 4", endian="<"):
    head = (f"ply\nformat binary_{'little' if endian == '<' else 'big'}_endian 1.0\n{count_line}\n"
            "property float x\nproperty float y\nproperty float z\nelement face 2\n"
            "property list uchar int vertex_indices\nend_header\n").encode()
    body = struct.pack(endian + "12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
    body += struct.pack(endian + "B3i", 3, 0, 1, 2) + struct.pack(endian + "B3i", 3, 0, 2, 3)
    return head + body


def binary_stl(triangles=1):
    body = b"x" * 80 + struct.pack("<I", triangles)
    for _ in range(triangles):
        body += struct.pack("<12fH", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0)
    return body


def test_valid_samples_read(tmp_path):
    for name, data in [("a.obj", OBJ_TEXT), ("a.off", OFF_TEXT), ("a.ply", PLY_ASCII),
                       ("a.stl", STL_ASCII)]:
        (tmp_path / name).write_text(data)
        V, F = io.read_mesh(tmp_path / name)
        assert len(F) == (1 if name == "a.stl" else 2)
    (tmp_path / "b.ply").write_bytes(binary_ply())
    (tmp_path / "b.stl").write_bytes(binary_stl(2))
    assert io.read_mesh(tmp_path / "b.ply")[1].tolist() == [[0, 1, 2], [0, 2, 3]]
    assert io.read_mesh(tmp_path / "b.stl")[0].shape == (3, 3)


TEXT_CASES = [  # (file name, contents, message pattern)
    ("trunc.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2", r"line 4: face with 2 corners"),
    ("garbage.obj", "v 0 0 0\nv 1 zero 0\n", r"line 2: 'zero' is not a finite number"),
    ("nan.obj", "v 0 0 nan\n", r"line 1: 'nan' is not a finite number"),
    ("range.obj", OBJ_TEXT + "f 1 2 9\n", r"line 7: vertex index 9 out of range"),
    ("zero.obj", OBJ_TEXT + "f 0 1 2\n", r"line 7: vertex index 0"),
    ("negative.obj", OBJ_TEXT + "f -1 -2 -9\n", r"line 7: vertex index -9 refers before"),
    ("corner.obj", OBJ_TEXT + "f 1/x 2 3\n", r"line 7: .*texture coordinate index"),
    ("overflow.obj", OBJ_TEXT + "f 1 2 99999999999999999999\n", r"line 7: '99999999999999999999' is not a face corner"),
    ("bigindex.obj", OBJ_TEXT + "f 1 2 9999999999\n", r"line 7: vertex index 9999999999 is too large"),
    ("sign.obj", OBJ_TEXT + "f 1 2 +-3\n", r"line 7: '\+-3' is not a face corner"),
    ("noverts.obj", "# nothing\n", r"no vertices"),
    ("trunc.off", OFF_TEXT[:-4], r"line 8: face 1 has fewer than the 3 indices"),
    ("eof.off", OFF_TEXT[:-8] + "#" * 20 + "\n", r"line 8: unexpected end of file: 1 of 2 faces"),
    ("counts.off", "OFF\n4 3 0\n" + OFF_TEXT[10:], r"line 8: unexpected end of file: 2 of 3 faces read"),
    ("huge.off", "OFF\n999999999999 1 0\n0 0 0\n", r"line 2: the header announces 999999999999"),
    ("neg.off", "OFF\n-4 2 0\n", r"line 2: negative count"),
    ("range.off", OFF_TEXT.replace("3 0 2 3", "3 0 2 4"), r"line 8: face 1 has vertex index 4 outside \[0, 4\)"),
    ("garbage.off", OFF_TEXT.replace("1 0 0", "1 0 x"), r"line 4: 'x' is not a finite number"),
    ("header.off", "OF\n4 2 0\n", r"line 1: the file does not start with an OFF header"),
    ("small.off", OFF_TEXT.replace("3 0 2 3", "2 0 2"), r"line 8: face 1 has 2 corners"),
    ("huge.ply", PLY_ASCII.replace("vertex 4", "vertex 999999999999"), r"line 3: element 'vertex' announces 999999999999"),
    ("neg.ply", PLY_ASCII.replace("vertex 4", "vertex -4"), r"line 3: negative element count"),
    ("trunc.ply", PLY_ASCII[:-8], r"line 14: unexpected end of file in element 'face' \(1 of 2 records read\)"),
    ("range.ply", PLY_ASCII.replace("3 0 2 3", "3 0 2 7"), r"line 15: face 1: vertex index 7 outside"),
    ("hugeidx.ply", PLY_ASCII.replace("3 0 2 3", "3 0 2 1e300"), r"line 15: face 1: vertex index 1e\+300 outside"),
    ("garbage.ply", PLY_ASCII.replace("1 0 0\n", "1 O 0\n"), r"line 11: 'O' is not a finite number"),
    ("extra.ply", PLY_ASCII.replace("0 0 1\n", "0 0 1 5\n"), r"line 13: vertex 3: more values"),
    ("type.ply", PLY_ASCII.replace("float x", "flaot x"), r"line 4: unknown PLY type 'flaot'"),
    ("noend.ply", PLY_ASCII.replace("end_header", "end_headr"), r"line 9: unknown PLY header keyword 'end_headr'"),
    ("magic.ply", "pyl\n" + PLY_ASCII[4:], r"line 1: not a PLY file"),
    ("trunc.stl", STL_ASCII.replace("endloop\nendfacet\nendsolid t\n", ""), r"line 6: unexpected end of file inside a solid"),
    ("four.stl", STL_ASCII.replace("endloop", "vertex 1 1 1\nendloop"), r"line 7: a facet with more than 3 vertices"),
    ("garbage.stl", STL_ASCII.replace("vertex 1 0 0", "vertex 1 0 zz"), r"line 5: 'vertex' needs 3 finite numbers"),
    ("columns.xyz", "1 2 3\n4 5 6\n7 8\n", r"line 3: 2 values on a line where the first line has 3"),
    ("garbage.xyz", "1 2 3\n4 5 six\n", r"line 2: 'six' is not a finite number"),
    ("four.xyz", "1 2 3 4\n", r"line 1: 4 values on a line"),
]


@pytest.mark.parametrize("name,contents,pattern", TEXT_CASES, ids=[c[0] for c in TEXT_CASES])
def test_malformed_text_raises_with_line(tmp_path, name, contents, pattern):
    path = tmp_path / name
    path.write_text(contents)
    reader = io.read_points if name.endswith(".xyz") else io.read_mesh
    expect_error(path, pattern, reader)


BINARY_CASES = [
    ("trunc.ply", binary_ply()[:-5], r"byte \d+: unexpected end of file"),
    ("huge.ply", binary_ply("element vertex 999999999999"), r"line 3: element 'vertex' announces 999999999999"),
    ("range.ply", binary_ply().replace(struct.pack("<B3i", 3, 0, 2, 3), struct.pack("<B3i", 3, 0, 2, 9)),
     r"byte \d+: face 1: vertex index 9 outside"),
    ("negidx.ply", binary_ply().replace(struct.pack("<B3i", 3, 0, 2, 3), struct.pack("<B3i", 3, 0, -2, 3)),
     r"byte \d+: face 1: vertex index -2 outside"),
    ("nan.ply", binary_ply().replace(struct.pack("<3f", 1, 0, 0), struct.pack("<3f", np.nan, 0, 0)),
     r"byte \d+: vertex 1 has a non-finite x"),
    ("small.ply", binary_ply().replace(struct.pack("<B3i", 3, 0, 2, 3), struct.pack("<B3i", 2, 0, 2, 3)),
     r"byte \d+: face 1: face with 2 corners|byte \d+: unexpected"),
    ("count.stl", binary_stl(2)[:-50], r"byte 80: the binary STL header announces 2 triangles"),
    ("short.stl", b"\x00" * 40, r"byte 0: too short for a binary STL"),
    ("nan.stl", binary_stl(1).replace(struct.pack("<f", 1), struct.pack("<f", np.inf), 2), r"byte \d+: triangle 0 has a non-finite"),
    ("trunc.off", b"OFF BINARY\n" + struct.pack(">3i", 3, 1, 0) + struct.pack(">9f", *range(9)) + struct.pack(">3i", 3, 0, 1),
     r"byte 63: unexpected end of file while reading face indices .*read as big-endian float32 with face colour counts"),
    ("huge.off", b"OFF BINARY\n" + struct.pack(">3i", 2**31 - 1, 5, 0) + b"\0" * 100,
     r"byte 23: the header announces 2147483647 vertices"),
    ("neg.off", b"OFF BINARY\n" + struct.pack(">3i", -3, 1, 0) + b"\0" * 100, r"byte 23: negative count"),
]


@pytest.mark.parametrize("name,contents,pattern", BINARY_CASES, ids=[c[0] for c in BINARY_CASES])
def test_malformed_binary_raises_with_byte(tmp_path, name, contents, pattern):
    path = tmp_path / name
    path.write_bytes(contents)
    expect_error(path, pattern)


def test_missing_empty_directory_and_extension(tmp_path):
    expect_error(tmp_path / "absent.obj", "does not exist")
    (tmp_path / "empty.ply").write_bytes(b"")
    expect_error(tmp_path / "empty.ply", "empty")
    (tmp_path / "dir.obj").mkdir()
    expect_error(tmp_path / "dir.obj", "is a directory")
    (tmp_path / "mesh.abc").write_text(OBJ_TEXT)
    expect_error(tmp_path / "mesh.abc", "unknown file extension '.abc'")
    (tmp_path / "noext").write_text(OBJ_TEXT)
    expect_error(tmp_path / "noext", "no file extension")
    expect_error(tmp_path / "absent.xyz", "does not exist", io.read_points)
    (tmp_path / "points.xyz").write_text("1 2 3\n")
    expect_error(tmp_path / "points.xyz", "XYZ files hold point clouds")
    expect_error(tmp_path / "points.obj", "read_points reads XYZ and PLY", io.read_points)
    if os.path.exists("/dev/null"):
        expect_error(Path("/dev/null"), "not a regular file", format="obj")


def test_write_errors(tmp_path):
    V, F = closed_octahedron()
    with pytest.raises(meshsmith.InputError, match="face 1 has vertex index 6 outside"):
        io.write_mesh(tmp_path / "m.obj", V, np.array([[0, 1, 2], [0, 1, 6]]))
    bad = V.copy()
    bad[2, 1] = np.nan
    with pytest.raises(meshsmith.InputError, match="V row 2 is not finite"):
        io.write_mesh(tmp_path / "m.ply", bad, F)
    with pytest.raises(meshsmith.InputError, match="F has shape"):
        io.write_mesh(tmp_path / "m.ply", V, F[:, :2])
    with pytest.raises(meshsmith.InputError, match="cannot open file for writing"):
        io.write_mesh(tmp_path / "no" / "such" / "dir.obj", V, F)
    with pytest.raises(meshsmith.InputError, match="cannot write a mesh as XYZ"):
        io.write_mesh(tmp_path / "m.xyz", V, F)
    with pytest.raises(meshsmith.InputError, match="N has 2 rows but P has 6"):
        io.write_points(tmp_path / "p.xyz", V, V[:2])
    with pytest.raises(meshsmith.InputError, match="face 0 has 2 corners"):
        io.write_mesh(tmp_path / "p.obj", V, Polygons(np.array([0, 2]), np.array([0, 1])))
    with pytest.raises(meshsmith.InputError, match="binary STL stores float32"):
        io.write_mesh(tmp_path / "m.stl", V * 1e300, F)
    with pytest.raises(meshsmith.InputError, match="STL file needs at least one face"):
        io.write_mesh(tmp_path / "m.stl", V, np.zeros((0, 3), int))
    assert not any(tmp_path.iterdir())  # nothing was written by a failed call


def test_points_only_meshes_and_comments(tmp_path):
    V, _ = closed_octahedron()
    for name in ("v.obj", "v.ply", "v.off"):
        io.write_mesh(tmp_path / name, V, np.zeros((0, 3), dtype=int))
        V2, F2 = io.read_mesh(tmp_path / name)
        np.testing.assert_array_equal(V2, V)
        assert F2.shape == (0, 3)
    (tmp_path / "c.off").write_text("# comment\nCOFF 4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n"
                                     "0 1 0 0 0 255 255 # inline\n\n0 0 1 1 1 1 1\n4 0 1 2 3 0.5 0.5 0.5\n")
    V, polygons = io.read_mesh(tmp_path / "c.off", triangulate=False)
    assert V.shape == (4, 3) and polygons.to_list() == [[0, 1, 2, 3]]


def test_polygon_attributes_from_flat_arrays(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    polygons = Polygons.from_list([[0, 1, 2, 3]])
    UV = V[:, :2].copy()
    io.write_mesh(tmp_path / "q.obj", V, polygons, UV=UV, F_uv=np.array([0, 1, 2, 3]))
    mesh = io.read_mesh(tmp_path / "q.obj", triangulate=False, return_attributes=True)
    assert mesh.F_uv.to_list() == [[0, 1, 2, 3]]
    np.testing.assert_array_equal(mesh.UV, UV)


# --------------------------------------------------------------------------------------------
# Fuzz: random bytes and mutated valid files give InputError or a valid mesh, never a crash

def sample_files():
    V, F = closed_octahedron()
    samples = {"obj": OBJ_TEXT.encode(), "off": OFF_TEXT.encode(), "ply": PLY_ASCII.encode(),
               "stl": STL_ASCII.encode(), "bply": binary_ply(), "beply": binary_ply(endian=">"),
               "bstl": binary_stl(3),
               "boff": b"OFF BINARY\n" + struct.pack(">3i", 4, 1, 0) + struct.pack(">12f", *range(12))
               + struct.pack(">5i", 3, 0, 1, 2, 0),
               "tply": build_ply("binary_little_endian", V, F.tolist(), strips=[[0, 1, 2, -1, 3, 4, 5]]),
               "xyz": b"1 2 3 0 0 1\n4 5 6 0 1 0\n",
               "objattr": (OBJ_TEXT + "vt 0 0\nvt 1 0\nvn 0 0 1\nf -4/1/1 -3/2/1 -2/-1/-1 -1//1\n"
                           "f 1/1 2/2 3/1\n").encode(),
               "coff": b"COFF\n4 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n0 0 1 1 1 1 1\n4 0 1 2 3\n",
               "stcnoff": b"STCNOFF\n3 1 0\n0 0 0 0 0 1 255 0 0 0 0\n1 0 0 0 0 1 0 255 0 9 1 0\n"
                          b"0 1 0 0 0 1 0 0 255 0 1\n3 0 1 2 0.5 0.5 0.5\n",
               "leoff": b"OFF BINARY\n" + struct.pack("<3i", 4, 1, 0) + struct.pack("<12f", *range(12))
               + struct.pack("<4i", 3, 0, 1, 2),
               "cply": (b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                        b"property float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
                        b"property uchar blue\nelement face 1\nproperty list uchar int vertex_indices\n"
                        b"property uchar red\nproperty uchar green\nproperty uchar blue\n"
                        b"property list uchar float texcoord\nend_header\n"
                        + b"".join(struct.pack("<3f3B", *p, 9, 99, 199) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0)])
                        + struct.pack("<B3i3BB6f", 3, 0, 1, 2, 1, 2, 3, 6, 0, 0, 1, 0, 0, 1))}
    return samples


EXTENSION = {"bply": "ply", "beply": "ply", "bstl": "stl", "boff": "off", "tply": "ply",
             "objattr": "obj", "coff": "off", "stcnoff": "off", "leoff": "off", "cply": "ply"}


def check_reader_result(path, ext):
    try:
        if ext == "xyz":
            P, N = io.read_points(path)
            assert np.all(np.isfinite(P)) and (N is None or N.shape == P.shape)
            return
        V, F = io.read_mesh(path)
    except meshsmith.InputError as error:
        assert str(path) in str(error)
        return
    assert V.ndim == 2 and V.shape[1] == 3 and np.all(np.isfinite(V))
    assert F.ndim == 2 and F.shape[1] == 3
    if len(F):
        assert F.min() >= 0 and F.max() < len(V)
    # The other read modes accept the same file and agree.
    mesh = io.read_mesh(path, triangulate=False, return_attributes=True)
    np.testing.assert_array_equal(mesh.V, V)
    assert np.all(mesh.F.sizes >= 3) and mesh.F.offsets[-1] == len(mesh.F.indices)
    np.testing.assert_array_equal(mesh.F.triangulate(), F)
    for values, corners in ((mesh.UV, mesh.F_uv), (mesh.normals, mesh.F_normal)):
        if corners is not None:
            assert np.all((corners.indices >= -1) & (corners.indices < len(values)))
    if mesh.colors is not None:
        assert mesh.colors.shape in ((len(V), 3), (len(V), 4)) and np.all(np.isfinite(mesh.colors))
    if mesh.face_colors is not None:
        assert mesh.face_colors.shape[0] == len(mesh.F) and np.all(np.isfinite(mesh.face_colors))


@pytest.mark.filterwarnings("ignore::meshsmith.io.SkippedDataWarning")  # mutations make odd statements
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.binary(max_size=600), ext=st.sampled_from(["obj", "off", "ply", "stl", "xyz"]))
def test_fuzz_random_bytes(tmp_path, data, ext):
    path = tmp_path / f"random.{ext}"
    path.write_bytes(data)
    check_reader_result(path, ext)


@pytest.mark.filterwarnings("ignore::meshsmith.io.SkippedDataWarning")  # mutations make odd statements
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(kind=st.sampled_from(sorted(sample_files())), data=st.data())
def test_fuzz_mutated_valid_files(tmp_path, kind, data):
    contents = bytearray(sample_files()[kind])
    action = data.draw(st.sampled_from(["truncate", "flip", "insert", "digits"]))
    if action == "truncate":
        contents = contents[:data.draw(st.integers(0, len(contents)))]
    elif action == "flip":
        for _ in range(data.draw(st.integers(1, 4))):
            position = data.draw(st.integers(0, len(contents) - 1))
            contents[position] = data.draw(st.integers(0, 255))
    elif action == "insert":
        position = data.draw(st.integers(0, len(contents)))
        contents[position:position] = data.draw(st.binary(min_size=1, max_size=8))
    else:  # replace a digit by a large or negative number
        digits = [i for i, c in enumerate(contents) if chr(c).isdigit()]
        if digits:
            position = data.draw(st.sampled_from(digits))
            replacement = data.draw(st.sampled_from([b"999999999999", b"-1", b"4294967295", b"1e308"]))
            contents[position:position + 1] = replacement
    ext = EXTENSION.get(kind, kind)
    path = tmp_path / f"mutated.{ext}"
    path.write_bytes(bytes(contents))
    check_reader_result(path, ext)


finite_doubles = st.floats(allow_nan=False, allow_infinity=False, width=64)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(V=hnp.arrays(np.float64, st.tuples(st.integers(3, 12), st.just(3)), elements=finite_doubles),
       data=st.data(),
       mode=st.sampled_from([("obj", {}), ("off", {"binary": False}), ("ply", {"binary": False}),
                             ("ply", {}), ("ply", {"big_endian": True}), ("stl", {"binary": False})]))
def test_round_trip_property(tmp_path, V, data, mode):
    """Any finite doubles and any polygons survive a text or binary PLY round trip exactly."""
    ext, kwargs = mode
    n = len(V)
    faces = data.draw(st.lists(st.lists(st.integers(0, n - 1), min_size=3, max_size=6),
                               min_size=1, max_size=10))
    if ext == "stl":  # STL stores triangles and merges equal points: compare corner positions
        F = np.array([face[:3] for face in faces])
        io.write_mesh(tmp_path / "p.stl", V, F, **kwargs)
        V2, F2 = io.read_mesh(tmp_path / "p.stl")
        np.testing.assert_array_equal(V2[F2], np.where(V[F] == 0, 0.0, V[F]))  # -0 merges with 0
        return
    polygons = Polygons.from_list(faces)
    io.write_mesh(tmp_path / f"p.{ext}", V, polygons, **kwargs)
    V2, polygons2 = io.read_mesh(tmp_path / f"p.{ext}", triangulate=False)
    np.testing.assert_array_equal(V2, V)
    assert polygons2.to_list() == faces


# --------------------------------------------------------------------------------------------
# Large OBJ files are parsed in parallel pieces: same result, same errors as one piece

def large_obj_text(side=180, relative=False):
    """A side x side grid as OBJ (> 4 MB) with vt and vn, faces after all vertices."""
    x, y = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    V = np.column_stack([x.ravel(), y.ravel(), np.sin(7 * x.ravel()) * 0.1 + 1 / 3])
    i = np.arange(side - 1)
    a = (i[:, None] * side + i[None, :]).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + side + 1]),
                        np.column_stack([a, a + side + 1, a + side])])
    lines = [f"v {p[0]!r} {p[1]!r} {p[2]!r}" for p in V.tolist()]
    lines += [f"vt {p[0]!r} {p[1]!r}" for p in V.tolist()]
    lines += ["vn 0 0 1"]
    n = len(V)
    for f in F.tolist():
        if relative:
            lines.append("f " + " ".join(f"{c - n}/{c - n}/-1" for c in f))
        else:
            lines.append("f " + " ".join(f"{c + 1}/{c + 1}/1" for c in f))
    return "\n".join(lines) + "\n", V, F


def test_large_obj_parallel_pieces_agree(tmp_path):
    text, V, F = large_obj_text()
    assert len(text) > 4 << 20
    (tmp_path / "big.obj").write_text(text)
    mesh = io.read_mesh(tmp_path / "big.obj", return_attributes=True)
    np.testing.assert_array_equal(mesh.V, V)
    np.testing.assert_array_equal(mesh.F, F)
    np.testing.assert_array_equal(mesh.UV, V[:, :2])
    np.testing.assert_array_equal(mesh.F_uv, F)
    np.testing.assert_array_equal(mesh.F_normal, np.zeros_like(F))
    igl = pytest.importorskip("igl")
    V_igl, F_igl = igl.read_triangle_mesh(str(tmp_path / "big.obj"))
    np.testing.assert_array_equal(mesh.V, V_igl)
    np.testing.assert_array_equal(mesh.F, F_igl)
    # Relative indices need the counts of earlier pieces: same result.
    text_relative, _, _ = large_obj_text(relative=True)
    (tmp_path / "relative.obj").write_text(text_relative)
    relative = io.read_mesh(tmp_path / "relative.obj", return_attributes=True)
    np.testing.assert_array_equal(relative.F, F)
    np.testing.assert_array_equal(relative.F_uv, F)


def test_large_obj_errors_keep_true_line_numbers(tmp_path):
    text, V, F = large_obj_text()
    lines = text.splitlines()
    bad = list(lines)
    bad[len(bad) * 3 // 4] = "v 1 2 oops"
    (tmp_path / "bad.obj").write_text("\n".join(bad) + "\n")
    expect_error(tmp_path / "bad.obj", rf"line {len(bad) * 3 // 4 + 1}: 'oops' is not a finite number")
    far = list(lines)
    far[-1] = f"f 1 2 {len(V) + 5}"
    (tmp_path / "far.obj").write_text("\n".join(far) + "\n")
    expect_error(tmp_path / "far.obj", rf"line {len(far)}: vertex index {len(V) + 5} out of range")


def test_number_parsing_is_exact(tmp_path):
    """Every decimal form a file may hold reads as Python's float() of it (correct rounding)."""
    rng = np.random.default_rng(9)
    tokens = []
    for _ in range(6000):
        kind = rng.integers(0, 6)
        if kind == 0:  # short decimals as scanners write them
            tokens.append(f"{rng.uniform(-1000, 1000):.{rng.integers(0, 9)}f}")
        elif kind == 1:  # shortest round trip of random doubles
            tokens.append(repr(float(rng.normal() * 10.0 ** rng.integers(-30, 30))))
        elif kind == 2:  # scientific with awkward exponents
            tokens.append(f"{rng.uniform(1, 10):.{rng.integers(1, 17)}e}".replace("e+0", "E").replace("e-0", "e-"))
        elif kind == 3:  # long digit strings (beyond 19 digits, or 2^53)
            tokens.append("".join(str(d) for d in rng.integers(0, 10, rng.integers(15, 25))) + "." + "9" * int(rng.integers(0, 5)))
        elif kind == 4:  # forms with signs, leading dots, trailing dots, leading zeros
            tokens.append(str(rng.choice(["+", "-", ""])) + str(rng.choice([".5", "1.", "007.25", "0.000001234", "9007199254740993", "123456789012345678", "1e22", "1e23", "8.98846567431158e307", "4.9e-324", "2.2250738585072011e-308"])))
        else:  # halfway cases of binary rounding
            tokens.append(repr(float(rng.integers(1, 2**53))) [:-2] + "." + "5" * int(rng.integers(1, 3)))
    while len(tokens) % 3:
        tokens.append("0")
    lines = [" ".join(tokens[i:i + 3]) for i in range(0, len(tokens), 3)]
    (tmp_path / "numbers.xyz").write_text("\n".join(lines) + "\n")
    P, _ = io.read_points(tmp_path / "numbers.xyz")
    expected = np.array([float(t) for t in tokens]).reshape(-1, 3)
    assert np.array_equal(P, expected)
    assert np.array_equal(np.signbit(P), np.signbit(expected))
