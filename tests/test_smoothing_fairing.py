"""Bi-Laplacian fairing (smoothing.bilaplacian): libigl agreement on the same held set, analytic
truth (a plane stays a plane), C¹ hold of the boundary ring, and bad input."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, smoothing

igl = pytest.importorskip("igl")


def boundary_ring(F, n):
    boundary = np.unique(igl.boundary_loop(np.asarray(F, np.int64)))
    adjacency = igl.adjacency_list(np.asarray(F, np.int64))
    ring = set(boundary.tolist())
    for v in boundary:
        ring.update(adjacency[v])
    return np.array(sorted(ring))


def test_bilaplacian_equals_libigl_harmonic_k2_with_the_same_held_vertices():
    V, F = datasets.disk(n_rings=14, n_segments=56)
    rng = np.random.default_rng(3)
    V = V + 0.02 * rng.standard_normal(V.shape)
    fixed = np.array([0, 50, 400])
    ours = smoothing.bilaplacian(V, F, fixed=fixed)
    held = np.union1d(boundary_ring(F, len(V)), fixed)
    theirs = igl.harmonic(V, F.astype(np.int64), held.astype(np.int64), V[held], 2)
    assert np.abs(ours - theirs).max() <= 1e-9 * np.abs(V).max()
    assert np.array_equal(ours[held], V[held])


def test_a_noisy_plane_fairs_to_the_plane():
    V, F = datasets.grid(24, 24)
    rng = np.random.default_rng(7)
    noisy = V.copy()
    noisy[:, 2] += 0.05 * rng.standard_normal(len(V))
    held = boundary_ring(F, len(V))
    noisy[held, 2] = 0.0   # the boundary ring is in the plane z = 0
    faired = smoothing.bilaplacian(noisy, F)
    assert np.abs(faired[:, 2]).max() <= 1e-12
    assert np.abs(noisy[:, 2]).max() > 0.05


def test_fixed_vertices_hold_a_closed_mesh_and_the_cap_is_smooth():
    V, F = datasets.icosphere(3)
    bumped = V.copy()
    cap = V[:, 2] > 0.6
    bumped[cap] *= 1.0 + 0.1 * np.random.default_rng(1).standard_normal((cap.sum(), 1))
    fixed = np.flatnonzero(~cap)
    faired = smoothing.bilaplacian(bumped, F, fixed=fixed)
    assert np.array_equal(faired[fixed], bumped[fixed])
    # The faired cap deviates from the sphere far less than the bumped one did.
    assert np.abs(np.linalg.norm(faired[cap], axis=1) - 1).max() < 0.3 * np.abs(
        np.linalg.norm(bumped[cap], axis=1) - 1).max()


@pytest.mark.parametrize("fixed", [None, [], [0, 0], [-1], [10 ** 6], [0.5]])
def test_closed_mesh_without_valid_fixed_vertices_is_an_input_error(fixed):
    V, F = datasets.icosphere(2)
    with pytest.raises(meshsmith.InputError):
        smoothing.bilaplacian(V, F, fixed=fixed)


def test_a_free_component_is_named():
    V, F = datasets.icosphere(2)
    V2, F2 = np.vstack([V, V + 3]), np.vstack([F, F + len(V)])
    with pytest.raises(meshsmith.InputError, match=f"vertex {len(V)} is in a connected part"):
        smoothing.bilaplacian(V2, F2, fixed=[0])


def test_meshsmith_smooth_bilaplacian_writes_the_fairing(tmp_path):
    import subprocess
    import sys

    from meshsmith import io
    V, F = datasets.disk(n_rings=10, n_segments=40)
    V = V + 0.01 * np.random.default_rng(2).standard_normal(V.shape)
    io.write_mesh(tmp_path / "disk.ply", V, F)
    run = lambda *args: subprocess.run([sys.executable, "-m", "meshsmith", "smooth", *map(str, args)],  # noqa: E731
                                       capture_output=True, text=True)
    result = run(tmp_path / "disk.ply", "-o", tmp_path / "faired.ply", "--method", "bilaplacian")
    assert result.returncode == 0, result.stderr
    assert "bilaplacian smoothing, one solve" in result.stdout
    U, _ = io.read_mesh(tmp_path / "faired.ply")
    assert np.abs(U - smoothing.bilaplacian(io.read_mesh(tmp_path / "disk.ply")[0], F)).max() <= 1e-6
    bad = run(tmp_path / "disk.ply", "-o", tmp_path / "x.ply", "--method", "bilaplacian", "--epsilon", "0.1")
    assert bad.returncode == 2 and "--epsilon does not apply to --method bilaplacian" in bad.stderr
