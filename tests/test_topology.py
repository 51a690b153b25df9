"""topology: edges, boundary loops, components, χ, genus, manifoldness, orientation, split, info.

Checked against libigl on the same input, against the counts in ../shared/data/README.md, and
against constructions whose topology is known by hand.
"""
import re

import igl
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, geometry, topology


# Meshes are read here with libigl (and a tiny quad OBJ reader) because meshsmith.io is being
# written in parallel; these helpers should switch to meshsmith.io.read_mesh once it lands.
def read_mesh(path):
    V, F = igl.read_triangle_mesh(str(path))
    return np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)


def read_polygon_obj_as_fan(path):
    """OBJ with polygon faces, each triangulated as a fan from its first corner."""
    V, F = [], []
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            V.append([float(x) for x in parts[1:4]])
        elif parts[0] == "f":
            corners = [int(p.split("/")[0]) - 1 for p in parts[1:]]
            F += [[corners[0], corners[k], corners[k + 1]] for k in range(1, len(corners) - 1)]
    return np.array(V), np.array(F, dtype=np.int64)


# file: (V, F, E, χ, components, boundary loops, boundary edges, genus, unreferenced vertices),
# all from ../shared/data/README.md.
SHARED_MESHES = {
    "armadillo.obj": (14587, 29170, 43755, 2, 1, 0, 0, 0, 0),
    "bob_tri.obj": (5344, 10688, 16032, 0, 1, 0, 0, 1, 0),
    "bumpy-cube.obj": (19970, 39936, 59904, 2, 1, 0, 0, 0, 0),
    "bunny.off": (3485, 6966, 10449, 2, 1, 0, 0, 0, 0),
    "camelhead.off": (11381, 22704, 34084, 1, 1, 1, 56, 0, 0),
    "cheburashka.off": (6669, 13334, 20001, 2, 1, 0, 0, 0, 0),
    "decimated-knight.off": (502, 1000, 1500, 2, 1, 0, 0, 0, 0),
    "decimated-max.obj": (5272, 10540, 15810, 2, 1, 0, 0, 0, 0),
    "fandisk.obj": (6475, 12946, 19419, 2, 1, 0, 0, 0, 0),
    "fertility.off": (4494, 9000, 13500, -6, 1, 0, 0, 4, 0),
    "hand_lowres.obj": (810, 1602, 2411, 1, 1, 1, 16, 0, 0),
    "kitten.off": (2500, 5000, 7500, 0, 1, 0, 0, 1, 0),
    "nefertiti-lowres.obj": (35002, 70000, 105000, 2, 1, 0, 0, 0, 0),
    "plane_holes.obj": (8519, 16747, 25291, -25, 1, 27, 341, 0, 0),
    "pmp-bunny.off": (34835, 69666, 104499, 2, 1, 0, 0, 0, 0),
    "rocker-arm.obj": (10044, 20088, 30132, 0, 1, 0, 0, 1, 0),
    "spot.obj": (2930, 5856, 8784, 2, 1, 0, 0, 0, 0),
    "stanford-bunny.obj": (35947, 69451, 104288, -3, 1, 5, 223, 0, 1113),
    "torus.obj": (2304, 4608, 6912, 0, 1, 0, 0, 1, 0),
}
WITH_BOUNDARY = ["camelhead.off", "hand_lowres.obj", "plane_holes.obj", "stanford-bunny.obj"]


@pytest.mark.parametrize("name", sorted(SHARED_MESHES))
def test_shared_mesh_counts_match_the_data_readme(data_dir, name):
    V, F = read_mesh(data_dir / name)
    n_v, n_f, n_e, chi, n_comp, n_loops, n_bedges, genus, n_unref = SHARED_MESHES[name]
    info = topology.info(V, F)
    assert (info.n_vertices, info.n_faces, info.n_edges) == (n_v, n_f, n_e)
    assert info.euler_characteristic == chi == topology.euler_characteristic(F)
    assert topology.euler_characteristic(V, F) == chi
    assert (info.n_components, info.n_boundary_loops, info.n_boundary_edges) == (n_comp, n_loops, n_bedges)
    assert info.genus == genus == topology.genus(F)
    assert info.n_unreferenced_vertices == n_unref
    assert info.is_manifold and info.is_oriented
    assert info.n_non_manifold_edges == info.n_non_manifold_vertices == 0
    assert len(topology.boundary_loops(F)) == n_loops
    assert sum(len(loop) for loop in topology.boundary_loops(F)) == n_bedges


@pytest.mark.parametrize("name", ["bunny.off", "camelhead.off", "plane_holes.obj", "fertility.off"])
def test_edges_match_libigl_as_sets(data_dir, name):
    _, F = read_mesh(data_dir / name)
    ours = topology.edges(F)
    assert ours.dtype == np.int64 and ours.shape[1] == 2
    assert np.all(ours[:, 0] < ours[:, 1])
    assert np.array_equal(ours, np.unique(ours, axis=0))  # sorted, no duplicates
    theirs = np.sort(igl.edges(F), axis=1)
    assert {tuple(e) for e in ours.tolist()} == {tuple(e) for e in theirs.tolist()}
    assert len(ours) == len(theirs)


def test_edges_of_procedural_shapes_match_libigl():
    for V, F in [datasets.torus(n_major=17, n_minor=9), datasets.disk(5, 23), datasets.cube(3)]:
        ours = {tuple(e) for e in topology.edges(F).tolist()}
        theirs = {tuple(e) for e in np.sort(igl.edges(F), axis=1).tolist()}
        assert ours == theirs


@pytest.mark.parametrize("name", WITH_BOUNDARY)
def test_boundary_loops_match_libigl_vertex_for_vertex(data_dir, name):
    _, F = read_mesh(data_dir / name)
    ours = topology.boundary_loops(F)
    assert all(loop.dtype == np.int64 for loop in ours)
    lengths = [len(loop) for loop in ours]
    assert lengths == sorted(lengths, reverse=True)
    theirs = igl.boundary_loop_all(F)
    # Same loops, same start vertex and same direction (libigl's order is by start vertex).
    assert sorted(tuple(loop.tolist()) for loop in ours) == sorted(tuple(loop) for loop in theirs)
    longest = igl.boundary_loop(F)
    if len(ours) == 1 or len(ours[0]) > len(ours[1]):
        assert np.array_equal(ours[0], longest)


def test_boundary_loop_follows_the_faces_and_is_closed():
    V, F = datasets.grid(4, 3)
    (loop,) = topology.boundary_loops(F)
    assert len(loop) == 2 * (4 + 3) and loop[0] == loop.min()
    directed = {(a, b) for f in F.tolist() for a, b in zip(f, f[1:] + f[:1])}
    assert all((a, b) in directed for a, b in zip(loop, np.roll(loop, -1)))
    # The grid's normals are +z, so its boundary runs counter-clockwise seen from +z.
    P = V[loop, :2]
    assert 0.5 * np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1]) > 0
    assert topology.boundary_loops(datasets.icosphere(1)[1]) == []


def test_boundary_loops_of_a_pinched_boundary_share_the_pinch_vertex():
    # Two triangles touching at vertex 0: two loops of three, both through vertex 0.
    F = np.array([[0, 1, 2], [0, 3, 4]])
    loops = topology.boundary_loops(F)
    assert [loop.tolist() for loop in loops] == [[0, 1, 2], [0, 3, 4]]


def _several_components():
    parts = [datasets.torus(n_major=12, n_minor=6), datasets.icosphere(1), datasets.grid(3, 2)]
    V, F, offset = [], [], 0
    for P, T in parts:
        V.append(P + [3.0 * len(V), 0, 0])
        F.append(T + offset)
        offset += len(P)
    V.append(np.zeros((2, 3)))  # two unreferenced vertices at the end
    return np.vstack(V), np.vstack(F), [len(T) for _, T in parts]


def test_connected_components_agree_with_libigl_and_label_unreferenced_vertices():
    V, F, face_counts = _several_components()
    components = topology.connected_components(F, n_vertices=len(V))
    assert components.count == 3
    assert components.face_labels.tolist() == sum(([c] * n for c, n in enumerate(face_counts)), [])
    assert components.vertex_labels.dtype == np.int64 and len(components.vertex_labels) == len(V)
    assert components.vertex_labels[-2:].tolist() == [-1, -1]
    referenced = components.vertex_labels >= 0
    theirs = igl.vertex_components(F)                  # one label per vertex up to F.max()
    assert len(theirs) == len(V) - 2
    # Same partition of the referenced vertices (labels may be numbered differently).
    pairs = set(zip(components.vertex_labels[referenced].tolist(), theirs.tolist()))
    assert len(pairs) == 3
    assert np.array_equal(components.vertex_labels[F[:, 0]], components.face_labels)
    # Without n_vertices the trailing unreferenced vertices are not known.
    assert len(topology.connected_components(F).vertex_labels) == len(V) - 2


def test_components_are_vertex_connected():
    F = np.array([[0, 1, 2], [0, 3, 4], [5, 6, 7]])  # two triangles sharing only vertex 0
    components = topology.connected_components(F)
    assert components.count == 2 and components.face_labels.tolist() == [0, 0, 1]


def test_genus_per_component_and_total():
    V, F, _ = _several_components()
    assert topology.genus(F, per_component=True).tolist() == [1, 0, 0]
    assert topology.genus(F) == 1
    info = topology.info(V, F)
    assert (info.n_components, info.n_boundary_loops, info.genus) == (3, 1, 1)
    assert info.n_unreferenced_vertices == 2
    assert info.euler_characteristic == 0 + 2 + 1


def test_complex_edge_file(data_dir):
    V, F = read_polygon_obj_as_fan(data_dir / "cubes_complex_edge.obj")
    assert (len(V), len(F)) == (14, 24)
    bad_edges = topology.non_manifold_edges(F)
    assert bad_edges.shape == (1, 2)
    counts = {}
    for f in F.tolist():
        for a, b in zip(f, f[1:] + f[:1]):
            counts[tuple(sorted((a, b)))] = counts.get(tuple(sorted((a, b))), 0) + 1
    assert counts[tuple(bad_edges[0])] == 4
    assert sorted(topology.non_manifold_vertices(F).tolist()) == sorted(bad_edges[0].tolist())
    assert not topology.is_manifold(F) and topology.is_oriented(F)
    assert topology.euler_characteristic(F) == 3
    with pytest.raises(meshsmith.InputError, match=r"edge \(\d+, \d+\) has more than two faces"):
        topology.genus(F)
    info = topology.info(V, F)
    assert info.genus is None and not info.is_manifold
    assert (info.n_non_manifold_edges, info.n_non_manifold_vertices) == (1, 2)
    assert info.volume == pytest.approx(2.0)
    assert "undefined" in str(info)
    ok, *_ = igl.is_edge_manifold(F)
    assert not ok


def test_complex_vertex_file(data_dir):
    V, F = read_polygon_obj_as_fan(data_dir / "cubes_complex_vertex.obj")
    assert (len(V), len(F)) == (15, 24)
    assert topology.non_manifold_edges(F).shape == (0, 2)
    bad = topology.non_manifold_vertices(F)
    assert len(bad) == 1
    # libigl agrees on which vertex is not vertex-manifold.
    assert np.flatnonzero(~igl.is_vertex_manifold(F)).tolist() == bad.tolist()
    assert not topology.is_manifold(F) and topology.is_oriented(F)
    assert topology.euler_characteristic(F) == 3
    assert topology.boundary_loops(F) == []
    with pytest.raises(meshsmith.InputError, match=f"vertex {bad[0]} joins several fans"):
        topology.genus(F)
    assert topology.connected_components(F).count == 1   # vertex-connected


@pytest.mark.parametrize("name", ["cubes_complex_edge.obj", "cubes_complex_vertex.obj"])
def test_split_non_manifold_makes_the_cube_files_manifold_without_moving_points(data_dir, name):
    V, F = read_polygon_obj_as_fan(data_dir / name)
    V2, F2, origin = topology.split_non_manifold_vertices(V, F)
    assert V2.dtype == np.float64 and F2.dtype == np.int64 and origin.dtype == np.int64
    assert topology.is_manifold(F2) and topology.is_oriented(F2)
    assert np.array_equal(V2, V[origin])
    assert np.array_equal(origin[F2], F)                  # same faces on the same points
    assert np.array_equal(origin[:len(V)], np.arange(len(V)))
    extra = 1 if "vertex" in name else 2                  # one copy per extra fan
    assert len(V2) == len(V) + extra
    # Two closed cubes, each a sphere: the split recovered the intended surfaces.
    assert topology.connected_components(F2).count == 2
    assert topology.genus(F2, per_component=True).tolist() == [0, 0]
    assert topology.boundary_loops(F2) == []
    assert geometry.volume(V2, F2) == pytest.approx(2.0)


def test_split_detaches_the_faces_of_a_fin():
    # Three triangles on edge (0, 1): each is its own fan at both ends of the edge.
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1]])
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    assert topology.non_manifold_edges(F).tolist() == [[0, 1]]
    assert topology.non_manifold_vertices(F).tolist() == [0, 1]
    V2, F2, origin = topology.split_non_manifold_vertices(V, F)
    assert topology.is_manifold(F2) and np.array_equal(V2, V[origin])
    assert len(V2) == 5 + 4 and topology.connected_components(F2).count == 3


def test_split_leaves_a_manifold_mesh_unchanged():
    V, F = datasets.torus(n_major=10, n_minor=5)
    V2, F2, origin = topology.split_non_manifold_vertices(V, F)
    assert np.array_equal(V2, V) and np.array_equal(F2, F) and np.array_equal(origin, np.arange(len(V)))


def test_orientation_flip_and_mobius_strip():
    V, F = datasets.icosphere(2)
    assert topology.is_oriented(F)
    flipped = F.copy()
    flipped[7] = flipped[7, ::-1]
    assert not topology.is_oriented(flipped) and topology.is_manifold(flipped)
    assert topology.genus(flipped) == 0          # orientable, just not oriented
    # Möbius strip: a band of 2n triangles whose ends are glued with a half twist.
    n = 12
    top, bottom = np.arange(n), np.arange(n, 2 * n)
    F_strip = []
    for i in range(n - 1):
        F_strip += [[top[i], bottom[i], bottom[i + 1]], [top[i], bottom[i + 1], top[i + 1]]]
    F_strip += [[top[n - 1], bottom[n - 1], top[0]], [top[n - 1], top[0], bottom[0]]]  # twist
    F_strip = np.array(F_strip)
    assert topology.is_manifold(F_strip) and not topology.is_oriented(F_strip)
    assert len(topology.boundary_loops(F_strip)) == 1     # a Möbius strip has one boundary
    assert topology.euler_characteristic(F_strip) == 0
    with pytest.raises(meshsmith.InputError, match="not orientable"):
        topology.genus(F_strip)
    V_strip = np.random.default_rng(0).normal(size=(2 * n, 3))
    assert topology.info(V_strip, F_strip).genus is None


def test_degenerate_faces_do_not_break_anything():
    F = np.array([[0, 1, 2], [0, 2, 3], [1, 1, 2]])     # last face repeats a vertex
    assert {tuple(e) for e in topology.edges(F).tolist()} == {(0, 1), (1, 2), (0, 2), (2, 3), (0, 3)}
    assert topology.euler_characteristic(F) == 4 - 5 + 3
    topology.non_manifold_vertices(F)
    topology.boundary_loops(F)


def test_info_prints_an_aligned_block(data_dir):
    V, F = read_mesh(data_dir / "stanford-bunny.obj")
    text = str(topology.info(V, F))
    lines = text.splitlines()
    assert len(lines) >= 12
    value_columns = {len(re.match(r"^(\S+(?: \S+)*\s+)", line).group(1)) for line in lines}
    assert len(value_columns) == 1                    # every value starts in the same column
    assert "35,947  (1,113 unreferenced)" in text and "5  (223 edges)" in text
    assert "genus                 0" in text


def test_info_geometric_fields():
    V, F = datasets.cube(4, size=2.0)
    info = topology.info(V, F)
    assert info.surface_area == pytest.approx(24.0) and info.volume == pytest.approx(8.0)
    assert np.allclose(info.bounding_box[0], -1) and np.allclose(info.bounding_box[1], 1)


BAD_FACES = [
    (np.zeros((0, 3), dtype=int), "F is empty"),
    (np.array([[0, 1, -1]]), "indexes vertex -1"),
    (np.array([[0, 1, 2.0]]), "expected integer indices"),
    (np.array([[0, 1]]), "F has shape (1, 2)"),
]


@pytest.mark.parametrize("F, message", BAD_FACES)
@pytest.mark.parametrize("function", [topology.edges, topology.boundary_loops,
                                      topology.connected_components, topology.euler_characteristic,
                                      topology.genus, topology.non_manifold_edges,
                                      topology.non_manifold_vertices, topology.is_manifold,
                                      topology.is_oriented])
def test_bad_faces_raise_input_error(function, F, message):
    with pytest.raises(meshsmith.InputError, match=re.escape(message)):
        function(F)


@pytest.mark.parametrize("function", [topology.info, topology.split_non_manifold_vertices,
                                      topology.euler_characteristic])
def test_bad_meshes_raise_input_error(function):
    V, F = datasets.icosphere(0)
    with pytest.raises(meshsmith.InputError, match=re.escape("V[3, 1] is nan")):
        function(np.where(np.arange(len(V))[:, None] * 3 + np.arange(3) == 10, np.nan, V), F)
    with pytest.raises(meshsmith.InputError, match="indexes vertex 12, outside"):
        function(V, np.vstack([F, [[0, 1, 12]]]))
    with pytest.raises(meshsmith.InputError, match="V is empty"):
        function(np.zeros((0, 3)), F)
    with pytest.raises(meshsmith.InputError, match="F is empty"):
        function(V, F[:0])


def test_connected_components_rejects_an_index_beyond_n_vertices():
    with pytest.raises(meshsmith.InputError, match=r"indexes vertex 5, outside \[0, 4\)"):
        topology.connected_components(np.array([[0, 1, 5]]), n_vertices=4)


def test_inputs_are_not_modified():
    V, F = datasets.cube(2)
    V0, F0 = V.copy(), F.copy()
    topology.split_non_manifold_vertices(V, F)
    topology.info(V, F)
    topology.boundary_loops(F)
    assert np.array_equal(V, V0) and np.array_equal(F, F0)


@pytest.mark.parametrize("n_vertices, message", [(-1, "n_vertices = -1: expected an integer in [0, 2147483647]"),
                                                 (2.5, "n_vertices = 2.5: expected an integer"),
                                                 (np.nan, "n_vertices = nan: expected an integer"),
                                                 (2**40, "n_vertices = 1099511627776: expected an integer in [0, 2147483647]"),
                                                 (2**70, "expected an integer in [0, 2147483647]")])
def test_connected_components_rejects_a_bad_vertex_count(n_vertices, message):
    with pytest.raises(meshsmith.InputError, match=re.escape(message)):
        topology.connected_components(np.array([[0, 1, 2]]), n_vertices=n_vertices)


def test_a_stray_huge_index_is_rejected_instead_of_allocating_for_it():
    F = np.array([[0, 1, 2], [0, 2, 2_000_000_000]])
    with pytest.raises(meshsmith.InputError, match=re.escape("F[1] = (0, 2, 2000000000) indexes vertex")):
        topology.edges(F)
    # With an explicit vertex count the caller decides how many vertices there are.
    labels = topology.connected_components(np.array([[0, 1, 2]]), n_vertices=10).vertex_labels
    assert labels.tolist() == [0, 0, 0] + [-1] * 7


def _random_damaged_spheres(count, seed=0):
    """Random subsets of an icosphere's faces with a few vertices glued together: holes,
    pinched boundaries, pinch vertices and non-manifold edges in every combination."""
    rng = np.random.default_rng(seed)
    V, F = datasets.icosphere(2)
    for _ in range(count):
        glue = np.arange(len(V))
        for _ in range(rng.integers(0, 4)):
            a, b = rng.integers(0, len(V), 2)
            glue[glue == b] = a
        G = glue[F[rng.random(len(F)) < rng.uniform(0.3, 1.0)]]
        G = G[(G[:, 0] != G[:, 1]) & (G[:, 1] != G[:, 2]) & (G[:, 0] != G[:, 2])]
        if len(G):
            yield V, G


def test_split_makes_any_damaged_mesh_manifold():
    for V, F in _random_damaged_spheres(150):
        V2, F2, origin = topology.split_non_manifold_vertices(V, F)
        assert topology.is_manifold(F2)
        assert np.array_equal(origin[F2], F) and np.array_equal(V2, V[origin])
        if topology.is_manifold(F):
            assert np.array_equal(F2, F) and len(V2) == len(V)


def test_non_manifold_vertices_and_loops_agree_with_libigl_on_damaged_meshes():
    compared_loops = 0
    for _, F in _random_damaged_spheres(150, seed=1):
        if len(topology.non_manifold_edges(F)):
            continue   # libigl's is_vertex_manifold leaves non-manifold edges to is_edge_manifold
        used = np.unique(F)
        theirs = used[~igl.is_vertex_manifold(F)[used]]
        ours = topology.non_manifold_vertices(F)
        assert ours.tolist() == theirs.tolist()
        if len(ours) == 0:
            compared_loops += 1
            assert (sorted(tuple(loop.tolist()) for loop in topology.boundary_loops(F))
                    == sorted(tuple(loop) for loop in igl.boundary_loop_all(F)))
    assert compared_loops >= 1


def test_boundary_loops_agree_with_libigl_on_spheres_with_random_holes():
    rng = np.random.default_rng(2)
    V, F = datasets.icosphere(3)
    compared = 0
    for _ in range(60):
        G = np.delete(F, rng.choice(len(F), size=rng.integers(2, 12), replace=False), axis=0)
        if len(topology.non_manifold_vertices(G)):
            continue   # a pinched boundary can be walked in more than one way
        compared += 1
        ours = topology.boundary_loops(G)
        assert len(ours) >= 1
        assert (sorted(tuple(loop.tolist()) for loop in ours)
                == sorted(tuple(loop) for loop in igl.boundary_loop_all(G)))
        info = topology.info(V, G)
        assert info.genus == 0 and info.n_boundary_loops == len(ours)
    assert compared > 10


@pytest.mark.parametrize("name", ["cubes_complex_edge.obj", "cubes_complex_vertex.obj"])
def test_split_creates_as_many_vertices_as_libigl(data_dir, name):
    V, F = read_polygon_obj_as_fan(data_dir / name)
    V2, _, _ = topology.split_non_manifold_vertices(V, F)
    V_igl, F_igl, _ = igl.split_nonmanifold(V, F)
    assert len(V2) == len(V_igl) and topology.is_manifold(F_igl)


def test_info_text_of_a_non_manifold_mesh(data_dir):
    text = str(topology.info(*read_polygon_obj_as_fan(data_dir / "cubes_complex_edge.obj")))
    assert "no  (1 non-manifold edge, 2 non-manifold vertices)" in text
    assert "genus                 undefined" in text
    assert re.search(r"^volume\s+2$", text, re.MULTILINE)   # closed and oriented: a true volume


def _same_partition(a, b):
    """True when label arrays a and b group the elements the same way."""
    pairs = set(zip(np.asarray(a).tolist(), np.asarray(b).tolist()))
    return len(pairs) == len(set(np.asarray(a).tolist())) == len(set(np.asarray(b).tolist()))


def test_edge_connected_components_agree_with_libigl_facet_components():
    F = np.array([[0, 1, 2], [0, 3, 4], [5, 6, 7], [1, 2, 8]])  # 0 and 1 touch at a vertex only
    by_edge = topology.connected_components(F, connectivity="edge")
    assert by_edge.count == 3 and by_edge.face_labels.tolist() == [0, 1, 2, 0]
    assert by_edge.vertex_labels[0] == 0                        # the pinch: its lowest face's
    assert topology.connected_components(F).count == 2
    for _, G in _random_damaged_spheres(60, seed=3):
        ours = topology.connected_components(G, connectivity="edge")
        count, theirs = igl.facet_components(G)
        assert ours.count == count and _same_partition(ours.face_labels, theirs)
        by_vertex = topology.connected_components(G)
        assert _same_partition(by_vertex.vertex_labels[np.unique(G)], igl.vertex_components(G)[np.unique(G)])


def test_edge_connectivity_separates_the_cubes_touching_at_a_vertex(data_dir):
    _, F = read_polygon_obj_as_fan(data_dir / "cubes_complex_vertex.obj")
    assert topology.connected_components(F, connectivity="edge").count == 2
    assert topology.connected_components(F, connectivity="vertex").count == 1


def test_unknown_connectivity_is_an_input_error():
    with pytest.raises(meshsmith.InputError, match="connectivity must be 'vertex' or 'edge', got 'face'"):
        topology.connected_components(np.array([[0, 1, 2]]), connectivity="face")
