"""`meshsmith repair`: the input's attributes survive (exactly where faces survive, interpolated on
new faces, or named as dropped), --volumetric / --rho, --report JSON, stage progress."""
import json

import numpy as np
import pytest

from meshsmith import cli, datasets, geometry, io, repair, topology


def with_hole(V, F, centre, radius):
    """(V, F) without the faces whose centroid is within `radius` of `centre` (a hole there)."""
    keep = np.linalg.norm(V[F].mean(axis=1) - centre, axis=1) > radius
    return F[keep]


def repair_cli(capsys, *arguments):
    status = cli.main(["repair", *map(str, arguments)])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    return captured.out


def corner_values(V, F, values):
    """{face's corner positions (sorted): {corner position: its value}} for per-corner values (m, 3, k)."""
    table = {}
    for corners, value in zip(V[F], values):
        points = [tuple(p) for p in corners]
        table[tuple(sorted(points))] = {p: tuple(v) for p, v in zip(points, value)}
    return table


def test_spot_uvs_survive_hole_filling(data_dir, tmp_path, capsys):
    path = data_dir / "spot.obj"
    if not path.is_file():
        pytest.skip("spot.obj is not in the shared data")
    mesh = io.read_mesh(path, return_attributes=True)
    F_holed = with_hole(mesh.V, mesh.F, mesh.V[100], 0.08)
    keep = np.isin(np.arange(len(mesh.F)), np.flatnonzero(
        np.linalg.norm(mesh.V[mesh.F].mean(axis=1) - mesh.V[100], axis=1) > 0.08))
    source, target, record = tmp_path / "holed.obj", tmp_path / "filled.obj", tmp_path / "report.json"
    io.write_mesh(source, mesh.V, F_holed, UV=mesh.UV, F_uv=mesh.F_uv[keep])
    printed = repair_cli(capsys, source, "-o", target, "--fill-holes", "--report", record)
    out = io.read_mesh(target, return_attributes=True)
    assert out.UV is not None and topology.boundary_loops(out.F) == []
    report = json.loads(record.read_text())["attributes"]
    assert report["written"] == ["UV"] and report["dropped"] == {}
    assert report["kept_faces"] == len(F_holed) and report["interpolated_faces"] == len(out.F) - len(F_holed)
    assert "UV kept exactly on" in printed and "interpolated from the nearest input surface" in printed
    # Every input face keeps its texture coordinates exactly, corner by corner (OBJ: 17 digits).
    before = corner_values(mesh.V, F_holed, mesh.UV[mesh.F_uv[keep]])
    after = corner_values(out.V, out.F, out.UV[out.F_uv])
    assert all(after.get(key) == value for key, value in before.items())
    # The patch's UVs are blends of the nearby faces': inside their UV bounding box, nowhere NaN.
    patch_uv = np.array([uv for key, value in after.items() if key not in before for uv in value.values()])
    assert len(patch_uv) and np.isfinite(patch_uv).all()
    near = np.linalg.norm(mesh.V[mesh.F[keep]].mean(axis=1) - mesh.V[100], axis=1) < 0.2
    local = mesh.UV[mesh.F_uv[keep][near]].reshape(-1, 2)
    assert (patch_uv >= local.min(axis=0) - 1e-12).all() and (patch_uv <= local.max(axis=0) + 1e-12).all()


def coloured_sphere_with_hole(tmp_path):
    V, F = datasets.icosphere(3)
    colors = np.column_stack([(V[:, 0] + 1) / 2, (V[:, 1] + 1) / 2, (V[:, 2] + 1) / 2])
    normals = V / np.linalg.norm(V, axis=1, keepdims=True)
    F_holed = with_hole(V, F, np.array([0.0, 0.0, 1.0]), 0.35)
    path = tmp_path / "coloured.ply"
    io.write_mesh(path, V, F_holed, colors=colors, normals=normals, F_normal=F_holed)
    return path, V, colors


def test_ply_colours_and_normals_follow_and_are_interpolated_on_the_patch(tmp_path, capsys):
    source, V, colors = coloured_sphere_with_hole(tmp_path)
    target = tmp_path / "filled.ply"
    printed = repair_cli(capsys, source, "-o", target, "--fill-holes")
    out = io.read_mesh(target, return_attributes=True)
    assert out.colors is not None and out.normals is not None, printed
    assert topology.boundary_loops(out.F) == []
    index = {tuple(p): i for i, p in enumerate(V)}
    old = np.array([tuple(p) in index for p in out.V])
    rows = np.array([index[tuple(p)] for p in out.V[old]])
    # Input vertices keep their colour, to the file's precision (PLY colours are bytes).
    np.testing.assert_allclose(out.colors[old], colors[rows], atol=1 / 255)
    # New vertices of the patch over the north pole: blue high, red and green near the middle.
    new = ~old
    assert new.sum() > 0
    assert (out.colors[new, 2] > 0.9).all() and (np.abs(out.colors[new, :2] - 0.5) < 0.2).all()
    normals = out.normals[out.F_normal[np.isin(out.F, np.flatnonzero(new))]]
    assert np.allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-5) and (normals[:, 2] > 0.9).all()
    assert "colors" in printed and "normals" in printed


def test_a_format_that_cannot_hold_an_attribute_drops_it_and_says_why(tmp_path, capsys):
    source, _, _ = coloured_sphere_with_hole(tmp_path)
    record = tmp_path / "r.json"
    printed = repair_cli(capsys, source, "-o", tmp_path / "out.stl", "--report", record)
    assert "attributes: colors dropped:" in printed and "attributes: normals dropped:" in printed
    dropped = json.loads(record.read_text())["attributes"]["dropped"]
    assert set(dropped) == {"colors", "normals"} and all("STL" in reason for reason in dropped.values())


def test_shared_ply_colours_survive(data_dir, tmp_path, capsys):
    coloured = [path for path in sorted(data_dir.glob("*.ply"))
                if io.read_mesh(path, return_attributes=True).colors is not None]
    if not coloured:
        pytest.skip("no PLY with vertex colours in the shared data")
    mesh = io.read_mesh(coloured[0], return_attributes=True)
    target = tmp_path / "out.ply"
    repair_cli(capsys, coloured[0], "-o", target)
    out = io.read_mesh(target, return_attributes=True)
    assert out.colors is not None and len(out.colors) == len(out.V)
    index = {tuple(p): i for i, p in enumerate(mesh.V)}
    rows = np.array([index[tuple(p)] for p in out.V])
    np.testing.assert_allclose(out.colors, mesh.colors[rows], atol=1 / 255)


def test_volumetric_rebuilds_closed_and_reports(tmp_path, capsys):
    source, V, colors = coloured_sphere_with_hole(tmp_path)
    target, record = tmp_path / "rebuilt.ply", tmp_path / "report.json"
    printed = repair_cli(capsys, source, "-o", target, "--volumetric", "0.08", "--rho", "0.3", "--report", record)
    out = io.read_mesh(target, return_attributes=True)
    assert topology.boundary_loops(out.F) == [] and topology.is_manifold(out.F)
    assert geometry.volume(out.V, out.F) > 0
    assert len(repair.self_intersections(out.V, out.F)) == 0
    report = json.loads(record.read_text())
    assert report["volumetric"]["epsilon"] == 0.08 and report["volumetric"]["rho"] == 0.3
    assert report["volumetric"]["closing_cells"] > 0                    # the hole, closed by rho
    assert report["output"]["boundary_loops"] == 0 and report["output"]["faces"] == len(out.F)
    assert report["output"]["volume"] == pytest.approx(geometry.volume(out.V, out.F))
    assert report["attributes"]["kept_faces"] == 0 and report["attributes"]["interpolated_faces"] == len(out.F)
    assert "volumetric: rebuilt on a" in printed and "every face new" in printed
    # Colours come from the nearest input point: the x-coloured red channel follows x.
    assert np.corrcoef(out.colors[:, 0], out.V[:, 0])[0, 1] > 0.95
    # Without rho the hole (0.35 wide) is not closed by the grid, and the surface still is closed:
    # the volumetric repair makes a thin shell around the open sheet.
    assert cli.main(["repair", str(source), "-o", str(target), "--volumetric", "0.08"]) == 0
    assert topology.boundary_loops(io.read_mesh(target)[1]) == []


@pytest.mark.parametrize("arguments, word", [
    (["--volumetric", "0.1", "--fill-holes"], "--volumetric"),
    (["--rho", "0.1"], "--rho"),
    (["--volumetric", "0"], "--volumetric"),
    (["--volumetric", "0.1", "--rho", "-1"], "--rho"),
    (["--max-hole", "10"], "--max-hole"),
])
def test_bad_usage_is_one_line(tmp_path, capsys, arguments, word):
    source, _, _ = coloured_sphere_with_hole(tmp_path)
    assert cli.main(["repair", str(source), "-o", str(tmp_path / "o.obj"), *arguments]) == 2
    err = capsys.readouterr().err
    assert err.startswith("meshsmith: error:") and word in err and len(err.strip().splitlines()) == 1


def test_repair_shows_its_stages(tmp_path, monkeypatch, capsys):
    source, _, _ = coloured_sphere_with_hole(tmp_path)
    calls = []

    class RecordingBar(cli.ProgressBar):
        def __call__(self, fraction, stage):
            calls.append((fraction, stage))
            return True

    monkeypatch.setattr(cli.repair, "ProgressBar", RecordingBar)
    repair_cli(capsys, source, "-o", tmp_path / "o.ply", "--fill-holes")
    stages = []
    for _, stage in calls:
        name = stage.split(":")[0]
        if not stages or stages[-1] != name:
            stages.append(name)
    assert stages == ["reading", "cleaning", "filling holes", "checking", "writing"]
    assert calls[-1][0] == 1.0 and [f for f, _ in calls] == sorted(f for f, _ in calls)
