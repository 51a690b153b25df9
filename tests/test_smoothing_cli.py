"""`meshsmith smooth` (issue 17 part 5): the command runs, respects --epsilon (and --slab), reports the
volume of a closed mesh, shows its progress, and rejects bad usage with one line; the demo's
smoothing stage."""
import subprocess
import sys

import numpy as np
import pytest

from meshsmith import cli, datasets, geometry, io


def run(*args):
    return subprocess.run([sys.executable, "-m", "meshsmith", *map(str, args)], capture_output=True, text=True)


@pytest.fixture()
def noisy_file(tmp_path):
    V, F = datasets.noisy(*datasets.icosphere(3), sigma=0.3, seed=4)
    path = tmp_path / "noisy.ply"
    io.write_mesh(path, V, F)
    return path


def test_taubin_by_default_keeps_the_volume_and_says_so(noisy_file, tmp_path):
    out = tmp_path / "smooth.obj"
    result = run("smooth", noisy_file, "-o", out, "--iterations", "20")
    assert result.returncode == 0, result.stderr
    V0, F0 = io.read_mesh(noisy_file)
    V, F = io.read_mesh(out)
    np.testing.assert_array_equal(F, F0)
    assert "taubin smoothing, 20 iterations" in result.stdout
    line = next(line for line in result.stdout.splitlines() if line.startswith("volume"))
    printed = float(line.split("(")[1].rstrip("%)"))
    assert printed == pytest.approx(100 * (geometry.volume(V, F) / geometry.volume(V0, F0) - 1), abs=1e-2)
    assert abs(printed) < 3.0           # 20 Laplacian steps: -29% here


@pytest.mark.parametrize("extra", [[], ["--slab"]])
def test_epsilon_bounds_every_vertex(noisy_file, tmp_path, extra):
    out = tmp_path / "bounded.ply"
    epsilon = 0.002
    result = run("smooth", noisy_file, "-o", out, "--method", "laplacian", "--iterations", "30",
                 "--epsilon", epsilon, *extra)
    assert result.returncode == 0, result.stderr
    V0, F = io.read_mesh(noisy_file)
    V, _ = io.read_mesh(out)
    D = V - V0
    if extra:
        bounded = np.abs((D * geometry.vertex_normals(V0, F)).sum(axis=1))
    else:
        bounded = np.linalg.norm(D, axis=1)
    # PLY stores the float64 positions exactly.
    assert bounded.max() <= epsilon and bounded.max() > 0.5 * epsilon


def test_the_progress_bar_reaches_the_end(noisy_file, tmp_path, monkeypatch):
    calls = []

    class RecordingBar(cli.ProgressBar):
        def __call__(self, fraction, stage):
            calls.append((fraction, stage))
            return True

    monkeypatch.setattr(cli.smoothing, "ProgressBar", RecordingBar)
    assert cli.main(["smooth", str(noisy_file), "-o", str(tmp_path / "o.off"), "--method", "laplacian",
                     "--implicit", "--lambda", "4"]) == 0
    assert calls[-1] == (1.0, "smoothing") and any(stage == "factorizing" for _, stage in calls)


@pytest.mark.parametrize("arguments, status, word", [
    (["--slab"], 2, "--slab needs --epsilon"),
    (["--implicit"], 2, "--implicit needs --method laplacian"),
    (["--lambda", "0"], 2, "--lambda"),
    (["--mu", "0.5"], 2, "--mu"),
    (["--epsilon", "-1"], 2, "--epsilon"),
    (["--method", "bogus"], 2, "--method"),
])
def test_bad_usage_is_one_line(noisy_file, tmp_path, arguments, status, word):
    result = run("smooth", noisy_file, "-o", tmp_path / "x.obj", *arguments)
    assert result.returncode == status
    assert word in result.stderr and "Traceback" not in result.stderr


def test_a_non_manifold_mesh_with_intrinsic_weights_fails_with_one_line(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], dtype=float)
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    path = tmp_path / "fin.obj"
    io.write_mesh(path, V, F)
    result = run("smooth", path, "-o", tmp_path / "x.obj", "--weights", "cotan_delaunay")
    assert result.returncode == 1 and "edge-manifold" in result.stderr and "Traceback" not in result.stderr


def test_demo_smoothing_stage(tmp_path):
    from meshsmith import demo
    V, F = datasets.torus(1.0, 0.4, 48, 24)
    context = demo.DemoContext(tmp_path, "torus", V, F)
    section = demo.stage_smoothing(context)
    assert all((tmp_path / name).stat().st_size > 1000 for name, _ in section.images)
    figures = context.figures["smoothing"]
    distance = lambda name: figures[f"{name}: mean distance to the clean surface / bounding-box diagonal"]  # noqa: E731
    assert distance("Taubin") < 0.6 * distance("noisy")
    assert abs(figures["Taubin: volume change"]) < 0.2 * abs(figures["Laplacian: volume change"])
