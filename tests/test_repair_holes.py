"""meshsmith.repair.fill_holes (§2.4.1, Liepa 2003).

Invariants (closed, manifold, oriented, every input face and vertex kept, components kept, no
fold-over), analytic truth on planar holes (the patch is the hole: its area, its plane), the exact
search as the reference of the Delaunay-restricted one (its weight is never worse), the selection
options, pinched loops and islands (a hole's islands joined to it by bridges, or kept apart), and every mesh of ../shared/data cleaned and filled with the
report's counts checked.
"""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, geometry, repair, topology


def assert_filled(V, F, V2, F2, report, *, closed=True):
    """The invariants of fill_holes' output."""
    V, F = np.asarray(V, dtype=float), np.asarray(F)
    assert V2.dtype == np.float64 and F2.dtype == np.int64
    np.testing.assert_array_equal(V2[:len(V)], V)            # every input vertex kept, in place
    np.testing.assert_array_equal(F2[:len(F)], F)            # every input face kept, in order
    assert topology.is_manifold(F2) and topology.is_oriented(F2)
    assert len(topology.non_manifold_vertices(F2)) <= len(topology.non_manifold_vertices(F))
    assert not meshsmith.core.mesh_defects(V2, F2).degenerate_faces.size
    before = topology.connected_components(F, len(V)).count
    assert topology.connected_components(F2, len(V2)).count == before   # no component dropped or joined
    if closed:
        assert topology.boundary_loops(F2) == []
    added = sum(len(p.faces) for p in report.patches)
    assert len(F2) == len(F) + added
    assert len(V2) == len(V) + sum(len(p.vertices) for p in report.patches)
    for patch in report.patches:
        assert patch.max_dihedral_angle < 150, f"fold-over in the patch of loop {patch.loop}"


def sphere_with_hole(subdivisions=3, cap=0.8):
    """An icosphere without the faces above z = cap (one loop)."""
    V, F = datasets.icosphere(subdivisions)
    keep = V[F].mean(axis=1)[:, 2] < cap
    V2, F2, _ = repair.remove_unreferenced(V, F[keep])
    return V2, F2


def grid_with_square_hole(n=12, hole=(4, 8)):
    """A flat n×n grid (z = 0) without the quads of the square [hole[0], hole[1])²."""
    V, F = datasets.grid(n, n)
    centre = V[F].mean(axis=1)
    lo, hi = hole[0] / n, hole[1] / n
    inside = (centre[:, 0] > lo) & (centre[:, 0] < hi) & (centre[:, 1] > lo) & (centre[:, 1] < hi)
    return V, F[~inside], (hi - lo) ** 2


# ---- synthetic holes ---------------------------------------------------------------------------

def test_sphere_cap_is_closed_outward_and_near_the_sphere():
    V, F = sphere_with_hole()
    V2, F2, report = repair.fill_holes(V, F)
    assert_filled(V, F, V2, F2, report)
    assert report.filled == 1 and report.unfilled == () and report.patches[0].search == "delaunay"
    assert geometry.volume(V2, F2) > 0
    patch = report.patches[0]
    assert 0.8 <= patch.edge_length_ratio <= 1.25
    assert len(patch.vertices) > 0                       # refinement added vertices inside the cap
    # The cap's patch lies inside the sphere, between the loop's plane and the sphere.
    new = V2[patch.vertices]
    assert (np.linalg.norm(new, axis=1) < 1 + 1e-9).all() and (new[:, 2] > 0.7).all()


def test_fairing_bulges_the_cap_towards_the_sphere():
    # Bi-Laplacian fairing continues the sphere into the hole (C¹ at the rim) where the refined
    # patch alone spans it flat: the patch vertices come close to the unit sphere and the largest
    # angle at the rim drops.
    V, F = sphere_with_hole(4, cap=0.7)
    flat = repair.fill_holes(V, F, fair=False)
    faired = repair.fill_holes(V, F)
    np.testing.assert_array_equal(flat.F, faired.F)                      # fairing moves, never reconnects
    off_flat = np.abs(np.linalg.norm(flat.V[flat.report.patches[0].vertices], axis=1) - 1).mean()
    off_faired = np.abs(np.linalg.norm(faired.V[faired.report.patches[0].vertices], axis=1) - 1).mean()
    assert off_faired < 0.2 * off_flat and off_faired < 0.025        # thin plate, not the sphere itself
    assert faired.report.patches[0].max_dihedral_angle < flat.report.patches[0].max_dihedral_angle
    unrefined = repair.fill_holes(V, F, refine=False)
    assert unrefined.report.patches[0].vertices.size == 0                # nothing to fair without refinement


def test_planar_hole_patch_is_the_hole_exactly():
    V, F, hole_area = grid_with_square_hole()
    for refine in (False, True):
        V2, F2, report = repair.fill_holes(V, F, refine=refine, holes=[1])   # loop 0 is the outer rim
        assert_filled(V, F, V2, F2, report, closed=False)
        patch = report.patches[0]
        faces = F2[patch.faces]
        assert geometry.surface_area(V2, faces) == pytest.approx(hole_area, rel=1e-12)
        np.testing.assert_array_equal(V2[patch.vertices][:, 2], 0.0)
        normals = geometry.face_normals(V2, faces)
        np.testing.assert_allclose(normals, np.tile([0, 0, 1.0], (len(faces), 1)), atol=1e-12)
        assert patch.max_dihedral_angle < 1e-5
        if refine:
            assert 0.8 <= patch.edge_length_ratio <= 1.25 and len(patch.vertices) > 0
        else:
            assert len(patch.vertices) == 0 and len(faces) == patch.loop_edges - 2


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_delaunay_search_weight_is_never_better_than_the_exact_optimum(seed):
    # The exact search minimizes (largest dihedral angle, area) over every triangulation; the
    # restricted one over a subset, so its largest angle can only be equal or worse.
    V, F = datasets.noisy(*sphere_with_hole(3, cap=0.3 + 0.2 * seed), sigma=0.02, seed=seed)
    exact = repair.fill_holes(V, F, refine=False, search="exact").report.patches[0]
    restricted = repair.fill_holes(V, F, refine=False, search="delaunay").report.patches[0]
    assert exact.search == "exact" and restricted.search == "delaunay"
    assert exact.max_dihedral_angle <= restricted.max_dihedral_angle + 1e-9
    assert len(exact.faces) == len(restricted.faces) == exact.loop_edges - 2


def test_large_zigzag_loop_stays_in_the_delaunay_search_space():
    # A staircase cut through a lat-long sphere: a loop of hundreds of edges, many of them not
    # Delaunay edges (nearly cocircular quads); the loop's own edges complete the search space.
    V, F = datasets.uv_sphere(60, 240)
    centre = V[F].mean(axis=1)
    phi = np.arctan2(centre[:, 1], centre[:, 0])
    keep = np.arccos(np.clip(centre[:, 2] / np.linalg.norm(centre, axis=1), -1, 1)) > 0.6 + 0.15 * np.sin(3 * phi)
    V, F, _ = repair.remove_unreferenced(V, F[keep])
    V2, F2, report = repair.fill_holes(V, F, refine=False)
    assert_filled(V, F, V2, F2, report)
    assert report.patches[0].loop_edges > 300 and report.patches[0].search == "delaunay"


def test_pinched_loops_share_a_vertex_and_stay_manifold():
    # Two holes touching at one vertex: the two diagonal quads around a grid vertex removed.
    V, F = datasets.grid(6, 6)
    centre = V[F].mean(axis=1)
    quad = np.floor(centre[:, :2] * 6).astype(int)
    removed = ((quad[:, 0] == 2) & (quad[:, 1] == 2)) | ((quad[:, 0] == 3) & (quad[:, 1] == 3))
    F = F[~removed]
    assert len(topology.non_manifold_vertices(F)) == 1
    V2, F2, report = repair.fill_holes(V, F, max_hole_edges=8)
    assert report.filled == len(topology.boundary_loops(F)) - 1           # every loop but the rim
    assert_filled(V, F, V2, F2, report, closed=False)
    assert len(topology.non_manifold_vertices(F2)) == 0 and len(topology.boundary_loops(F2)) == 1


def test_island_inside_a_hole_keeps_its_own_component():
    # A bowl floating inside the cap hole of a sphere: each is closed on its own, neither dropped.
    V, F = sphere_with_hole(3, cap=0.6)
    bowl_V, bowl_F = sphere_with_hole(2, cap=0.0)
    V = np.vstack([V, 0.1 * bowl_V + [0, 0, 0.85]])
    F = np.vstack([F, bowl_F + len(V) - len(bowl_V)])
    V2, F2, report = repair.fill_holes(V, F)
    assert_filled(V, F, V2, F2, report)
    assert report.filled == 2 and topology.connected_components(F2).count == 2


def plane_with_island(lift=0.0):
    """A 16×16 grid with the square [0.25, 0.75]² cut out and a 4×4 grid patch (the island, facing
    +z as the plane does, no vertex shared) floating in the middle of the hole, `lift` above it."""
    V, F, _ = grid_with_square_hole(16, (4, 12))
    island_V, island_F = datasets.grid(4, 4, size=(0.2, 0.2))
    island_V = island_V + [0.4, 0.4, lift]
    return np.vstack([V, island_V]), np.vstack([F, island_F + len(V)])


def test_an_island_is_filled_with_its_hole_as_one_region():
    V, F = plane_with_island()
    loops = topology.boundary_loops(F)
    assert [len(loop) for loop in loops] == [64, 32, 16]          # rim, hole, island
    assert topology.connected_components(F, len(V)).count == 2
    V2, F2, report = repair.fill_holes(V, F, keep_border=True)    # the rim kept; not the island's only loop
    assert report.filled == 1 and report.patches[0].loop == 1 and report.patches[0].islands == (2,)
    assert report.kept_borders.tolist() == [0]
    assert report.counts()["islands_joined"] == 1 and "1 island loops filled" in str(report)
    np.testing.assert_array_equal(F2[:len(F)], F)
    assert topology.is_manifold(F2) and topology.is_oriented(F2)
    assert topology.connected_components(F2, len(V2)).count == 1         # the island joined to the rim
    remaining = topology.boundary_loops(F2)
    assert len(remaining) == 1 and len(remaining[0]) == 64               # the rim, kept open
    assert repair.self_intersections(V2, F2).shape == (0, 2)
    # Flat, and covering exactly the annulus between the hole and the island: the unit square.
    np.testing.assert_allclose(V2[:, 2], 0.0, atol=1e-12)
    assert geometry.surface_area(V2, F2) == pytest.approx(1.0, rel=1e-12)
    assert report.patches[0].max_dihedral_angle < 1e-6
    assert 0.8 <= report.patches[0].edge_length_ratio <= 1.25


def test_without_islands_each_loop_is_closed_on_its_own_and_the_patches_overlap():
    V, F = plane_with_island()
    V2, F2, report = repair.fill_holes(V, F, holes=[1, 2], islands=False)
    assert report.filled == 2 and all(p.islands == () for p in report.patches)
    assert topology.connected_components(F2, len(V2)).count == 2
    assert len(repair.self_intersections(V2, F2)) > 0                    # the hole's patch covers the island
    assert geometry.surface_area(V2, F2) == pytest.approx(1.0 + 2 * 0.2 ** 2, rel=1e-9)


def test_a_lifted_island_is_joined_and_the_patch_bends_to_it():
    V, F = plane_with_island(lift=0.05)
    V2, F2, report = repair.fill_holes(V, F, holes=[1])           # the island's loop joins the hole's
    assert report.patches[0].islands == (2,)
    assert topology.connected_components(F2, len(V2)).count == 1 and len(topology.boundary_loops(F2)) == 1
    assert topology.is_manifold(F2) and topology.is_oriented(F2)
    assert repair.self_intersections(V2, F2).shape == (0, 2)
    new = V2[len(V):]
    assert (new[:, 2] > 0).all() and new[:, 2].max() < 0.05 + 1e-9      # between the plane and the island
    assert report.patches[0].max_dihedral_angle < 60


def test_selection_by_index_size_and_diameter():
    V, F, _ = grid_with_square_hole(12, (4, 8))
    loops = topology.boundary_loops(F)
    assert [len(loop) for loop in loops] == [48, 16]
    report = repair.fill_holes(V, F, max_hole_edges=20).report
    assert [p.loop for p in report.patches] == [1]
    report = repair.fill_holes(V, F, max_hole_diameter=0.5).report   # the hole spans 4/12·√2 = 0.47
    assert [p.loop for p in report.patches] == [1]
    report = repair.fill_holes(V, F, max_hole_diameter=0.4).report
    assert report.patches == ()
    report = repair.fill_holes(V, F, holes=[0]).report
    assert [p.loop for p in report.patches] == [0] and len(report.loops) == 2
    report = repair.fill_holes(V, F, keep_border=True).report
    assert [p.loop for p in report.patches] == [1] and report.kept_borders.tolist() == [0]


def test_scaled_input_gives_the_same_faces():
    V, F = sphere_with_hole()
    V1, F1, _ = repair.fill_holes(V, F)
    V2, F2, _ = repair.fill_holes(V * 2.0 ** 200, F)
    np.testing.assert_array_equal(F1, F2)
    np.testing.assert_array_equal(V1 * 2.0 ** 200, V2)


def test_progress_and_cancel():
    V, F = sphere_with_hole()
    calls = []
    repair.fill_holes(V, F, progress=lambda fraction, stage: calls.append(fraction))
    assert calls and calls[-1] == 1.0
    with pytest.raises(meshsmith.Cancelled):
        repair.fill_holes(V, F, progress=lambda fraction, stage: False)


def test_bad_input_is_an_input_error():
    V, F = sphere_with_hole()
    F_copy = F.copy()
    with pytest.raises(meshsmith.InputError, match="holes: loop 5"):
        repair.fill_holes(V, F, holes=[5])
    flipped = F.copy()
    flipped[0] = flipped[0, [0, 2, 1]]
    with pytest.raises(meshsmith.InputError, match="same direction"):
        repair.fill_holes(V, flipped)
    triple = np.vstack([F, F[:1, [0, 2, 1]], F[:1, [1, 0, 2]]])
    with pytest.raises(meshsmith.InputError, match="faces: hole filling needs an edge-manifold"):
        repair.fill_holes(V, triple)
    for option in ({"max_hole_edges": 2}, {"max_hole_diameter": -1.0}, {"density": 0.0}, {"search": "fast"}):
        with pytest.raises(meshsmith.InputError):
            repair.fill_holes(V, F, **option)
    np.testing.assert_array_equal(F, F_copy)


def test_report_counts_and_lines():
    V, F, _ = grid_with_square_hole()
    report = repair.fill_holes(V, F, holes=[1]).report
    counts = report.counts()
    assert counts["loops"] == 2 and counts["filled"] == 1 and counts["unfilled"] == 0
    assert counts["faces_added"] == len(report.patches[0].faces)
    assert str(report).startswith("1 of 2 holes filled")


# ---- the shared meshes -------------------------------------------------------------------------

#: Boundary loops of each shared mesh once cleaned (every other mesh is closed).
SHARED_HOLES = {"stanford-bunny.obj": 5, "plane_holes.obj": 27, "camelhead.off": 1, "hand_lowres.obj": 1}


def test_every_shared_mesh_is_cleaned_and_filled_into_a_closed_oriented_manifold(data_dir):
    seen = 0
    for path in sorted(data_dir.iterdir()):
        if path.suffix not in (".obj", ".off", ".ply"):
            continue
        V, F = meshsmith.io.read_mesh(path)
        if not len(F):
            continue
        seen += 1
        V, F, _ = repair.clean(V, F)
        V2, F2, report = repair.fill_holes(V, F)
        assert_filled(V, F, V2, F2, report)
        holes = SHARED_HOLES.get(path.name, 0)
        assert report.counts()["loops"] == report.filled == holes, path.name
        for patch in report.patches:
            assert 0.8 <= patch.edge_length_ratio <= 1.25, (path.name, patch.loop, patch.edge_length_ratio)
        components = topology.connected_components(F2, len(V2))
        for label in range(components.count):
            assert geometry.volume(V2, F2[components.face_labels == label]) > 0, (path.name, label)
    assert seen >= 20


def test_camelhead_keeps_its_outline_with_keep_border(data_dir):
    V, F = meshsmith.io.read_mesh(data_dir / "camelhead.off")
    V2, F2, report = repair.fill_holes(V, F, keep_border=True)
    assert report.patches == () and report.kept_borders.tolist() == [0]
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)


def test_stanford_bunny_holes(data_dir):
    V, F = meshsmith.io.read_mesh(data_dir / "stanford-bunny.obj")
    V, F, _ = repair.clean(V, F)
    V2, F2, report = repair.fill_holes(V, F)
    assert [p.loop_edges for p in report.patches] == [len(loop) for loop in topology.boundary_loops(F)]
    assert sum(p.loop_edges for p in report.patches) == 223            # README: 223 boundary edges
    assert all(p.search == "delaunay" for p in report.patches)
    # Five small holes on a closed bunny: the volume grows by a little.
    assert 0 < geometry.volume(V2, F2)


# ---- the command line --------------------------------------------------------------------------

def test_cli_repair_fills_and_reports(tmp_path, capsys):
    import json

    from meshsmith import cli
    V, F = sphere_with_hole()
    source, target, record = tmp_path / "in.obj", tmp_path / "out.ply", tmp_path / "report.json"
    meshsmith.io.write_mesh(source, V, F)
    assert cli.main(["repair", str(source), "-o", str(target), "--fill-holes", "--report", str(record)]) == 0
    printed = capsys.readouterr().out
    assert "1 of 1 holes filled" in printed and "0 boundary loops" in printed
    V2, F2 = meshsmith.io.read_mesh(target)
    assert topology.boundary_loops(F2) == [] and topology.is_manifold(F2)
    report = json.loads(record.read_text())
    assert report["fill_holes"]["filled"] == 1 and report["output"]["boundary_loops"] == 0
    assert report["output"]["self_intersecting_pairs"] == 0 and report["output"]["faces"] == len(F2)
    assert 0.8 <= report["fill_holes"]["patches"][0]["edge_length_ratio"] <= 1.25
    # --max-hole below the hole's size leaves it open
    assert cli.main(["repair", str(source), "-o", str(target), "--fill-holes", "--max-hole", "5"]) == 0
    assert "0 of 1 holes filled" in capsys.readouterr().out
    assert len(topology.boundary_loops(meshsmith.io.read_mesh(target)[1])) == 1


# ---- orientation of the components the fill closes -----------------------------------------------

def hemisphere(inward):
    V, F = datasets.icosphere(3)
    V, F, _ = repair.remove_unreferenced(V, F[V[F].mean(axis=1)[:, 2] > 0])
    return V, (F[:, ::-1].copy() if inward else F)


@pytest.mark.parametrize("inward", [True, False])
def test_a_filled_hemisphere_faces_outward_whichever_way_its_faces_pointed(inward):
    V, F = hemisphere(inward)
    V2, F2, report = repair.fill_holes(V, F)
    assert topology.boundary_loops(F2) == [] and topology.is_oriented(F2)
    assert geometry.volume(V2, F2) > 0.9 * (2 / 3) * np.pi * 0.95      # about half the unit ball
    assert report.reoriented_components == int(inward) == report.counts()["reoriented_components"]
    # The input faces are the input's, reversed as a whole when the component was inside out.
    np.testing.assert_array_equal(F2[:len(F)], F[:, [0, 2, 1]] if inward else F)
    assert ("reversed to face outward" in str(report)) == inward


def test_an_open_component_keeps_its_orientation_and_a_closed_one_is_not_touched():
    V, F = hemisphere(inward=True)
    W, G = datasets.icosphere(1)
    G_inward = G[:, ::-1]                        # a closed, inside-out sphere: not the fill's business
    both_V = np.vstack([V, W + [3.0, 0, 0]])
    both_F = np.vstack([F, G_inward + len(V)])
    _, F2, report = repair.fill_holes(both_V, both_F, max_hole_edges=3)   # fills nothing
    np.testing.assert_array_equal(F2, both_F)
    assert report.reoriented_components == 0
    _, F3, report = repair.fill_holes(both_V, both_F)
    assert report.reoriented_components == 1
    np.testing.assert_array_equal(F3[len(F):len(both_F)], G_inward + len(V))   # the closed sphere as it was


def test_cli_repair_fills_an_inward_hemisphere_outward(tmp_path, capsys):
    import json

    from meshsmith import cli
    V, F = hemisphere(inward=True)
    source, target, record = tmp_path / "in.off", tmp_path / "out.off", tmp_path / "report.json"
    meshsmith.io.write_mesh(source, V, F)
    assert cli.main(["repair", str(source), "-o", str(target), "--fill-holes", "--report", str(record)]) == 0
    assert "1 closed components reversed to face outward" in capsys.readouterr().out
    V2, F2 = meshsmith.io.read_mesh(target)
    assert geometry.volume(V2, F2) > 0
    figures = json.loads(record.read_text())
    assert figures["fill_holes"]["reoriented_components"] == 1 and figures["output"]["volume"] > 0
