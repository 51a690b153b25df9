"""meshsmith.reconstruction.poisson and trim_by_density (§2.2, §3.1).

Samples of a sphere and a torus reconstruct into closed manifolds of the right Euler
characteristic near the true surface; the shared bunny point cloud reconstructs within a small
mean and Hausdorff distance of its ground-truth mesh; the result is the same on one core as on
all; the density marks where the surface was closed without samples, and trimming removes it.
"""
import hashlib
import subprocess
import sys

import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, geometry, io, reconstruction as rc, topology


def assert_closed_manifold(V, F, chi):
    assert topology.is_manifold(F) and topology.is_oriented(F)
    assert topology.boundary_loops(F) == []
    assert topology.euler_characteristic(F) == chi
    assert geometry.volume(V, F) > 0  # outward


def test_sphere_samples_reconstruct_a_closed_sphere():
    P, N = datasets.sphere_points(6000, seed=1)
    mesh = rc.poisson(P, N, depth=6)
    assert_closed_manifold(mesh.V, mesh.F, 2)
    radii = np.linalg.norm(mesh.V, axis=1)
    h = 1.1 * 2 / 2 ** 6
    assert np.abs(radii - 1).max() < 0.5 * h          # measured: about 0.2 h
    assert abs(np.median(radii) - 1) < 0.05 * h
    assert mesh.level_depths.tolist() == [4, 5, 6]
    assert np.all(mesh.level_residuals < 1e-3)  # the default tolerance


def test_torus_samples_reconstruct_a_genus_one_surface():
    V, F = datasets.torus()
    P, N = datasets.sample_points(V, F, 20000, seed=2)
    mesh = rc.poisson(P, N, depth=7)
    assert_closed_manifold(mesh.V, mesh.F, 0)
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    assert geometry.mean_surface_distance(mesh.V, mesh.F, V, F) < 1e-3 * diagonal


def test_bunny_point_cloud_reconstructs_near_the_ground_truth(data_dir):
    P, N = io.read_points(data_dir / "pmp-bunny.xyz")
    V, F = io.read_mesh(data_dir / "pmp-bunny.off")
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    # The benchmark quotes them beside the peers' (measured: Open3D 1.30e-4 / 4.2e-3 at point_weight
    # 4, 1.27e-4 / 4.7e-3 at 8; pymeshlab 1.51e-4 / 4.1e-3 at 4; ours 1.27e-4 / 4.0e-3 both ways:
    # nearly every sample has depth >= 6 and so refines to 7, the octree's leaves there).
    for adaptive, hausdorff_bound in ((True, 4.5e-3), (False, 4.5e-3)):
        mesh = rc.poisson(P, N, depth=8, adaptive=adaptive)
        assert_closed_manifold(mesh.V, mesh.F, 2)
        mean = geometry.mean_surface_distance(mesh.V, mesh.F, V, F) / diagonal
        hausdorff = geometry.hausdorff_distance(mesh.V, mesh.F, V, F) / diagonal
        assert mean < 1.3e-4 and hausdorff < hausdorff_bound, (adaptive, mean, hausdorff)
        # Most of the 35k samples are too sparse for depth 8: the surface is extracted at depth 7 (at
        # most), at the size of the peers' meshes (measured at depth 8: Open3D 46968 vertices,
        # pymeshlab 46817).
        assert mesh.extraction_depth == 7 and mesh.level_depths.tolist() == [4, 5, 6, 7]
        assert 0.9 * 46968 < len(mesh.V) < 1.1 * 46968


def test_the_uniform_extraction_depth_follows_the_sample_density():
    P, N = datasets.sphere_points(3000, seed=3)
    deep = rc.poisson(P, N, depth=8, adaptive=False)  # 3000 samples support depth 6 on this sphere
    assert deep.extraction_depth == 6 and deep.level_depths.tolist() == [4, 5, 6]
    shallow = rc.poisson(P, N, depth=6, adaptive=False)
    assert_closed_manifold(deep.V, deep.F, 2)
    assert abs(len(deep.V) - len(shallow.V)) < 0.05 * len(shallow.V)
    forced = rc.poisson(P, N, depth=8, extraction_depth=8, adaptive=False)  # finer: about 4× the vertices per level
    assert forced.extraction_depth == 8 and forced.level_depths.tolist() == [4, 5, 6, 7, 8]
    assert_closed_manifold(forced.V, forced.F, 2)
    assert 10 * len(deep.V) < len(forced.V) < 20 * len(deep.V)
    assert np.abs(np.linalg.norm(forced.V, axis=1) - 1).max() < 0.02
    # Levels 7 and 8 solved only around the samples that reach them: smaller bands than forced's.
    refined = rc.poisson(P, N, depth=8, band_refinement=2, adaptive=False)
    assert refined.extraction_depth == 6 and refined.level_depths.tolist() == [4, 5, 6, 7, 8]
    assert np.all(0 < refined.level_unknowns[3:]) and np.all(refined.level_unknowns[3:] < forced.level_unknowns[3:] / 2)
    assert_closed_manifold(refined.V, refined.F, 2)
    assert abs(len(refined.V) - len(deep.V)) < 0.05 * len(deep.V)


def test_the_result_does_not_depend_on_the_thread_count():
    P, N = datasets.sphere_points(3000, seed=4)
    P = P * (1 + 0.2 * np.sin(3 * P[:, [0]]))
    mesh = rc.poisson(P, N, depth=6)
    digest = hashlib.sha256(mesh.V.tobytes() + mesh.F.tobytes() + mesh.density.tobytes()).hexdigest()
    one_core = subprocess.run([sys.executable, "-c", (
        "import os; os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})\n"
        "import hashlib, numpy as np\n"
        "from meshsmith import datasets, reconstruction as rc\n"
        "P, N = datasets.sphere_points(3000, seed=4)\n"
        "P = P * (1 + 0.2 * np.sin(3 * P[:, [0]]))\n"
        "m = rc.poisson(P, N, depth=6)\n"
        "print(hashlib.sha256(m.V.tobytes() + m.F.tobytes() + m.density.tobytes()).hexdigest())")],
        capture_output=True, text=True, check=True)
    assert one_core.stdout.strip() == digest
    for threads in (1, 2):
        again = rc.poisson(P, N, depth=6, threads=threads)
        assert hashlib.sha256(again.V.tobytes() + again.F.tobytes() + again.density.tobytes()).hexdigest() == digest
    adaptive = [rc.poisson(P, N, depth=6, adaptive=True, threads=threads) for threads in (1, 2, None)]
    assert all(np.array_equal(m.V, adaptive[0].V) and np.array_equal(m.F, adaptive[0].F) and
               np.array_equal(m.density, adaptive[0].density) for m in adaptive[1:])


def test_density_marks_the_unsampled_cap_and_trimming_removes_it():
    P, N = datasets.sphere_points(8000, seed=5)
    keep = P[:, 2] > -0.3                      # a sphere with its bottom cap missing
    mesh = rc.poisson(P[keep], N[keep], depth=6, scale=1.6)  # the cube holds the closed surface
    assert_closed_manifold(mesh.V, mesh.F, 2)  # Poisson closes the hole
    low = mesh.V[:, 2] < -0.6
    assert mesh.density[low].max() < np.median(mesh.density[~low]) / 4
    trimmed = rc.trim_by_density(mesh.V, mesh.F, mesh.density, threshold=np.median(mesh.density) / 4)
    assert trimmed.V[:, 2].min() > -0.6
    assert len(topology.boundary_loops(trimmed.F)) >= 1
    np.testing.assert_array_equal(trimmed.V, mesh.V[trimmed.vertex_map])
    assert np.all(mesh.density[trimmed.vertex_map] >= np.median(mesh.density) / 4)
    by_quantile = rc.trim_by_density(mesh.V, mesh.F, mesh.density, quantile=0.5)
    cut = np.quantile(mesh.density, 0.5)
    assert np.all(mesh.density[by_quantile.vertex_map] >= cut) and len(by_quantile.V) < len(mesh.V)


def test_progress_is_reported_and_cancels():
    P, N = datasets.sphere_points(2000)
    seen = []
    rc.poisson(P, N, depth=5, progress=lambda f, s: seen.append(f))
    assert seen[-1] == 1.0 and seen == sorted(seen)
    with pytest.raises(meshsmith.Cancelled):
        rc.poisson(P, N, depth=5, progress=lambda f, s: False)


def test_bad_input_is_an_input_error():
    P, N = datasets.sphere_points(200)
    with pytest.raises(meshsmith.InputError, match="at least 4"):
        rc.poisson(P[:3], N[:3])
    with pytest.raises(meshsmith.InputError, match="one line"):
        rc.poisson(np.outer(np.arange(10.0), [1, 2, 3]), N[:10])
    with pytest.raises(meshsmith.InputError, match="coincide"):
        rc.poisson(np.ones((10, 3)), N[:10])
    zero = N.copy()
    zero[17] = 0
    with pytest.raises(meshsmith.InputError, match=r"N\[17\]"):
        rc.poisson(P, zero)
    with pytest.raises(meshsmith.InputError, match="one normal per sample"):
        rc.poisson(P, N[:100])
    nan = P.copy()
    nan[5, 2] = np.nan
    with pytest.raises(meshsmith.InputError, match="P"):
        rc.poisson(nan, N)
    with pytest.raises(meshsmith.InputError, match="depth"):
        rc.poisson(P, N, depth=11)
    with pytest.raises(meshsmith.InputError, match="screening"):
        rc.poisson(P, N, screening=-1)
    with pytest.raises(meshsmith.InputError, match="samples_per_node"):
        rc.poisson(P, N, samples_per_node=0)
    with pytest.raises(meshsmith.InputError, match="extraction_depth"):
        rc.poisson(P, N, depth=6, extraction_depth=7, adaptive=False)
    with pytest.raises(meshsmith.InputError, match="band_refinement"):
        rc.poisson(P, N, band_refinement=11)
    with pytest.raises(meshsmith.InputError, match="adaptive = false"):
        rc.poisson(P, N, depth=6, band_refinement=1, adaptive=True)
    with pytest.raises(meshsmith.InputError, match="threads"):
        rc.poisson(P, N, threads=0)
    V, F = datasets.icosphere(1)
    with pytest.raises(meshsmith.InputError, match="one per vertex"):
        rc.trim_by_density(V, F, np.ones(5))
    with pytest.raises(meshsmith.InputError, match="quantile"):
        rc.trim_by_density(V, F, np.ones(len(V)), quantile=2)


def half_dense_sphere(seed):
    """A unit sphere sampled 10× more densely on x > 0 than on x < 0."""
    P, N = datasets.sphere_points(40000, seed=seed)
    keep = (P[:, 0] > 0) | (np.arange(len(P)) % 10 == 0)
    return P[keep], N[keep]


def edge_lengths(V, F):
    return np.linalg.norm(V[F] - V[np.roll(F, 1, axis=1)], axis=2).ravel()


def test_the_adaptive_octree_is_fine_only_where_the_samples_are_dense():
    P, N = half_dense_sphere(7)
    adaptive = rc.poisson(P, N, depth=8, adaptive=True)
    uniform = rc.poisson(P, N, depth=8)
    # Cells of different sizes meet along x = 0 without cracks: one closed oriented 2-manifold.
    assert_closed_manifold(adaptive.V, adaptive.F, 2)
    assert_closed_manifold(uniform.V, uniform.F, 2)
    # The dense half is extracted on the finest leaves, the sparse half on coarser ones.
    centres = adaptive.V[adaptive.F].mean(axis=1)
    lengths = edge_lengths(adaptive.V, adaptive.F).reshape(-1, 3).mean(axis=1)
    dense, sparse = np.median(lengths[centres[:, 0] > 0.3]), np.median(lengths[centres[:, 0] < -0.3])
    assert sparse > 1.15 * dense, (dense, sparse)  # measured: 1.21 (leaves of depth 7 and 8 on the sparse half)
    # Fewer unknowns than bands around every sample at one extraction depth, same accuracy.
    assert adaptive.level_unknowns.sum() < 0.9 * uniform.level_unknowns.sum()  # measured: 921k / 1073k
    errors = {name: np.abs(np.linalg.norm(mesh.V, axis=1) - 1) for name, mesh in (("a", adaptive), ("u", uniform))}
    # measured: mean 3.9e-4 (uniform 5.5e-4), max 6.8e-3 (6.8e-3)
    assert errors["a"].mean() < 1.1 * errors["u"].mean() and errors["a"].max() < 1.1 * errors["u"].max(), \
        (errors["a"].mean(), errors["u"].mean(), errors["a"].max(), errors["u"].max())


def test_adaptive_leaves_of_several_depths_close_a_torus():
    V, F = datasets.torus()
    P, N = datasets.sample_points(V, F, 30000, seed=8, noise=0.05)
    keep = (P[:, 1] > 0) | (np.arange(len(P)) % 8 == 0)
    mesh = rc.poisson(P[keep], N[keep], depth=7, adaptive=True)
    assert_closed_manifold(mesh.V, mesh.F, 0)
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    assert geometry.mean_surface_distance(mesh.V, mesh.F, V, F) < 2e-3 * diagonal
