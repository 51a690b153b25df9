"""`meshsmith deform`: the written mesh is the library's deformation of the input, and bad input
(overlapping or malformed vertex lists, a NaN or projective transform) fails with one line."""
import subprocess
import sys

import numpy as np
import pytest

from meshsmith import datasets, deformation, io


def run(*args):
    return subprocess.run([sys.executable, "-m", "meshsmith", *map(str, args)], capture_output=True, text=True)


@pytest.fixture()
def files(tmp_path):
    V, F = datasets.icosphere(3)
    io.write_mesh(tmp_path / "sphere.ply", V, F)
    c, s = np.cos(0.4), np.sin(0.4)
    T = np.array([[c, -s, 0, 0.1], [s, c, 0, 0.0], [0, 0, 1, 0.2], [0, 0, 0, 1]])
    np.savetxt(tmp_path / "T.txt", T)
    handle = np.flatnonzero(V[:, 2] > 0.8)
    fixed = np.flatnonzero(V[:, 2] < -0.8)
    np.savetxt(tmp_path / "fixed.txt", fixed, fmt="%d")
    return tmp_path, V, F, T, handle, fixed


@pytest.mark.parametrize("method", ["harmonic", "arap"])
def test_deform_writes_the_library_result(files, method):
    folder, V, F, T, handle, fixed = files
    out = folder / "out.ply"
    ids = ",".join(map(str, handle))
    result = run("deform", folder / "sphere.ply", "--handle", ids, "--fixed", f"@{folder / 'fixed.txt'}",
                 "--transform", folder / "T.txt", "--method", method, "--iterations", 3, "-o", out)
    assert result.returncode == 0, result.stderr
    assert f"{len(handle):,} handle and {len(fixed):,} fixed" in result.stdout
    U, F_out = io.read_mesh(out)
    if method == "harmonic":
        expected = deformation.Deformer(V, F, handle, fixed).transform(T)
    else:
        moved = V[handle] @ T[:3, :3].T + T[:3, 3]
        expected = deformation.arap(V, F, np.concatenate([handle, fixed]), np.concatenate([moved, V[fixed]]),
                                    iterations=3)
    assert np.array_equal(F_out, F)
    assert np.abs(U - expected).max() <= 1e-6   # the PLY's float precision


@pytest.mark.parametrize("arguments, status, words", [
    (["--handle", "0-5", "--fixed", "5-9"], 1, "both in handle and in fixed"),
    (["--handle", "5-2"], 2, "runs backwards"),
    (["--handle", "a,b"], 2, "expected indices and ranges"),
    (["--handle", "0,100000"], 1, "outside"),
])
def test_bad_vertex_lists(files, arguments, status, words):
    folder = files[0]
    result = run("deform", folder / "sphere.ply", *arguments, "--transform", folder / "T.txt", "-o", folder / "o.obj")
    assert result.returncode == status
    assert words in result.stderr and "Traceback" not in result.stderr and len(result.stderr.splitlines()) == 1


@pytest.mark.parametrize("matrix, words", [
    ("nan 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", "must be finite"),
    ("1 0 0 0\n0 1 0 0\n0 0 1 0\n1 0 0 1\n", "must be affine"),
    ("1 0 0\n0 1 0\n", "expected 4x4"),
])
def test_bad_transforms(files, matrix, words):
    folder = files[0]
    (folder / "bad.txt").write_text(matrix)
    result = run("deform", folder / "sphere.ply", "--handle", "0-3", "--transform", folder / "bad.txt", "-o",
                 folder / "o.obj")
    assert result.returncode == 1 and words in result.stderr and "Traceback" not in result.stderr
