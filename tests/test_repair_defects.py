"""meshsmith.repair.find_defects and `meshsmith info`'s defect list (§2.4): each kind of defect on
a constructed mesh with a known count, agreement with what clean then fixes, nothing on clean
closed meshes, and the self-intersection test on request."""
import json

import numpy as np
import pytest

import meshsmith
from meshsmith import cli, datasets, repair

SPHERE = datasets.icosphere(2)


def defects(V, F, **options):
    return repair.find_defects(V, F, **options).counts()


def only(found, **expected):
    """`found` has exactly the non-zero counts `expected`."""
    assert {name: value for name, value in found.items() if value} == expected


def test_a_clean_closed_mesh_has_none():
    for V, F in (SPHERE, datasets.torus(), datasets.cube(4)):
        found = repair.find_defects(V, F)
        assert not found.has_defects() and found.lines() == ["no defects found"]
        assert found.self_intersecting_pairs == 0


def test_holes():
    V, F = SPHERE
    apart = [0, 100, 250]                     # three faces sharing no vertex
    assert len(np.unique(F[apart])) == 9
    only(defects(V, np.delete(F, apart, axis=0)), boundary_loops=3, boundary_edges=9)
    only(defects(*datasets.grid(5, 5)), boundary_loops=1, boundary_edges=20)   # 5 x 5 cells


def test_degenerate_duplicate_unreferenced():
    V, F = SPHERE
    found = defects(np.vstack([V, [[5.0, 5, 5]]]), np.vstack([F, [[0, 0, 1]]]))
    assert found["degenerate_faces"] == 1 and found["unreferenced_vertices"] == 1
    assert found["duplicate_faces"] == 0 and found["self_intersecting_pairs"] == 0
    found = defects(V, np.vstack([F, F[7]]))
    assert found["duplicate_faces"] == 1 and found["non_manifold_edges"] == 3   # its three edges have three faces
    assert found["self_intersecting_pairs"] == 1                               # the same three vertices
    collinear = np.vstack([V, (V[F[0, 0]] + V[F[0, 1]]) / 2])
    found = defects(collinear, np.vstack([F, [[F[0, 0], F[0, 1], len(V)]]]))
    assert found["zero_area_faces"] == 1


def test_non_manifold_vertex():
    V, F = SPHERE
    top = int(np.argmax(V[:, 2]))
    V2 = np.vstack([V, V + 2 * V[top]])                    # a copy standing on the first's top
    F2 = np.vstack([F, F + len(V)])
    bottom = len(V) + int(np.argmin(V[:, 2]))
    F2[F2 == bottom] = top                                 # the second sphere's bottom is the first's top
    found = defects(V2, F2)
    assert found["non_manifold_vertices"] == 1 and found["non_manifold_edges"] == 0
    assert found["unreferenced_vertices"] == 1


def test_flipped_components():
    V, F = SPHERE
    inside_out = defects(np.vstack([V, V + 3]), np.vstack([F, F[:, ::-1] + len(V)]))
    only(inside_out, flipped_faces=len(F), flipped_components=1)
    one_face = F.copy()
    one_face[5] = one_face[5, ::-1]
    only(defects(V, one_face), flipped_faces=1, flipped_components=1)
    V2, F2, report = repair.clean(V, one_face)
    assert report.flipped_faces == 1


def test_self_intersections_on_request():
    V, F = SPHERE
    poked = V.copy()
    poked[0] *= -1.3
    found = repair.find_defects(poked, F)
    assert found.self_intersecting_pairs == len(repair.self_intersections(poked, F)) > 0
    skipped = repair.find_defects(poked, F, intersections=False)
    assert skipped.self_intersecting_pairs is None and "self-intersections not looked for" in skipped.lines()


def test_counts_agree_with_what_clean_fixes():
    rng = np.random.default_rng(4)
    V, F = SPHERE
    holed = np.delete(F, [3, 90], axis=0)
    broken = np.vstack([holed, holed[rng.choice(len(holed), 5, replace=False)], [[1, 1, 2]]])
    found = repair.find_defects(V, broken)
    report = repair.clean(V, broken, merge_tolerance=None).report
    assert found.degenerate_faces == report.degenerate_faces == 1
    assert found.duplicate_faces == report.duplicate_faces == 5
    assert found.non_manifold_edges > 0 and report.non_manifold_edges == 0     # clean removed the copies first
    assert found.boundary_loops == len(meshsmith.topology.boundary_loops(holed)) >= 1


def test_info_lists_them(tmp_path, capsys):
    V, F = SPHERE
    path = tmp_path / "holed.obj"
    meshsmith.io.write_mesh(path, np.vstack([V, [[4.0, 0, 0]]]), np.delete(F, [0, 100], axis=0))
    assert cli.main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "defects:" in out
    lines = dict(line.strip().rsplit(None, 1) for line in out.split("defects:")[1].splitlines() if line.strip())
    lines = {name.strip(): value for name, value in lines.items()}
    assert lines["boundary loops (holes and borders)"] == "2"
    assert lines["unreferenced vertices"] == "1"
    assert "self-intersecting face pairs" not in lines
    assert cli.main(["info", str(path), "--json", "--intersections"]) == 0
    figures = json.loads(capsys.readouterr().out)
    assert figures["defects"]["boundary_loops"] == 2 and figures["defects"]["self_intersecting_pairs"] == 0
    clean = tmp_path / "sphere.off"
    meshsmith.io.write_mesh(clean, V, F)
    assert cli.main(["info", str(clean)]) == 0
    assert "defects: none found" in capsys.readouterr().out


def test_bad_input():
    with pytest.raises(meshsmith.InputError):
        repair.find_defects(np.zeros((3, 3)), [[0, 1, 3]])
    with pytest.raises(meshsmith.InputError):
        repair.find_defects([[np.nan, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])


def test_demo_stage_repairs_the_broken_copy(tmp_path):
    from meshsmith.demo import DemoContext, stage_repair
    V, F = datasets.torus(n_major=48, n_minor=24)
    context = DemoContext(tmp_path, "torus", V, F)
    section = stage_repair(context)
    figures = context.figures["repair"]
    assert figures["before: boundary_loops"] >= 1 and figures["before: self_intersecting_pairs"] > 0
    assert figures["before: flipped_faces"] > 0 and figures["before: duplicate_faces"] == 20
    assert figures["clean: duplicate_faces"] == 20
    assert figures["self-intersections: remaining_pairs"] == 0
    after = {name.removeprefix("after: "): value for name, value in figures.items() if name.startswith("after: ")}
    assert after == dict.fromkeys(repair.MeshDefectCounts.__dataclass_fields__, 0)
    assert figures["fill holes: filled"] == figures["fill holes: loops"] >= 1
    assert context.V is V and context.F is F                          # the later stages keep the input
    for name, _ in section.images:
        assert (tmp_path / name).stat().st_size > 1000
