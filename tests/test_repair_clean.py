"""meshsmith.repair: clean, remove_unreferenced, orient_faces and merge_close_vertices (§2.4).

Invariants after clean (no unreferenced vertex, no degenerate or duplicate face, manifold,
consistently oriented, closed components of positive volume, maps that reproduce the output
from the input) on synthetic meshes with known defects and counts, and on every mesh of
../shared/data, which then also goes through parametrize and the demo.
"""
import contextlib
import io as text_io
import json

import numpy as np
import pytest

import meshsmith
from meshsmith import cli, core, datasets, geometry, parametrization, repair, topology
from meshsmith.demo import STAGES

COUNTS = ["merged_vertices", "degenerate_faces", "zero_area_faces", "duplicate_faces", "non_manifold_vertices",
          "non_manifold_edges", "vertex_copies", "small_components", "small_component_faces", "flipped_faces",
          "non_orientable_components", "needle_collapses", "needle_faces", "cap_flips", "unreferenced_vertices"]


def assert_clean(V, F, report, V_in, F_in, *, merge_tolerance=0.0):
    """The invariants of clean's output with the default options, and its maps and identities."""
    V_in, F_in = np.asarray(V_in, dtype=float), np.asarray(F_in)
    assert V.dtype == np.float64 and F.dtype == np.int64 and F.shape[1:] == (3,)
    np.testing.assert_array_equal(np.unique(F), np.arange(len(V)))            # every vertex used
    defects = core.mesh_defects(V, F)
    assert defects.empty, defects.summary
    assert topology.is_manifold(F) and topology.is_oriented(F)
    components = topology.connected_components(F, len(V))
    for label in range(components.count):
        faces = F[components.face_labels == label]
        if not topology.boundary_loops(faces):
            assert geometry.volume(V, faces) > 0, f"closed component {label} is inside out"
    # maps: each output vertex is an input vertex, each output face an input face (maybe reversed)
    np.testing.assert_array_equal(V, V_in[report.vertex_map])
    corners = V_in[F_in[report.face_map]]
    corners[report.flipped] = corners[report.flipped][:, [0, 2, 1]]
    np.testing.assert_allclose(V[F], corners, rtol=0, atol=3 * merge_tolerance)
    assert len(V) == len(V_in) - report.merged_vertices - report.unreferenced_vertices + report.vertex_copies
    assert len(F) == len(F_in) - report.degenerate_faces - report.zero_area_faces - report.duplicate_faces \
        - report.small_component_faces
    assert report.flipped_faces == len(report.flipped)


def expect(report, **counts):
    """The report's counts are `counts`, every other one zero."""
    assert report.counts() == {name: counts.get(name, 0) for name in COUNTS}


# ---- synthetic meshes with known defects -----------------------------------------------------

def test_clean_mesh_is_unchanged():
    V, F = datasets.torus(n_major=24, n_minor=12)
    V2, F2, report = repair.clean(V, F)
    expect(report)
    assert not report.changed and str(report) == "nothing to change"
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_array_equal(report.vertex_map, np.arange(len(V)))
    np.testing.assert_array_equal(report.face_map, np.arange(len(F)))


def test_unreferenced_vertices():
    V, F = datasets.icosphere(2)
    extra = np.array([[5.0, 5, 5], [6.0, 6, 6], [7.0, 7, 7]])
    V_in = np.vstack([extra[:1], V[:50], extra[1:2], V[50:], extra[2:]])        # at 0, 51 and the end
    F_in = np.where(F >= 50, F + 2, F + 1)
    V2, F2, report = repair.clean(V_in, F_in)
    expect(report, unreferenced_vertices=3)
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)
    assert_clean(V2, F2, report, V_in, F_in)
    removed = repair.remove_unreferenced(V_in, F_in)
    V3, F3, vertex_map = removed
    np.testing.assert_array_equal(V3, V)
    np.testing.assert_array_equal(F3, F)
    np.testing.assert_array_equal(vertex_map, np.setdiff1d(np.arange(len(V_in)), [0, 51, len(V_in) - 1]))
    assert removed.removed == 3 and removed.input_vertex_count == len(V_in)
    rows = removed.to_input_rows(np.arange(len(V3), dtype=float))
    assert np.isnan(rows[[0, 51, len(V_in) - 1]]).all() and np.array_equal(rows[vertex_map], np.arange(len(V3)))
    np.testing.assert_array_equal(removed.from_input_indices([1, 52]), [0, 50])
    with pytest.raises(meshsmith.InputError, match="vertex 51 is used by no face"):
        removed.from_input_indices([1, 51])
    with pytest.raises(meshsmith.InputError, match="outside"):
        removed.from_input_indices([len(V_in)])


def test_remove_unreferenced_copies_and_never_modifies_the_input():
    V, F = datasets.icosphere(1)
    V_in, F_in = V.copy(), F.astype(np.int32)
    V_in.setflags(write=False)
    V2, F2, vertex_map = repair.remove_unreferenced(V_in, F_in)
    V2[0] = 99.0
    F2[0] = 0
    assert F2.dtype == np.int64 and not np.shares_memory(V2, V_in)
    np.testing.assert_array_equal(V_in, V)
    np.testing.assert_array_equal(F_in, F)
    # (ragged lists and None are issue 14 part 1's conversion, tested with every function there)
    for bad in (np.zeros((len(V), 2)), np.full_like(V, np.nan)):
        with pytest.raises(meshsmith.InputError):
            repair.remove_unreferenced(bad, F)
    with pytest.raises(meshsmith.InputError):
        repair.remove_unreferenced(V, F + len(V))


def test_coincident_vertices_are_merged():
    # Two vertices duplicated and some of their faces moved to the copies: a crack, closed again.
    V, F = datasets.icosphere(2)
    V_in = np.vstack([V, V[[3, 40]]])
    F_in = F.copy()
    for copy, original in ((len(V), 3), (len(V) + 1, 40)):
        faces = np.flatnonzero((F == original).any(axis=1))[:2]
        F_in[faces] = np.where(F_in[faces] == original, copy, F_in[faces])
    V2, F2, report = repair.clean(V_in, F_in)
    expect(report, merged_vertices=2)
    np.testing.assert_array_equal(F2, F)
    assert_clean(V2, F2, report, V_in, F_in)
    # None turns merging off: the copies stay
    V3, _, report = repair.clean(V_in, F_in, merge_tolerance=None)
    assert report.merged_vertices == 0 and len(V3) >= len(V_in)


def test_merge_tolerance_joins_near_vertices_transitively():
    V, F = datasets.icosphere(2)
    rng = np.random.default_rng(1)
    # every vertex of ten faces that share no vertex gets a private copy, moved by at most 1e-7
    F_in = F.copy()
    extra, chosen, taken = [], [], set()
    for f in range(len(F)):
        if len(chosen) < 10 and not taken & set(F[f]):
            chosen.append(f)
            taken |= set(F[f])
    for f in chosen:
        for k in range(3):
            extra.append(V[F[f, k]] + rng.uniform(-1e-7, 1e-7, 3) / np.sqrt(3))
            F_in[f, k] = len(V) + len(extra) - 1
    V_in = np.vstack([V, extra])
    assert len(topology.boundary_loops(F_in)) > 0
    V2, F2, report = repair.clean(V_in, F_in, merge_tolerance=1e-6)
    expect(report, merged_vertices=30)
    np.testing.assert_array_equal(F2, F)
    assert_clean(V2, F2, report, V_in, F_in, merge_tolerance=1e-6)
    assert repair.clean(V_in, F_in).report.merged_vertices == 0     # exact merging finds none

    group, representatives = repair.merge_close_vertices([[0.0, 0, 0], [0.6, 0, 0], [1.2, 0, 0], [5, 0, 0]], tolerance=0.7)
    np.testing.assert_array_equal(group, [0, 0, 0, 1])             # a chain is one group
    np.testing.assert_array_equal(representatives, [0, 3])
    group, _ = repair.merge_close_vertices([[1.0, 0, 0], [0.0, 0, 0], [-0.0, 0, 0], [1.0, 0, 1e-300]])
    np.testing.assert_array_equal(group, [0, 1, 1, 2])             # -0.0 == 0.0; 1e-300 is not 0
    group, _ = repair.merge_close_vertices([[0.0, 0, 0], [1.0, 0, 0]], tolerance=1.0)
    np.testing.assert_array_equal(group, [0, 0])                   # at exactly the tolerance: merged
    for bad in (-1.0, np.nan, np.inf):
        with pytest.raises(meshsmith.InputError, match="merge tolerance"):
            repair.clean(V, F, merge_tolerance=bad)


def test_degenerate_zero_area_and_duplicate_faces():
    V, F = datasets.grid(4, 4)          # on a lattice of quarters: the midpoint of an edge is exact
    a, b, c = F[0]
    if V[a, 1] != V[b, 1] and V[a, 0] != V[b, 0]:
        a, b, c = F[0, 1], F[0, 2], F[0, 0]
    assert V[a, 1] == V[b, 1] or V[a, 0] == V[b, 0]
    midpoint = len(V)
    V_in = np.vstack([V, (V[a] + V[b]) / 2])
    F_in = np.vstack([F,
                      [[a, a, b], [c, b, b]],           # 2 repeated-index faces
                      [[a, midpoint, b]],               # 1 zero-area face (its middle vertex then unused)
                      F[[5, 9]], F[[17]][:, ::-1]])     # 3 duplicates, one of them reversed
    # the middle vertex is exactly on the segment, so the face is exactly flat
    assert geometry.face_areas(V_in, F_in[[len(F) + 2]])[0] == 0.0
    V2, F2, report = repair.clean(V_in, F_in)
    expect(report, degenerate_faces=2, zero_area_faces=1, duplicate_faces=3, unreferenced_vertices=1)
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_array_equal(report.face_map, np.arange(len(F)))
    assert_clean(V2, F2, report, V_in, F_in)
    # remove_degenerate=False keeps them all
    _, F3, report = repair.clean(V_in, F_in, remove_degenerate=False, split_non_manifold=False, orient=False)
    assert len(F3) == len(F_in) and report.unreferenced_vertices == 0


def test_non_manifold_vertex_and_edge_are_split():
    # Two tetrahedra sharing one corner (a pinch) and a fin on an edge of a sphere.
    tetra = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    tetra_faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    V_in = np.vstack([tetra, -tetra[1:]])
    F_in = np.vstack([tetra_faces, np.where(tetra_faces == 0, 0, tetra_faces + 3)])
    assert topology.non_manifold_vertices(F_in).tolist() == [0]
    V2, F2, report = repair.clean(V_in, F_in)
    expect(report, non_manifold_vertices=1, vertex_copies=1, flipped_faces=4)   # the reflected one was inside out
    assert_clean(V2, F2, report, V_in, F_in)
    assert topology.connected_components(F2).count == 2
    np.testing.assert_array_equal(report.vertex_map, [0, 1, 2, 3, 4, 5, 6, 0])

    V, F = datasets.icosphere(1)
    a, b = F[0, 0], F[0, 1]
    V_in = np.vstack([V, 1.5 * (V[a] + V[b]) / 2])
    F_in = np.vstack([F, [[a, b, len(V)]]])
    V2, F2, report = repair.clean(V_in, F_in)
    expect(report, non_manifold_vertices=2, non_manifold_edges=1, vertex_copies=2)
    assert_clean(V2, F2, report, V_in, F_in)
    # the fin is a component of its own now; min_component_faces removes it and its 3 vertices
    V3, F3, report = repair.clean(V_in, F_in, min_component_faces=2)
    expect(report, non_manifold_vertices=2, non_manifold_edges=1, vertex_copies=2, small_components=1,
           small_component_faces=1, unreferenced_vertices=3)
    np.testing.assert_array_equal(V3, V)
    np.testing.assert_array_equal(F3, F)
    assert_clean(V3, F3, report, V_in, F_in)
    # split_non_manifold=False leaves the edge
    assert not topology.is_manifold(repair.clean(V_in, F_in, split_non_manifold=False).F)


def test_orientation_flips_the_fewest_faces_and_turns_closed_components_outward():
    V, F = datasets.icosphere(2)
    rng = np.random.default_rng(0)
    flipped = np.sort(rng.choice(len(F), 30, replace=False))
    F_in = F.copy()
    F_in[flipped] = F_in[flipped][:, [0, 2, 1]]
    V2, F2, report = repair.clean(V, F_in)
    expect(report, flipped_faces=30)
    np.testing.assert_array_equal(report.flipped, flipped)
    np.testing.assert_array_equal(F2, F)
    assert_clean(V2, F2, report, V, F_in)
    # a sphere inside out: every face flips although they all agree
    _, F3, report = repair.clean(V, F[:, [0, 2, 1]])
    expect(report, flipped_faces=len(F))
    np.testing.assert_array_equal(F3, F)
    # an open disk keeps its majority orientation, either way up
    Vd, Fd = datasets.disk(6, 24)
    for disk_faces in (Fd, Fd[:, [0, 2, 1]]):
        F_in = disk_faces.copy()
        F_in[:5] = F_in[:5][:, [0, 2, 1]]
        _, F4, report = repair.clean(Vd, F_in)
        expect(report, flipped_faces=5)
        np.testing.assert_array_equal(F4, disk_faces)
    # --no-orient
    assert repair.clean(V, F[:, [0, 2, 1]], orient=False).report.flipped_faces == 0


def test_orient_faces_counts_components_and_non_orientable_ones():
    # A Möbius strip: a band of n quads whose ends are joined with a half twist.
    n = 24
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rim = [np.column_stack([(1 + s * np.cos(t / 2)) * np.cos(t), (1 + s * np.cos(t / 2)) * np.sin(t),
                            s * np.sin(t / 2)]) for s in (-0.3, 0.3)]
    V = np.vstack(rim)
    faces = []
    for i in range(n):
        j = (i + 1) % n
        low, high = (j, n + j) if j else (n, 0)      # the twist swaps the two rims
        faces += [[i, low, n + i], [low, high, n + i]]
    F = np.array(faces)
    assert topology.is_manifold(F)
    oriented = repair.orient_faces(V, F)
    assert (oriented.components, oriented.closed_components, oriented.non_orientable_components) == (1, 0, 1)
    assert repair.clean(V, F).report.non_orientable_components == 1
    Vs, Fs = datasets.icosphere(1)
    both = repair.orient_faces(np.vstack([Vs, Vs + 5]), np.vstack([Fs, Fs[:, ::-1] + len(Vs)]))
    assert (both.components, both.closed_components, both.non_orientable_components) == (2, 2, 0)
    np.testing.assert_array_equal(both.flipped, np.arange(len(Fs), 2 * len(Fs)))
    F_out, flips = both
    assert topology.is_oriented(F_out) and flips is both.flipped


def test_everything_at_once():
    V, F = datasets.icosphere(2)
    Vs, Fs = datasets.icosphere(1)
    V_in = np.vstack([V, Vs + 4.0, [[9.0, 9, 9]], [[20.0, 0, 0], [21, 0, 0], [20, 1, 0]], V[[7]]])
    s, lone, copy = len(V), len(V) + len(Vs) + 1, len(V_in) - 1
    F_in = np.vstack([F, Fs[:, ::-1] + s,                 # an inside-out second sphere
                      [[lone, lone + 1, lone + 2]],       # a lone triangle
                      [[0, 0, 1]], F[[3]]])               # a degenerate and a duplicate face
    first = np.flatnonzero((F_in == 7).any(axis=1))[0]
    F_in[first] = np.where(F_in[first] == 7, copy, F_in[first])     # a face on a coincident copy of vertex 7
    V2, F2, report = repair.clean(V_in, F_in, min_component_faces=2)
    expect(report, merged_vertices=1, degenerate_faces=1, duplicate_faces=1, small_components=1,
           small_component_faces=1, flipped_faces=len(Fs), unreferenced_vertices=4)
    assert_clean(V2, F2, report, V_in, F_in)
    assert report.lines() == ["1 merged vertices", "1 degenerate faces removed (repeated vertex)",
                              "1 duplicate faces removed", "1 small components removed",
                              "1 faces of small components removed", "80 faces flipped to orient",
                              "4 unreferenced vertices removed"]
    assert len(report.lines(all_kinds=True)) == len(COUNTS)


def test_triangle_soup_is_welded():
    # Every face on its own three vertices, as STL-like exports write them.
    V, F = datasets.icosphere(2)
    V_in, F_in = V[F].reshape(-1, 3), np.arange(3 * len(F)).reshape(-1, 3)
    V2, F2, report = repair.clean(V_in, F_in)
    expect(report, merged_vertices=3 * len(F) - len(V))
    assert_clean(V2, F2, report, V_in, F_in)
    assert topology.info(V2, F2).genus == 0 and not topology.boundary_loops(F2)


@pytest.mark.parametrize("seed", range(8))
def test_randomly_broken_meshes_come_out_clean(seed):
    # Faces deleted, flipped, duplicated (either way round) and degenerate; vertices shuffled,
    # duplicated at the same position and left unused; a second, inside-out component.
    rng = np.random.default_rng(seed)
    Vt, Ft = datasets.torus(n_major=20, n_minor=10)
    Vs, Fs = datasets.icosphere(1)
    V = np.vstack([Vt, Vs * 0.3 + [3.0, 0, 0]])
    F = np.vstack([Ft, Fs[:, ::-1] + len(Vt)])
    F = F[rng.random(len(F)) > 0.05]
    flip = rng.random(len(F)) < 0.1
    F[flip] = F[flip][:, ::-1]
    copies = F[rng.choice(len(F), 10)]
    copies[::2] = copies[::2, ::-1]
    degenerate = np.repeat(rng.choice(len(V), (4, 1)), 3, axis=1)
    degenerate[:, 2] = rng.choice(len(V), 4)
    F = np.vstack([F, copies, degenerate])
    twins = rng.choice(np.unique(F), 6, replace=False)        # coincident copies, each used by one corner
    flat = F.reshape(-1)
    for k, twin in enumerate(twins):
        flat[rng.choice(np.flatnonzero(flat == twin))] = len(V) + k
    V = np.vstack([V, V[twins], rng.random((5, 3))])          # and 5 unused vertices
    order = rng.permutation(len(V))
    V_in, F_in = V[order], np.argsort(order)[F]
    V2, F2, report = repair.clean(V_in, F_in)
    assert_clean(V2, F2, report, V_in, F_in)
    assert report.merged_vertices == len(twins)
    assert report.degenerate_faces >= 4 and report.duplicate_faces == len(copies)
    assert report.flipped_faces > 0 and report.unreferenced_vertices >= 5


def test_everything_removed_gives_an_empty_mesh():
    V = np.eye(3)
    V2, F2, report = repair.clean(V, [[0, 1, 1], [2, 2, 2]])
    assert V2.shape == (0, 3) and F2.shape == (0, 3)
    expect(report, degenerate_faces=2, unreferenced_vertices=3)


def test_bad_input_and_options():
    V, F = datasets.icosphere(1)
    for bad in (np.zeros((len(V), 2)), np.full_like(V, np.nan), np.zeros((0, 3))):
        with pytest.raises(meshsmith.InputError):
            repair.clean(bad, F)
    with pytest.raises(meshsmith.InputError):
        repair.clean(V, F + 100)
    for bad in (-1, 1.5, True):
        with pytest.raises(meshsmith.InputError, match="min_component_faces"):
            repair.clean(V, F, min_component_faces=bad)
    V_in, F_in = V.copy(), F.copy()
    repair.clean(V_in, F_in[:, ::-1], merge_tolerance=0.1, min_component_faces=3)
    np.testing.assert_array_equal(V_in, V)
    np.testing.assert_array_equal(F_in, F)


def test_cli_clean_prints_every_kind_with_its_count(tmp_path):
    V, F = datasets.icosphere(2)
    V_in = np.vstack([V, [[5.0, 5, 5]]])
    F_in = np.vstack([F[:, [0, 2, 1]], [[0, 0, 1]]])
    source, target = tmp_path / "in.obj", tmp_path / "out.ply"
    meshsmith.io.write_mesh(source, V_in, F_in)
    out = text_io.StringIO()
    with contextlib.redirect_stdout(out):
        assert cli.main(["clean", str(source), "-o", str(target)]) == 0
    lines = out.getvalue().splitlines()
    assert lines[0].endswith(f"{len(V)} vertices, {len(F)} faces")
    counts = {line.rsplit(None, 1)[0].strip(): int(line.rsplit(None, 1)[1].replace(",", "")) for line in lines[1:]}
    assert counts["faces flipped to orient"] == len(F) and counts["unreferenced vertices removed"] == 1
    assert counts["degenerate faces removed (repeated vertex)"] == 1 and len(counts) == len(COUNTS)
    V2, F2 = meshsmith.io.read_mesh(target)
    np.testing.assert_array_equal(F2, F)
    with contextlib.redirect_stdout(text_io.StringIO()):
        assert cli.main(["clean", str(source), "-o", str(target), "--no-orient", "--min-component-faces", "5",
                         "--merge-tolerance", "1e-9"]) == 0
    assert topology.is_oriented(meshsmith.io.read_mesh(target)[1]) and not np.array_equal(
        meshsmith.io.read_mesh(target)[1], F)
    with contextlib.redirect_stderr(text_io.StringIO()) as err:
        assert cli.main(["clean", str(source), "-o", str(target), "--merge-tolerance", "-1"]) == 1
    assert "merge tolerance" in err.getvalue()


def test_parametrization_refuses_non_manifold_input_naming_clean():
    V, F = datasets.disk(4, 12)
    V_in = np.vstack([V, [[0.0, 0.0, 1.0]]])
    F_in = np.vstack([F, [[F[0, 0], F[0, 1], len(V)]]])
    for function in (parametrization.parametrize, parametrization.cut_to_disk, parametrization.lscm,
                     parametrization.abf):
        with pytest.raises(meshsmith.InputError, match=r"meshsmith\.repair\.clean \(`meshsmith clean`"):
            function(V_in, F_in)
    Vs, Fs = datasets.icosphere(1)
    with pytest.raises(meshsmith.InputError, match=r"meshsmith\.repair\.clean"):
        meshsmith.decimation.progressive_mesh(Vs, np.vstack([Fs, Fs[:1, ::-1]]))   # a two-sided face


def test_parametrize_charts_every_component_side_by_side():
    V, F = datasets.icosphere(2)
    Vd, Fd = datasets.disk(5, 20)
    V_in = np.vstack([[[7.0, 7, 7]], V, Vd + [3.0, 0, 0]])
    F_in = np.vstack([F + 1, Fd + 1 + len(V)])
    result = parametrization.parametrize(V_in, F_in, method="tutte")
    assert np.isnan(result.uv[0]).all() and np.isfinite(result.uv[1:]).all()
    assert result.bijective and result.cut is not None and len(result.uv) == len(result.V)
    sphere_u = result.uv[np.unique(result.F[:len(F)]), 0]
    disk_u = result.uv[np.unique(result.F[len(F):]), 0]
    assert sphere_u.max() < disk_u.min()                      # the second chart right of the first
    np.testing.assert_array_equal(result.cut.V[result.cut.vertex_origin], result.cut.V)
    np.testing.assert_array_equal(result.cut.V[:len(V_in)], V_in)
    np.testing.assert_array_equal(result.cut.vertex_origin[result.F], F_in)
    np.testing.assert_array_equal(result.cut.V[result.F], V_in[F_in])


# ---- the shared meshes -----------------------------------------------------------------------

#: What clean changes on the shared meshes (../shared/data/README.md lists their defects); the
#: others are clean already.
SHARED_DEFECTS = {
    "stanford-bunny.obj": {"unreferenced_vertices": 1113},
    "cubes_complex_edge.obj": {"non_manifold_vertices": 2, "non_manifold_edges": 1, "vertex_copies": 2},
    "cubes_complex_vertex.obj": {"non_manifold_vertices": 1, "vertex_copies": 1},
}
PROBLEM_MESHES = ["stanford-bunny.obj", "cubes_complex_edge.obj", "cubes_complex_vertex.obj", "plane_holes.obj"]


def shared_meshes(data_dir):
    """(name, V, F) of every file of the shared folder with faces (point clouds left out)."""
    for path in sorted(data_dir.iterdir()):
        if path.suffix not in (".obj", ".off", ".ply", ".stl"):
            continue
        V, F = meshsmith.io.read_mesh(path)
        if len(F):
            yield path.name, V, F


def test_every_shared_mesh_is_cleaned_and_parametrized(data_dir):
    seen = set()
    for name, V, F in shared_meshes(data_dir):
        seen.add(name)
        V2, F2, report = repair.clean(V, F)
        expect(report, **SHARED_DEFECTS.get(name, {}))
        assert_clean(V2, F2, report, V, F)
        result = parametrization.parametrize(V2, F2)
        assert len(result.uv) == len(result.V) and np.isfinite(result.uv).all(), name
        assert result.uv.shape == (len(result.V), 2)
    assert set(SHARED_DEFECTS) | {"plane_holes.obj", "camelhead.off"} <= seen and len(seen) >= 20


@pytest.mark.parametrize("name", ["stanford-bunny.obj", "cubes_complex_edge.obj"])
def test_raw_shared_meshes_in_parametrize(data_dir, name):
    # Unreferenced vertices get NaN rows, every referenced one a finite UV; non-manifold input
    # is refused with a message naming clean.
    V, F = meshsmith.io.read_mesh(data_dir / name)
    if name == "cubes_complex_edge.obj":
        with pytest.raises(meshsmith.InputError, match=r"non-manifold\): clean the mesh first with meshsmith\.repair"):
            parametrization.parametrize(V, F)
        return
    result = parametrization.parametrize(V, F)
    used = np.zeros(len(result.uv), dtype=bool)
    used[result.F.ravel()] = True
    assert np.isfinite(result.uv[used]).all() and np.isnan(result.uv[~used]).all()
    assert (~used).sum() == 1113
    np.testing.assert_array_equal(result.V[result.F], V[F])   # the cut keeps every face where it was


def shared_file_names() -> list[str]:
    """Every mesh-format file of the shared folder, by name (empty where the folder is absent)."""
    from conftest import shared_data_dir
    directory = shared_data_dir()
    if directory is None:
        return []
    return sorted(path.name for path in directory.iterdir() if path.suffix in (".obj", ".off", ".ply", ".stl"))


@pytest.mark.slow
@pytest.mark.parametrize("name", shared_file_names() or PROBLEM_MESHES)
def test_demo_gives_a_complete_report(data_dir, tmp_path, name):
    # End to end on every shared file (2-9 s each here): every stage runs on the cleaned input; a
    # file without faces (bun000.ply, a range scan) is refused in one line instead.
    if not len(meshsmith.io.read_mesh(data_dir / name).F):
        assert cli.main(["demo", "--input", str(data_dir / name), "--out", str(tmp_path)]) == 1
        return
    with contextlib.redirect_stdout(text_io.StringIO()):
        assert cli.main(["demo", "--input", str(data_dir / name), "--out", str(tmp_path)]) == 0
    report = tmp_path / "index.html"
    figures = json.loads((tmp_path / "results.json").read_text())
    assert "errors" not in figures, figures.get("errors")
    assert list(figures["seconds_per_stage"]) == [stage.__name__.removeprefix("stage_") for stage in STAGES]
    assert figures["clean"] == {key: SHARED_DEFECTS.get(name, {}).get(key, 0) for key in COUNTS}
    page = report.read_text()
    assert "(failed)" not in page and "Cleaning" in page
    for image in ("shaded.png", "mean_curvature.png", "decimated_10.png", "parametrization_lscm.png"):
        assert (tmp_path / image).stat().st_size > 0


def test_demo_reports_a_failing_stage_and_goes_on(tmp_path, monkeypatch):
    from meshsmith.demo import pipeline, stage_clean, stage_input

    def stage_broken(context):
        raise meshsmith.InputError("broken on purpose")

    source = tmp_path / "in.obj"
    V, F = datasets.icosphere(1)
    meshsmith.io.write_mesh(source, np.vstack([V, [[3.0, 3, 3]]]), F[:, ::-1])
    monkeypatch.setattr(pipeline, "STAGES", [stage_clean, stage_broken, stage_input])
    page = pipeline.run_demo(tmp_path / "out", str(source)).read_text()
    figures = json.loads((tmp_path / "out" / "results.json").read_text())
    assert figures["errors"] == {"broken": "InputError: broken on purpose"}
    assert "broken (failed)" in page and "broken on purpose" in page
    assert figures["clean"]["flipped_faces"] == len(F) and figures["clean"]["unreferenced_vertices"] == 1
    assert figures["input"]["n_vertices"] == len(V) and figures["input"]["volume"] > 0   # ran on the cleaned mesh


def test_demo_refuses_a_point_cloud_in_one_line(tmp_path, capsys):
    # A range scan stored as PLY vertices only (like shared/data's bun000.ply): no stage could run,
    # so the demo says so once instead of writing a report of failed stages.
    from meshsmith import cli, io
    P, N = datasets.sample_points(*datasets.icosphere(2), 200, seed=0)
    scan = tmp_path / "scan.ply"
    io.write_points(scan, P, N)
    assert cli.main(["demo", "--input", str(scan), "--out", str(tmp_path / "report")]) == 1
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "holds no faces" in error[0]
    assert not (tmp_path / "report" / "index.html").exists()


def test_cli_clean_keeps_uvs_normals_and_colours_on_their_corners(tmp_path):
    """Per-corner UVs and normals follow each face's corners through the clean (faces flipped to
    orient them, a merged duplicate vertex, an unreferenced vertex), vertex colours their vertices,
    face colours their faces: checked corner by corner against the input, by position."""
    V, F = datasets.icosphere(2)
    n = len(V)
    V_in = np.vstack([V, [[5.0, 5, 5]], V[3:4]])           # vertex n unused, n + 1 duplicates 3
    F_in = F[:, [0, 2, 1]].copy()                            # every face inward: clean flips them all
    uses_3 = np.flatnonzero(np.any(F_in == 3, axis=1))[:2]
    F_in[uses_3] = np.where(F_in[uses_3] == 3, n + 1, F_in[uses_3])
    m = len(F_in)
    UV = np.random.default_rng(5).random((3 * m, 2))         # one UV per corner
    F_uv = np.arange(3 * m).reshape(m, 3)
    normals = np.random.default_rng(6).normal(size=(3 * m, 3))
    colors = np.random.default_rng(7).random((len(V_in), 3))
    colors[n + 1] = colors[3]
    face_colors = np.random.default_rng(8).random((m, 3))
    source = tmp_path / "in.obj"
    meshsmith.io.write_mesh(source, V_in, F_in, UV=UV, F_uv=F_uv, normals=normals, F_normal=F_uv, colors=colors)
    target = tmp_path / "out.obj"
    with contextlib.redirect_stdout(text_io.StringIO()) as out:
        assert cli.main(["clean", str(source), "-o", str(target)]) == 0
    assert out.getvalue().splitlines()[0].endswith("with normals, UV, colors")
    result = meshsmith.io.read_mesh(target, return_attributes=True)
    assert len(result.V) == len(V) and len(result.F) == m
    assert topology.is_oriented(result.F) and geometry.volume(result.V, result.F) > 0

    def corners(V_, F_, values, index):  # position of each corner -> its attribute, face by face
        return {tuple(V_[F_[f, k]].round(9).tolist()) + (tuple(sorted(map(tuple, V_[F_[f]].round(9).tolist()))),):
                tuple(values[index[f, k]].tolist()) for f in range(len(F_)) for k in range(3)}

    for values, index, out_values, out_index in ((UV, F_uv, result.UV, result.F_uv),
                                                 (normals, F_uv, result.normals, result.F_normal)):
        expected = corners(V_in, F_in, values, index)
        got = corners(result.V, result.F, out_values, out_index)
        assert got.keys() == expected.keys()
        for key in expected:
            np.testing.assert_allclose(got[key], expected[key], rtol=1e-6, atol=1e-6)
    by_position = {tuple(p.round(9).tolist()): c for p, c in zip(V_in, colors)}
    np.testing.assert_allclose(result.colors, [by_position[tuple(p.round(9).tolist())] for p in result.V], atol=1e-6)
    # face colours (not in OBJ) through the same mapping, on the MeshData directly
    from meshsmith.cli.repair import cleaned_attributes
    data = meshsmith.io.MeshData(V_in, F_in, face_colors=face_colors)
    V2, F2, report = repair.clean(V_in, F_in)
    np.testing.assert_array_equal(cleaned_attributes(data, V2, F2, report)["face_colors"], face_colors[report.face_map])
