"""meshsmith.repair.remove_self_intersections (§2.4): constructed self-intersecting meshes (a
vertex poked through a sphere, a torus with a vertex through its tube, a flap folded over a flat
grid) come out without intersection (CGAL's exact test), manifold and oriented, closed where the
input was closed and with the input's own border left open; two overlapping spheres, which
removal cannot resolve, come back with their remaining pairs counted; `meshsmith repair
--remove-self-intersections` reports the counts."""
import json

import numpy as np
import pytest

import meshsmith
from meshsmith import cli, datasets, repair, topology


def poked_sphere():
    """An icosphere with vertex 0 pushed through the centre and out of the far side."""
    V, F = datasets.icosphere(3)
    V = V.copy()
    V[0] *= -1.3
    return V, F


def poked_torus():
    V, F = datasets.torus(n_major=32, n_minor=16)
    V = V.copy()
    outer = int(np.argmax(np.linalg.norm(V, axis=1)))
    V[outer] *= 0.45      # the outermost vertex of the tube goes through its inner wall
    return V, F


def folded_grid():
    """A flat 12 x 12 grid with one interior vertex carried, in its plane, three cells over its
    neighbours, so its fan folds onto their faces (coplanar overlaps)."""
    V, F = datasets.grid(12, 12)
    V = V.copy()
    middle = int(np.argmin(np.linalg.norm(V[:, :2] - 0.5, axis=1)))
    V[middle] += [0.25, 0.0, 0.0]
    return V, F, middle


def assert_resolved(V, F, closed):
    assert repair.self_intersections(V, F).shape == (0, 2)
    assert topology.is_manifold(F) and topology.is_oriented(F)
    np.testing.assert_array_equal(np.unique(F), np.arange(len(V)))
    assert np.isfinite(V).all()
    if closed:
        assert topology.boundary_loops(F) == []


@pytest.mark.parametrize("make", [poked_sphere, poked_torus])
def test_closed_meshes_come_out_closed_without_intersection(make):
    V, F = make()
    before = repair.self_intersections(V, F)
    assert len(before) > 0
    V2, F2, report = repair.remove_self_intersections(V, F)
    assert_resolved(V2, F2, closed=True)
    assert report.initial_pairs == len(before) and report.remaining_pairs == 0
    assert 1 <= report.rounds <= 6 and report.unfilled_holes == 0 and report.filled_holes >= 1
    assert report.removed_faces >= len(np.unique(before))
    # faces are the kept input faces, in order, then the patches
    kept = report.face_origin >= 0
    assert kept[:kept.sum()].all() and (np.diff(report.face_origin[kept]) > 0).all()
    np.testing.assert_array_equal(V2[report.vertex_map >= 0], V[report.vertex_map[report.vertex_map >= 0]])
    original = F[report.face_origin[kept]]
    np.testing.assert_array_equal(report.vertex_map[F2[kept]], original)
    assert report.added_faces == int((~kept).sum())
    if report.rounds == 1:
        assert len(F2) == len(F) - report.removed_faces + report.added_faces
    # the genus is kept (a fill closes a disk-shaped hole)
    assert topology.genus(F2) == topology.genus(F)


def test_poked_vertex_is_dropped_and_the_sphere_stays_round():
    V, F = poked_sphere()
    V2, F2, report = repair.remove_self_intersections(V, F)
    assert 0 not in report.vertex_map                  # its fan was cut out with it
    radius = np.linalg.norm(V2, axis=1)
    assert radius.max() < 1.0 + 1e-9 and radius.min() > 0.8
    assert meshsmith.geometry.volume(V2, F2) > 0.9 * meshsmith.geometry.volume(*datasets.icosphere(3))


def test_open_surface_keeps_its_border():
    V, F, middle = folded_grid()
    assert len(repair.self_intersections(V, F)) > 0
    V2, F2, report = repair.remove_self_intersections(V, F)
    assert_resolved(V2, F2, closed=False)
    loops = topology.boundary_loops(F2)
    assert len(loops) == 1 and len(loops[0]) == len(topology.boundary_loops(F)[0])    # the rim, untouched
    assert report.remaining_pairs == 0 and report.filled_holes >= 1


def test_faces_mask_resolves_only_the_pairs_it_reaches():
    """Two poked spheres side by side: with only the first one's faces removable, its pairs are
    resolved and the second's are left as they were, uncounted."""
    V1, F1 = poked_sphere()
    V = np.vstack([V1, V1 + [3.0, 0, 0]])
    F = np.vstack([F1, F1 + len(V1)])
    pairs = repair.self_intersections(V, F)
    near_first = np.arange(len(F)) < len(F1)
    assert near_first[pairs].any(axis=1).any() and (~near_first[pairs]).all(axis=1).any()
    V2, F2, report = repair.remove_self_intersections(V, F, faces=near_first)
    assert report.initial_pairs == int(near_first[pairs].any(axis=1).sum()) and report.remaining_pairs == 0
    assert report.removed_faces > 0 and report.filled_holes >= 1
    # every face outside the mask is kept, unmoved, and the second poke's pairs are still there
    outside = np.flatnonzero(~near_first)
    assert np.isin(outside, report.face_origin).all()
    left = repair.self_intersections(V2, F2)
    assert len(left) == int((~near_first[pairs]).all(axis=1).sum()) > 0
    assert (report.face_origin[left] >= 0).all() and (~near_first[report.face_origin[left]]).all()
    with pytest.raises(meshsmith.InputError, match="faces"):
        repair.remove_self_intersections(V, F, faces=near_first[:-1])


def test_unchanged_without_intersections():
    V, F = datasets.icosphere(2)
    V2, F2, report = repair.remove_self_intersections(V, F)
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)
    assert report.counts() == dict.fromkeys(report.counts(), 0)
    assert str(report).startswith("0 self-intersecting face pairs found")


def test_overlapping_spheres_are_left_counted():
    V, F = datasets.icosphere(2)
    V2 = np.vstack([V, 0.9 * V + [0.5, 0, 0]])
    F2 = np.vstack([F, F + len(V)])
    initial = len(repair.self_intersections(V2, F2))
    V3, F3, report = repair.remove_self_intersections(V2, F2, max_rounds=2)
    assert report.rounds == 2 and report.initial_pairs == initial
    assert report.remaining_pairs == len(repair.self_intersections(V3, F3)) > 0
    assert topology.is_manifold(F3) and topology.is_oriented(F3)


def test_bad_options():
    with pytest.raises(meshsmith.InputError, match="max_rounds"):
        repair.remove_self_intersections(*datasets.icosphere(1), max_rounds=0)
    with pytest.raises(meshsmith.InputError):
        repair.remove_self_intersections(np.zeros((3, 3)), [[0, 1, 5]])


def test_repair_command_removes_them(tmp_path, capsys):
    V, F = poked_sphere()
    source, target, report = tmp_path / "poked.obj", tmp_path / "fixed.obj", tmp_path / "report.json"
    meshsmith.io.write_mesh(source, V, F)
    assert cli.main(["repair", str(source), "-o", str(target), "--remove-self-intersections",
                     "--report", str(report)]) == 0
    out = capsys.readouterr().out
    assert "self-intersections: 0 self-intersecting face pairs left" in out
    record = json.loads(report.read_text())
    assert record["self_intersections"]["initial_pairs"] > 0
    assert record["output"]["self_intersecting_pairs"] == 0 and record["output"]["boundary_loops"] == 0
    V2, F2 = meshsmith.io.read_mesh(target)
    assert repair.self_intersections(V2, F2).shape == (0, 2)
