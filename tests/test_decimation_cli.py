"""`meshsmith decimate` and `meshsmith lod`: the commands run, print faces before/after and the
Hausdorff distance, write what they announce, and fail with one line + exit 1 on bad input."""
import subprocess
import sys

import numpy as np
import pytest

from meshsmith import cli, datasets, geometry, io, topology


def run(*args):
    return subprocess.run([sys.executable, "-m", "meshsmith", *map(str, args)], capture_output=True, text=True)


@pytest.fixture()
def torus_file(tmp_path):
    V, F = datasets.torus(1.0, 0.4, 40, 20)
    path = tmp_path / "torus.ply"
    io.write_mesh(path, V, F)
    return path


@pytest.mark.parametrize("command", ["decimate", "lod"])
def test_help(command):
    result = run(command, "--help")
    assert result.returncode == 0 and "usage: meshsmith" in result.stdout


def hausdorff_printed(stdout):
    line = next(line for line in stdout.splitlines() if line.startswith("Hausdorff distance"))
    return float(line.split()[2])


@pytest.mark.parametrize("stop", [["--faces", "400"], ["--ratio", "0.25"], ["--error", "1e-4"]])
def test_decimate_qem(torus_file, tmp_path, stop):
    out = tmp_path / "out.obj"
    result = run("decimate", torus_file, "-o", out, *stop)
    assert result.returncode == 0, result.stderr
    V0, F0 = io.read_mesh(torus_file)
    V, F = io.read_mesh(out)
    assert f"{len(F0)} -> {len(F)} faces" in result.stdout
    if stop[0] == "--faces":
        assert len(F) == 400
    if stop[0] == "--ratio":
        assert len(F) == 400
    assert len(F) < len(F0)
    assert topology.is_manifold(F) and topology.euler_characteristic(F) == 0
    expected = geometry.hausdorff_distance(V, F, V0, F0)
    assert hausdorff_printed(result.stdout) == pytest.approx(expected, rel=1e-4)


def test_decimate_cluster(torus_file, tmp_path):
    out = tmp_path / "out.off"
    result = run("decimate", torus_file, "-o", out, "--faces", "300", "--method", "cluster")
    assert result.returncode == 0, result.stderr
    V, F = io.read_mesh(out)
    assert len(V) <= 150 and "cell size" in result.stdout
    result = run("decimate", torus_file, "-o", out, "--error", "0.1", "--method", "cluster")
    assert result.returncode == 0, result.stderr
    V0, F0 = io.read_mesh(torus_file)
    V, F = io.read_mesh(out)
    # every representative lies in a cell of an input vertex: at most a cell diagonal (the
    # requested error) from the input surface
    symmetric, out_to_in, _ = geometry.hausdorff_distance(V, F, V0, F0, one_sided=True)
    assert out_to_in <= 0.1 + 1e-12
    assert hausdorff_printed(result.stdout) == pytest.approx(symmetric, rel=1e-4)


def test_progressive_and_lod(torus_file, tmp_path):
    out, pm_path = tmp_path / "base.ply", tmp_path / "torus.pm"
    result = run("decimate", torus_file, "-o", out, "--faces", "200", "--progressive", pm_path)
    assert result.returncode == 0, result.stderr
    assert "vertex splits" in result.stdout
    V0, F0 = io.read_mesh(torus_file)
    Vb, Fb = io.read_mesh(out)
    assert len(Fb) == 200
    for faces in (200, 801, len(F0)):
        lod = tmp_path / f"lod{faces}.ply"
        result = run("lod", pm_path, "--faces", faces, "-o", lod)
        assert result.returncode == 0, result.stderr
        V, F = io.read_mesh(lod)
        assert len(F) <= faces and len(F) >= faces - 1
        assert topology.is_manifold(F)
    np.testing.assert_array_equal(V, V0)       # PLY keeps float64: the full level is the input


def test_errors_are_one_line(torus_file, tmp_path):
    out = tmp_path / "out.ply"
    result = run("decimate", torus_file, "-o", out, "--ratio", "1.5")   # a flag out of range: usage
    assert result.returncode == 2 and "--ratio" in result.stderr and len(result.stderr.strip().splitlines()) == 1
    cases = [
        ["decimate", torus_file, "-o", out, "--faces", "10", "--method", "cluster", "--progressive", tmp_path / "x.pm"],
        ["decimate", tmp_path / "missing.ply", "-o", out, "--faces", "10"],
        ["lod", tmp_path / "missing.pm", "--faces", "10", "-o", out],
        ["lod", torus_file, "--faces", "10", "-o", out],     # not a progressive mesh
    ]
    for args in cases:
        result = run(*args)
        assert result.returncode == 1, (args, result.stdout)
        assert result.stderr.startswith("meshsmith: error:") and len(result.stderr.strip().splitlines()) == 1
    assert run("decimate", torus_file, "-o", out).returncode == 2      # no stop rule: argparse
    pm_path = tmp_path / "t.pm"
    assert run("decimate", torus_file, "-o", out, "--faces", "400", "--progressive", pm_path).returncode == 0
    result = run("lod", pm_path, "--faces", "5", "-o", out)
    assert result.returncode == 1 and "below the base mesh" in result.stderr


def test_progress_bar_is_used(torus_file, tmp_path, monkeypatch):
    calls = []

    class RecordingBar(cli.ProgressBar):
        def __call__(self, fraction, stage):
            calls.append((fraction, stage))
            return True

    monkeypatch.setattr(cli.decimation, "ProgressBar", RecordingBar)  # the decimate command's module
    assert cli.main(["decimate", str(torus_file), "-o", str(tmp_path / "o.ply"), "--faces", "300"]) == 0
    assert calls and calls[-1][0] == 1.0


def test_demo_decimation_stage(tmp_path):
    from meshsmith import demo
    V, F = datasets.torus(1.0, 0.4, 48, 24)
    context = demo.DemoContext(tmp_path, "torus", V, F)
    section = demo.stage_decimation(context)
    assert [name for name, _ in section.images] == ["decimated_100.png", "decimated_10.png", "decimated_1.png"]
    assert all((tmp_path / name).stat().st_size > 1000 for name, _ in section.images)
    figures = context.figures["decimation"]
    assert figures["100%: faces"] == len(F)
    assert figures["10%: faces"] <= len(F) // 10 and figures["1%: faces"] <= max(4, len(F) // 100)
    assert 0 < figures["10%: Hausdorff distance / bounding-box diagonal"] \
        < figures["1%: Hausdorff distance / bounding-box diagonal"] < 0.1
    assert all(figures[f"{p}%: manifold, Euler characteristic"] == (True, 0) for p in (100, 10, 1))
    assert (tmp_path / "decimation.pm").is_file()
