"""datasets: procedural shapes and samples, checked with meshsmith.topology and geometry."""
import re

import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, geometry, topology

# name: (generator call, χ, genus, boundary loops)
SHAPES = {
    "icosphere": (lambda: datasets.icosphere(3), 2, 0, 0),
    "icosphere0": (lambda: datasets.icosphere(0), 2, 0, 0),
    "uv_sphere": (lambda: datasets.uv_sphere(), 2, 0, 0),
    "uv_sphere_coarse": (lambda: datasets.uv_sphere(2, 3), 2, 0, 0),
    "torus": (lambda: datasets.torus(), 0, 1, 0),
    "torus_coarse": (lambda: datasets.torus(n_major=3, n_minor=3, minor_radius=0.5), 0, 1, 0),
    "grid": (lambda: datasets.grid(), 1, 0, 1),
    "grid_1x1": (lambda: datasets.grid(1, 1, size=(2.0, 3.0)), 1, 0, 1),
    "disk": (lambda: datasets.disk(), 1, 0, 1),
    "disk_odd": (lambda: datasets.disk(7, 29), 1, 0, 1),
    "disk_one_ring": (lambda: datasets.disk(1, 5), 1, 0, 1),
    "cube": (lambda: datasets.cube(), 2, 0, 0),
    "cube1": (lambda: datasets.cube(1), 2, 0, 0),
}


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_shapes_have_the_right_topology_and_are_clean(name):
    make, chi, genus, loops = SHAPES[name]
    V, F = make()
    assert V.dtype == np.float64 and V.shape[1] == 3 and F.dtype == np.int64 and F.shape[1] == 3
    info = topology.info(V, F)
    assert (info.euler_characteristic, info.genus, info.n_boundary_loops) == (chi, genus, loops)
    assert info.is_manifold and info.is_oriented and info.n_components == 1
    assert info.n_unreferenced_vertices == 0
    assert len(np.unique(V.round(12), axis=0)) == len(V)          # no duplicate vertices
    assert np.all(geometry.face_areas(V, F) > 0)                   # no degenerate triangles
    if loops == 0:
        assert info.volume > 0                                     # outward orientation
    else:                                                          # flat shapes face +z
        normals = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
        assert np.all(normals[:, 2] > 0) and np.allclose(V[:, 2], 0)


def test_sizes_and_radii():
    V, F = datasets.icosphere(2, radius=3.0)
    assert (len(V), len(F)) == (162, 320)
    assert np.allclose(np.linalg.norm(V, axis=1), 3.0)
    V, F = datasets.uv_sphere(8, 12, radius=0.5)
    assert (len(V), len(F)) == (2 + 7 * 12, 2 * 12 * 7)
    assert np.allclose(np.linalg.norm(V, axis=1), 0.5)
    V, F = datasets.torus(2.0, 0.5, 20, 10)
    ring_distance = np.hypot(np.linalg.norm(V[:, :2], axis=1) - 2.0, V[:, 2])
    assert np.allclose(ring_distance, 0.5) and len(F) == 400
    V, F = datasets.grid(4, 3, size=(2.0, 1.5))
    assert (len(V), len(F)) == (20, 24)
    assert geometry.surface_area(V, F) == pytest.approx(3.0)
    V, F = datasets.disk(16, 64, radius=2.0)
    assert np.linalg.norm(V, axis=1).max() == pytest.approx(2.0)
    boundary = topology.boundary_loops(F)[0]
    assert len(boundary) == 64 and np.allclose(np.linalg.norm(V[boundary], axis=1), 2.0)
    assert geometry.surface_area(V, F) == pytest.approx(np.pi * 4, rel=0.01)
    V, F = datasets.cube(3, size=2.0)
    assert (len(V), len(F)) == (6 * 9 + 2, 12 * 9)
    assert np.abs(V).max() == 1.0 and geometry.volume(V, F) == pytest.approx(8.0)


def test_icosphere_at_eight_subdivisions_is_the_benchmark_size():
    V, F = datasets.icosphere(6)
    assert len(F) == 20 * 4 ** 6 and len(V) == 10 * 4 ** 6 + 2
    assert topology.euler_characteristic(F) == 2


def test_noisy_moves_vertices_along_normals_deterministically():
    V, F = datasets.icosphere(3)
    V1, F1 = datasets.noisy(V, F, sigma=0.05, seed=3)
    V2, _ = datasets.noisy(V, F, sigma=0.05, seed=3)
    V3, _ = datasets.noisy(V, F, sigma=0.05, seed=4)
    assert np.array_equal(V1, V2) and not np.array_equal(V1, V3)
    assert np.array_equal(F1, F) and F1 is not F
    displacement = V1 - V
    # On a sphere the area-weighted vertex normal is (nearly) radial: little tangential motion.
    radial = np.einsum("ij,ij->i", displacement, V)
    assert np.all(np.abs(radial) >= 0.999 * np.linalg.norm(displacement, axis=1))
    edge = np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1).mean()
    assert np.std(radial) == pytest.approx(0.05 * edge, rel=0.1)
    Vi, _ = datasets.noisy(V, F, sigma=0.05, seed=3, direction="isotropic")
    assert np.std(Vi - V) == pytest.approx(0.05 * edge, rel=0.1)
    assert np.array_equal(datasets.noisy(V, F, sigma=0.0)[0], V)


def test_sample_points_lie_on_the_surface_with_the_face_normals():
    V, F = datasets.cube(2, size=2.0)
    P, N = datasets.sample_points(V, F, 5000, seed=1)
    assert P.shape == N.shape == (5000, 3)
    assert np.allclose(np.linalg.norm(N, axis=1), 1.0)
    assert np.allclose(np.abs(P).max(axis=1), 1.0)                 # on the cube's surface
    # The normal is the outward axis of the side the point lies on.
    side = np.argmax(np.abs(P), axis=1)
    assert np.allclose(N[np.arange(len(P)), side], np.sign(P[np.arange(len(P)), side]))
    # Area-uniform: each of the six sides gets about a sixth of the points.
    counts = np.bincount(side * 2 + (P[np.arange(len(P)), side] > 0), minlength=6)
    assert np.all(np.abs(counts / 5000 - 1 / 6) < 0.03)
    P2, N2 = datasets.sample_points(V, F, 5000, seed=1)
    assert np.array_equal(P, P2) and np.array_equal(N, N2)
    Pn, Nn = datasets.sample_points(V, F, 5000, seed=1, noise=0.1)
    assert np.array_equal(Nn, N) and not np.allclose(np.abs(Pn).max(axis=1), 1.0)
    Vs, Fs = datasets.icosphere(4)
    Ps, Ns = datasets.sample_points(Vs, Fs, 1000)
    assert np.allclose(np.linalg.norm(Ps, axis=1), 1.0, atol=0.01)
    assert np.all(np.einsum("ij,ij->i", Ps, Ns) > 0.99)


def test_sphere_points():
    P, N = datasets.sphere_points(2000, seed=5, radius=2.0)
    assert np.allclose(np.linalg.norm(P, axis=1), 2.0) and np.allclose(P, 2.0 * N)
    assert np.allclose(P.mean(axis=0), 0, atol=0.1)
    assert np.array_equal(P, datasets.sphere_points(2000, seed=5, radius=2.0)[0])


def test_scan_pair_has_the_documented_noise_outliers_and_motion():
    V, F = datasets.icosphere(4)                       # unit sphere: distances to it are analytic
    pair = datasets.scan_pair(V, F, n_source=3000, n_target=5000, noise=0.01, outliers=0.25, angle=30.0,
                              translation=0.1, seed=3)
    assert pair.source.shape == (4000, 3) and pair.n_outliers == 1000
    assert pair.target.shape == pair.target_normals.shape == (5000, 3)
    assert np.isclose(pair.diagonal, np.linalg.norm(V.max(0) - V.min(0)))
    R, t = pair.motion[:3, :3], pair.motion[:3, 3]
    assert np.allclose(R @ R.T, np.eye(3), atol=1e-14) and np.isclose(np.linalg.det(R), 1.0)
    assert np.isclose(np.degrees(np.arccos((np.trace(R) - 1) / 2)), 30.0)
    assert np.isclose(np.linalg.norm(t), 0.1 * pair.diagonal) and np.array_equal(pair.motion[3], [0, 0, 0, 1])
    back = (pair.source - t) @ R                      # the inverse motion
    radial = np.linalg.norm(back, axis=1) - 1.0
    surface, wrong = radial[:-1000], back[-1000:]
    # Isotropic noise of 1% of the diagonal: its normal component has that standard deviation.
    assert abs(surface.std() / (0.01 * pair.diagonal) - 1.0) < 0.1 and abs(surface.mean()) < 0.002
    box = 1.0 + 0.1 * pair.diagonal                   # the bounding box grown by the margin
    assert np.abs(wrong).max() <= box and np.abs(wrong).max() > 1.0
    assert np.allclose(np.linalg.norm(pair.target, axis=1), 1.0, atol=0.01)
    again = datasets.scan_pair(V, F, n_source=3000, n_target=5000, noise=0.01, outliers=0.25, seed=3)
    assert all(np.array_equal(a, b) for a, b in zip(pair, again))
    assert not np.array_equal(pair.source, datasets.scan_pair(V, F, n_source=3000, outliers=0.25, seed=4).source)
    assert datasets.scan_pair(V, F, n_source=10, outliers=0.0).source.shape == (10, 3)


def test_partial_views_are_posed_noisy_samples_facing_their_views():
    V, F = datasets.icosphere(4)                       # unit sphere: distances to it are analytic
    views = datasets.partial_views(V, F, n_views=3, n_points=2000, noise=0.005, seed=7)
    assert len(views.scans) == 3 and all(scan.shape == (2000, 3) for scan in views.scans)
    assert np.array_equal(views.poses[0], np.eye(4)) and np.array_equal(views.starts[0], np.eye(4))
    for k, (scan, pose, start) in enumerate(zip(*views[:3])):
        world = scan @ pose[:3, :3].T + pose[:3, 3]   # back in the mesh's frame
        radial = np.linalg.norm(world, axis=1) - 1.0
        assert abs(radial.std() / (0.005 * views.diagonal) - 1.0) < 0.15
        azimuth = 2 * np.pi * k / 3
        facing = world @ np.array([np.cos(azimuth), 0.0, np.sin(azimuth)])
        assert facing.min() > -0.2                    # normal · view > −0.1, up to the noise (σ 0.017)
        if k:
            assert np.isclose(np.degrees(np.arccos((np.trace(pose[:3, :3]) - 1) / 2)), 25.0)
            assert np.isclose(np.linalg.norm(pose[:3, 3]), 0.05 * views.diagonal)
            off = np.linalg.inv(pose) @ start
            assert np.isclose(np.degrees(np.arccos((np.trace(off[:3, :3]) - 1) / 2)), 10.0)
            assert np.isclose(np.linalg.norm(off[:3, 3]), 0.02 * views.diagonal)
    again = datasets.partial_views(V, F, n_views=3, n_points=2000, noise=0.005, seed=7)
    assert all(np.array_equal(a, b) for a, b in zip(views.scans, again.scans))
    with pytest.raises(meshsmith.InputError, match="view 0 sees"):
        datasets.partial_views(V, F, n_points=25000)
    with pytest.raises(meshsmith.InputError, match="noise must be a non-negative"):
        datasets.partial_views(V, F, noise=np.nan)


@pytest.mark.parametrize("call, message", [
    (lambda: datasets.scan_pair(*datasets.cube(1), outliers=1.0), "outliers must be a fraction in [0, 1)"),
    (lambda: datasets.scan_pair(*datasets.cube(1), noise=-0.1), "noise must be a non-negative"),
    (lambda: datasets.scan_pair(*datasets.cube(1), angle=np.inf), "angle must be a non-negative"),
    (lambda: datasets.scan_pair(*datasets.cube(1), n_source=0), "n_source = 0: expected an integer"),
    (lambda: datasets.icosphere(-1), "subdivisions = -1: expected an integer in [0, 10]"),
    (lambda: datasets.icosphere(2.5), "subdivisions = 2.5: expected an integer"),
    (lambda: datasets.icosphere(2**70), "subdivisions = 1180591620717411303424: expected an integer in [0, 10]"),
    (lambda: datasets.icosphere(np.nan), "subdivisions = nan: expected an integer"),
    (lambda: datasets.icosphere(2, radius=0), "radius must be a positive"),
    (lambda: datasets.uv_sphere(1, 8), "n_latitude = 1: expected an integer in [2, 67108864]"),
    (lambda: datasets.uv_sphere(8, 2), "n_longitude = 2: expected an integer in [3, 67108864]"),
    (lambda: datasets.torus(n_major=2), "n_major = 2: expected an integer in [3, 67108864]"),
    (lambda: datasets.torus(1.0, 1.5), "minor_radius (1.5) must be smaller"),
    (lambda: datasets.torus(minor_radius=np.nan), "minor_radius must be a positive"),
    (lambda: datasets.grid(0, 3), "nx = 0: expected an integer in [1, 67108864]"),
    (lambda: datasets.grid(2, 2, size=(1.0, -1.0)), "size[1] must be a positive"),
    (lambda: datasets.grid(2, 2, size=3.0), "size must be a pair"),
    (lambda: datasets.disk(0), "n_rings = 0: expected an integer in [1, 67108864]"),
    (lambda: datasets.disk(4, 2), "n_segments = 2: expected an integer in [3, 67108864]"),
    (lambda: datasets.cube(0), "subdivisions = 0: expected an integer in [1, 67108864]"),
    (lambda: datasets.cube(True), "subdivisions = True: expected an integer"),
    (lambda: datasets.noisy(*datasets.cube(1), sigma=-1), "sigma must be a non-negative"),
    (lambda: datasets.noisy(*datasets.cube(1), direction="up"), "direction must be"),
    (lambda: datasets.noisy(np.zeros((0, 3)), np.zeros((0, 3), int)), "V is empty"),
    (lambda: datasets.sample_points(*datasets.cube(1), n=0), "n = 0: expected an integer in [1, 67108864]"),
    (lambda: datasets.sample_points(*datasets.cube(1), n=5, seed=-1), "seed = -1: expected an integer in [0, 18446744073709551615]"),
    (lambda: datasets.sample_points(*datasets.cube(1), n=5, seed=np.nan), "seed = nan: expected an integer"),
    (lambda: datasets.sample_points(*datasets.cube(1), n=5, noise=-0.1), "noise must be"),
    (lambda: datasets.sample_points(np.zeros((3, 3)), [[0, 1, 2]], n=5), "zero area"),
    (lambda: datasets.sample_points(np.zeros((3, 3)), [[0, 1, 3]], n=5), "indexes vertex 3"),
    (lambda: datasets.sphere_points(0), "n = 0: expected an integer in [1, 67108864]"),
    (lambda: datasets.icosphere(12), "subdivisions = 12: expected an integer in [0, 10]"),
    (lambda: datasets.uv_sphere(10**5, 10**5), "at most MAX_ELEMENTS"),
    (lambda: datasets.torus(n_major=10**6, n_minor=10**6), "at most MAX_ELEMENTS"),
    (lambda: datasets.grid(10**5, 10**5), "at most MAX_ELEMENTS"),
    (lambda: datasets.disk(10**4, 10**4), "at most MAX_ELEMENTS"),
    (lambda: datasets.cube(10**3), "at most MAX_ELEMENTS"),
    (lambda: datasets.sample_points(*datasets.cube(1), n=10**9), "n = 1000000000: expected an integer in [1, 67108864]"),
    (lambda: datasets.sphere_points(2**63), "n = 9223372036854775808: expected an integer in [1, 67108864]"),
    (lambda: datasets.sphere_points(10**9), "n = 1000000000: expected an integer in [1, 67108864]"),
])
def test_bad_parameters_raise_input_error(call, message):
    with pytest.raises(meshsmith.InputError, match=re.escape(message)):
        call()
