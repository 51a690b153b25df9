"""`meshsmith parametrize` and the demo's parametrization stage: texture coordinates written as
OBJ vt lines that reproduce the library's map, pictures, distortion printed, clean errors."""
import json
import subprocess
import sys

import numpy as np
import pytest

from meshsmith import cli, datasets, geometry, io
from meshsmith import parametrization as P


def run(*args):
    return subprocess.run([sys.executable, "-m", "meshsmith", *map(str, args)], capture_output=True, text=True)


@pytest.fixture()
def disk_file(tmp_path):
    V, F = datasets.disk(n_rings=8, n_segments=32)
    V = V.copy()
    V[:, 2] = 0.3 * V[:, 0] ** 2
    path = tmp_path / "disk.off"
    io.write_mesh(path, V, F)
    return path


@pytest.fixture()
def torus_file(tmp_path):
    V, F = datasets.torus(n_major=32, n_minor=16)
    path = tmp_path / "torus.ply"
    io.write_mesh(path, V, F)
    return path


def test_help():
    result = run("parametrize", "--help")
    assert result.returncode == 0 and "usage: meshsmith parametrize" in result.stdout
    for method in ("tutte", "harmonic", "stretch", "lscm", "abf", "abf++"):
        assert method in result.stdout


@pytest.mark.parametrize("method", ["tutte", "harmonic", "stretch", "lscm"])
def test_parametrize_disk_writes_the_library_map(disk_file, tmp_path, method, capsys):
    out = tmp_path / "flat.obj"
    assert cli.main(["parametrize", str(disk_file), "--method", method, "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "angle distortion" in printed and "bijective                                True" in printed
    mesh = io.read_mesh(out, return_attributes=True)
    V, F = io.read_mesh(disk_file)
    np.testing.assert_array_equal(mesh.F, F)
    expected = P.parametrize(V, F, method=method).uv
    np.testing.assert_allclose(mesh.UV[mesh.F_uv], expected[F], atol=1e-12)


def test_parametrize_closed_mesh_is_cut_and_pictured(torus_file, tmp_path):
    out, picture = tmp_path / "torus.obj", tmp_path / "torus.png"
    result = run("parametrize", torus_file, "--method", "lscm", "-o", out, "--picture", picture)
    assert result.returncode == 0, result.stderr
    assert "seam edges" in result.stdout
    mesh = io.read_mesh(out, return_attributes=True)
    V, F = io.read_mesh(torus_file)
    assert len(mesh.V) == len(V) and len(mesh.UV) > len(V)  # seam vertices have two texture coordinates
    # the texture coordinates are one-to-one on the cut mesh
    assert P.is_bijective(mesh.UV, mesh.F_uv)
    d = geometry.triangle_distortion(V[P.cut_to_disk(V, F).vertex_origin], mesh.F_uv, mesh.UV)
    assert len(d.flipped_faces) == 0
    from PIL import Image
    with Image.open(picture) as image:
        assert image.size == (1280, 640)


@pytest.mark.parametrize("args, message", [
    (["--method", "lscm", "-o", "{tmp}/out.ply"], ".obj"),
    (["--method", "abf++", "-o", "{tmp}/missing-folder/out.obj"], "missing-folder"),
])
def test_parametrize_clean_errors(disk_file, tmp_path, args, message):
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    if "-o" not in args:
        args += ["-o", str(tmp_path / "out.obj")]
    result = run("parametrize", disk_file, *args)
    assert result.returncode == 1
    assert result.stderr.startswith("meshsmith: error:") and message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_parametrize_non_manifold_input_is_a_clean_error(tmp_path):
    V, F = datasets.icosphere(1)
    F = np.vstack([F, [[F[0, 0], F[0, 1], F[10, 2] if F[10, 2] not in F[0] else F[11, 2]]]])
    path = tmp_path / "bad.off"
    io.write_mesh(path, V, F)
    result = run("parametrize", path, "-o", tmp_path / "out.obj")
    assert result.returncode == 1 and "non-manifold" in result.stderr


def test_demo_parametrization_stage(tmp_path):
    from meshsmith import demo
    name, V, F, uv = demo.builtin_shape()
    context = demo.DemoContext(out=tmp_path, name=name, V=V, F=F, uv=uv)
    section = demo.stage_parametrization(context)
    assert [image for image, _ in section.images] == [f"parametrization_{m}.png" for m in ("tutte", "lscm", "stretch")]
    assert all((tmp_path / image).stat().st_size > 1000 for image, _ in section.images)
    figures = context.figures["parametrization"]
    for method in ("tutte", "lscm", "stretch"):
        assert figures[f"{method}: bijective"] is True and figures[f"{method}: flipped triangles"] == 0
        assert figures[f"{method}: seam edges"] > 0  # the torus was cut
    assert figures["lscm: angle distortion (mean sigma1/sigma2)"] < figures["tutte: angle distortion (mean sigma1/sigma2)"]
    # the stretch-minimizing map never ends above the mean-value harmonic map it starts from
    cut = P.cut_to_disk(V, F)
    start = geometry.triangle_distortion(cut.V, cut.F, P.harmonic(cut.V, cut.F, weights="mean_value"))
    assert figures["stretch: stretch (Sander L2, 1 = isometry)"] <= start.normalized_global_stretch_l2
    assert figures["lscm: stretch (Sander L2, 1 = isometry)"] < figures["tutte: stretch (Sander L2, 1 = isometry)"]
    json.dumps(figures)  # results.json must be able to hold them
