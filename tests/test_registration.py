"""Registration (§2.3.1): Horn's absolute orientation against analytic truth and scipy, ICP on
samples of a shared mesh under a known motion with noise and outliers, the raw Stanford scan pair
bun045 → bun000 against Stanford's own alignment (bun.conf), and bad input."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import meshsmith
from meshsmith import InputError, datasets, io, registration

RNG = np.random.default_rng(7)


def random_motion(rng, angle_degrees, translation):
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    direction = rng.normal(size=3)
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec(np.radians(angle_degrees) * axis).as_matrix()
    T[:3, 3] = translation * direction / np.linalg.norm(direction)
    return T


# ---- align: Horn's quaternion method -------------------------------------------------------

@pytest.mark.parametrize("scale", [1.0, 3.7])
def test_align_is_exact_on_noise_free_correspondences(scale):
    A = RNG.normal(size=(200, 3))
    truth = random_motion(RNG, 150.0, 5.0)   # far beyond ICP's range: align is global
    truth[:3, :3] *= scale
    B = registration.apply_transform(truth, A)
    T = registration.align(A, B, scale=scale != 1.0)
    assert np.abs(T - truth).max() < 1e-12 * max(1.0, scale * 5)
    assert np.array_equal(T[3], [0, 0, 0, 1])
    if scale == 1.0:   # rigid: no scale even when B is bigger than A
        T_rigid = registration.align(A, 2.0 * B)
        assert np.allclose(np.linalg.det(T_rigid[:3, :3]), 1.0, atol=1e-12)


def test_align_rotation_agrees_with_scipy_under_noise():
    A = RNG.normal(size=(500, 3))
    truth = random_motion(RNG, 40.0, 1.0)
    B = registration.apply_transform(truth, A) + 0.05 * RNG.normal(size=A.shape)
    weights = RNG.random(len(A))
    T = registration.align(A, B, weights=weights)
    ca, cb = (weights @ A) / weights.sum(), (weights @ B) / weights.sum()
    reference, _ = Rotation.align_vectors(B - cb, A - ca, weights=weights)   # Kabsch on the centred sets
    assert np.abs(T[:3, :3] - reference.as_matrix()).max() < 1e-10
    assert np.allclose(T[:3, 3], cb - T[:3, :3] @ ca, atol=1e-12)


def test_align_scale_from_the_spreads_is_symmetric():
    A = RNG.normal(size=(300, 3))
    B = 2.0 * registration.apply_transform(random_motion(RNG, 20.0, 1.0), A) + 0.1 * RNG.normal(size=A.shape)
    forward, backward = registration.align(A, B, scale=True), registration.align(B, A, scale=True)
    assert np.abs(forward @ backward - np.eye(4)).max() < 1e-12
    spreads = ((B - B.mean(0)) ** 2).sum() / ((A - A.mean(0)) ** 2).sum()
    assert np.isclose(np.cbrt(np.linalg.det(forward[:3, :3])), np.sqrt(spreads), rtol=1e-13)


def test_align_zero_weights_ignore_outliers_and_scale_invariance():
    A = RNG.normal(size=(50, 3))
    truth = random_motion(RNG, 70.0, 2.0)
    B = registration.apply_transform(truth, A)
    B[:10] += 5.0 * RNG.normal(size=(10, 3))          # wrong correspondences, weight 0
    weights = np.r_[np.zeros(10), np.ones(40)]
    assert np.abs(registration.align(A, B, weights=weights) - truth).max() < 1e-12
    # Coordinates near 1e200 (normalized internally): the same rotation.
    T_big = registration.align(1e200 * A[10:], 1e200 * B[10:])
    assert np.abs(T_big[:3, :3] - truth[:3, :3]).max() < 1e-12


@pytest.mark.parametrize("A, B, words", [
    (np.zeros((5, 3)), np.ones((5, 3)), "identical"),
    (np.outer(np.arange(6.0), [1, 2, 3]), RNG.normal(size=(6, 3)), "collinear"),
    (RNG.normal(size=(6, 3)), np.outer(np.arange(6.0), [1, 2, 3]) + 1, "collinear"),
    (RNG.normal(size=(2, 3)), RNG.normal(size=(2, 3)), "at least 3"),
    (RNG.normal(size=(5, 3)), RNG.normal(size=(6, 3)), "correspond"),
    (np.full((4, 3), np.nan), RNG.normal(size=(4, 3)), "nan"),
    (np.zeros((0, 3)), np.zeros((0, 3)), "empty"),
    (RNG.normal(size=(4, 2)), RNG.normal(size=(4, 2)), "shape"),
])
def test_align_rejects_degenerate_input(A, B, words):
    with pytest.raises(InputError, match=words):
        registration.align(A, B)


def test_align_rejects_bad_weights():
    A = RNG.normal(size=(5, 3))
    with pytest.raises(InputError, match="weights\\[2\\]"):
        registration.align(A, A, weights=[1, 1, -1, 1, 1])
    with pytest.raises(InputError, match="positive weight"):
        registration.align(A, A, weights=[1, 1, 0, 0, 0])
    with pytest.raises(InputError, match="entries"):
        registration.align(A, A, weights=[1, 1, 1])


# ---- ICP ------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def scan_pair(data_dir):
    """datasets.scan_pair on the shared bunny: 4000 source samples with 1% of the diagonal noise
    and 1000 outliers (20%), under a known motion of 30° and 10% of the diagonal, onto 8000
    other clean samples."""
    V, F = io.read_mesh(data_dir / "bunny.off")
    pair = datasets.scan_pair(V, F, seed=3)
    assert pair.n_outliers == 1000 and len(pair.source) == 5000
    return dict(pair._asdict(), V=V)


def recovery_errors(T, pair):
    """Angle (degrees) of T ∘ motion and the largest displacement of a mesh vertex under it / diagonal."""
    residual = T @ pair["motion"]
    moved = registration.apply_transform(residual, pair["V"])
    return (np.degrees(registration.rotation_angle(residual)),
            np.linalg.norm(moved - pair["V"], axis=1).max() / pair["diagonal"])


@pytest.mark.parametrize("method", registration.ICP_METHODS)
@pytest.mark.parametrize("rejection", ["trim", "max_distance"])
def test_icp_recovers_a_known_motion_despite_noise_and_outliers(scan_pair, method, rejection):
    options = dict(trim=0.75) if rejection == "trim" else dict(trim=0.9, max_distance=0.05 * scan_pair["diagonal"])
    result = registration.icp(scan_pair["source"], scan_pair["target"], method=method, max_iterations=200,
                              target_normals=scan_pair["target_normals"] if method == "point_to_plane" else None,
                              **options)
    angle, displacement = recovery_errors(result.transform, scan_pair)
    assert result.converged, result
    assert angle < 0.5 and displacement < 0.005, (angle, displacement)
    # The outliers (the last rows) are mostly rejected, the surface points mostly kept.
    outlier_kept = result.inliers[-scan_pair["n_outliers"]:].mean()
    surface_kept = result.inliers[:-scan_pair["n_outliers"]].mean()
    assert outlier_kept < 0.3 and surface_kept > 0.8, (outlier_kept, surface_kept)
    assert len(result.rms_history) == result.iterations and result.rms <= result.rms_history[0]
    assert np.isclose(result.inlier_fraction, result.inliers.mean())


def test_icp_without_outlier_rejection_is_worse(scan_pair):
    """The test above is not trivial: with every pair kept, the outliers pull the answer off."""
    result = registration.icp(scan_pair["source"], scan_pair["target"], max_iterations=200)
    trimmed = registration.icp(scan_pair["source"], scan_pair["target"], max_iterations=200, trim=0.75)
    assert recovery_errors(result.transform, scan_pair)[1] > 2 * recovery_errors(trimmed.transform, scan_pair)[1]


def test_icp_is_deterministic_whatever_the_thread_count(scan_pair):
    runs = [registration.icp(scan_pair["source"], scan_pair["target"], method="point_to_plane", trim=0.8,
                             threads=threads) for threads in (1, 2, None)]
    for run in runs[1:]:
        assert np.array_equal(run.transform, runs[0].transform)
        assert np.array_equal(run.inliers, runs[0].inliers)


def test_icp_voxel_reduction_keeps_per_point_results(scan_pair):
    voxel = 0.01 * scan_pair["diagonal"]
    result = registration.icp(scan_pair["source"], scan_pair["target"], method="point_to_plane", trim=0.75,
                              voxel_size=voxel, max_iterations=100)
    assert result.inliers.shape == (len(scan_pair["source"]),)
    angle, displacement = recovery_errors(result.transform, scan_pair)
    assert angle < 0.5 and displacement < 0.005, (angle, displacement)


def torus_demo_pair():
    """The demo's case: trimmed point-to-plane ICP (trim 0.8) of a torus scan with 0.5% noise and
    15% outliers, moved by 25° and 8% of the diagonal."""
    V, F = datasets.torus(major_radius=1.0, minor_radius=0.4, n_major=48, n_minor=24)
    pair = datasets.scan_pair(V, F, n_source=3000, n_target=6000, noise=0.005, outliers=0.15, margin=0.0,
                              angle=25.0, translation=0.08, seed=16)
    return V, F, pair, dict(method="point_to_plane", target_normals=pair.target_normals, trim=0.8, max_iterations=50)


def test_icp_oscillation_between_pair_sets_ends_as_converged():
    """With a pose tolerance alone (relative change and cycle/stall tests off) the trimmed ICP of
    the demo's torus never converges: its pairs flip at the trim threshold and the RMS wanders at
    the noise level for all 50 iterations. The stall/cycle tests end it as converged, at the pose
    of least RMS, aligned to the noise (mean distance of the aligned scan to the torus)."""
    V, F, pair, options = torus_demo_pair()
    plain = registration.icp(pair.source, pair.target, relative_rmse=0.0, patience=0, **options)
    assert not plain.converged and plain.stop == "max_iterations" and plain.iterations == 50
    tail = plain.rms_history[10:]
    assert tail.max() - tail.min() < 0.05 * tail.min()         # it is aligned: the RMS only wanders
    assert np.any(np.diff(tail) > 0)                          # ... up and down, so no tolerance ends it
    result = registration.icp(pair.source, pair.target, **options)
    assert result.converged and result.stop in ("cycle", "stalled"), result.stop
    assert result.iterations < 50 and result.rms <= 1.0001 * result.rms_history[-10:].min(), result.rms
    surface = meshsmith.geometry.SurfaceDistance(V, F)
    scan = registration.apply_transform(np.linalg.inv(pair.motion), pair.source[:-pair.n_outliers])
    after = surface.distances(registration.apply_transform(result.transform @ pair.motion, scan)).mean()
    noise = surface.distances(scan).mean()                    # the scan's own distance: its noise
    assert after < 1.1 * noise, (after, noise)


def test_icp_stop_reasons_and_relative_change():
    V, F = datasets.cube(4)
    pair = datasets.scan_pair(V * [1.0, 0.7, 0.4], F, n_source=1000, n_target=2000, noise=0.01, outliers=0.0,
                              angle=10.0, translation=0.05, seed=2)
    P, Q = pair.source, pair.target
    exact = registration.icp(P, Q, max_iterations=100)
    assert exact.converged and exact.stop in ("tolerance", "relative_change", "cycle", "stalled")
    # A coarse relative change (Open3D's relative_rmse) stops earlier, reported as such.
    coarse = registration.icp(P, Q, max_iterations=100, relative_rmse=0.01, relative_fitness=1.0, patience=0)
    assert coarse.converged and coarse.stop == "relative_change" and coarse.iterations < exact.iterations
    assert registration.icp(P, Q, max_iterations=1).stop == "max_iterations"
    for bad, words in ((dict(relative_rmse=-1.0), "relative_rmse"), (dict(relative_fitness=np.nan), "relative_fitness"),
                       (dict(patience=1), "patience"), (dict(patience=-2), "patience")):
        with pytest.raises(InputError, match=words):
            registration.icp(P, Q, **bad)


def test_icp_initial_transform_is_included():
    P = RNG.normal(size=(400, 3)) * [3, 2, 1]
    truth = random_motion(RNG, 120.0, 2.0)              # too far for ICP alone
    Q = registration.apply_transform(truth, P)
    result = registration.icp(P, Q, initial=truth @ random_motion(RNG, 2.0, 0.01))
    assert result.converged and np.abs(result.transform - truth).max() < 1e-6
    assert result.rms < 1e-6


def test_icp_reports_non_convergence_and_cancels():
    P = RNG.normal(size=(300, 3)) * [3, 2, 1]
    Q = registration.apply_transform(random_motion(RNG, 20.0, 0.5), P)
    result = registration.icp(P, Q, max_iterations=1)
    assert not result.converged and result.iterations == 1
    with pytest.raises(meshsmith.Cancelled):
        registration.icp(P, Q, progress=lambda fraction, stage: False)


def test_icp_bunny_scans_align_as_stanford_aligned_them(data_dir):
    """bun045 → bun000, the raw range scans. Start: the identity (the scans differ by 34°, within
    ICP's reach with point-to-plane). Truth: Stanford's bun.conf for bun045 (translation
    (-0.0520211, -0.000383981, -0.0109223), quaternion (0.00548449, -0.294635, -0.0038555,
    0.955586) read as (x, y, z, w) and conjugated: the convention that maps bun045 into bun000's
    frame)."""
    source = io.read_points(data_dir / "bun045.ply")[0]
    target = io.read_points(data_dir / "bun000.ply")[0]
    truth = np.eye(4)
    truth[:3, :3] = Rotation.from_quat([0.00548449, -0.294635, -0.0038555, 0.955586]).as_matrix().T
    truth[:3, 3] = [-0.0520211, -0.000383981, -0.0109223]
    result = registration.icp(source, target, method="point_to_plane", trim=0.8, max_iterations=100)
    assert result.converged
    assert 33.5 < np.degrees(registration.rotation_angle(result.transform)) < 35.0
    assert np.degrees(registration.rotation_angle(np.linalg.inv(truth) @ result.transform)) < 0.2
    displacement = np.linalg.norm(registration.apply_transform(result.transform, source)
                                  - registration.apply_transform(truth, source), axis=1).max()
    assert displacement < 0.001 * 0.2474 * 2       # 0.1% of bun000's diagonal (0.2474) twice over
    assert result.rms < 0.0005                       # scanner noise level: 0.3 mm on a 25 cm scan


@pytest.mark.parametrize("options, words", [
    (dict(voxel_size=0.0), "voxel_size"),
    (dict(voxel_size=-1.0), "voxel_size"),
    (dict(voxel_size=1e-9), "2\\^21"),
    (dict(voxel_size=100.0), "after the voxel reduction"),
    (dict(max_distance=0.0), "max_distance"),
    (dict(max_distance=1e-9), "within it"),
    (dict(trim=0.0), "trim"),
    (dict(trim=1.5), "trim"),
    (dict(max_iterations=0), "max_iterations"),
    (dict(tolerance=0.0), "tolerance"),
    (dict(method="point_to_surface"), "method"),
    (dict(initial=np.ones((3, 3))), "initial"),
    (dict(initial=np.full((4, 4), np.nan)), "initial"),
    (dict(method="point_to_plane", target_normals=np.zeros((300, 3))), "target_normals\\[0\\]"),
    (dict(method="point_to_plane", target_normals=np.ones((10, 3))), "rows"),
])
def test_icp_rejects_bad_parameters(options, words):
    P = RNG.normal(size=(300, 3))
    with pytest.raises(InputError, match=words):
        registration.icp(P + 5.0, P, **options)


def test_icp_rejects_bad_points():
    P = RNG.normal(size=(30, 3))
    with pytest.raises(InputError, match="source"):
        registration.icp(np.zeros((0, 3)), P)
    with pytest.raises(InputError, match="target"):
        registration.icp(P, np.vstack([P, [np.nan, 0, 0]]))


def test_voxel_downsample_matches_a_numpy_grouping():
    P = RNG.random((2000, 3)) * [2, 1, 0.5]
    voxel = 0.1
    cells = np.floor(P / voxel - P.min(0) / voxel).astype(np.int64)
    keys, inverse = np.unique(cells, axis=0, return_inverse=True)   # lexicographic, as documented
    inverse = inverse.reshape(-1)
    expected = np.zeros((len(keys), 3))
    np.add.at(expected, inverse, P)
    expected /= np.bincount(inverse)[:, None]
    assert np.allclose(registration.voxel_downsample(P, voxel), expected, rtol=0, atol=1e-14)


def test_icp_normal_angle_rejects_exactly_the_incompatible_pairs(scan_pair):
    """Normal compatibility (45°) with a light trim (0.9) rejects most outliers, whose PCA normals
    point anywhere, and recovers the motion where the light trim alone does not; at the result,
    the inlier mask is exactly the pairs (closest points by scipy) whose normals differ by at
    most the angle, as lines, and that the trim keeps."""
    from scipy.spatial import cKDTree
    source, target = scan_pair["source"], scan_pair["target"]
    source_normals = meshsmith.points.estimate_normals(source, k=16)
    options = dict(method="point_to_plane", trim=0.9, max_iterations=200, target_normals=scan_pair["target_normals"])
    result = registration.icp(source, target, normal_angle=45.0, source_normals=source_normals, **options)
    angle, displacement = recovery_errors(result.transform, scan_pair)
    assert result.converged and angle < 0.5 and displacement < 0.005, (angle, displacement)
    assert result.inliers[-scan_pair["n_outliers"]:].mean() < 0.15, result.inliers[-scan_pair["n_outliers"]:].mean()
    assert result.inliers[:-scan_pair["n_outliers"]].mean() > 0.8
    moved = registration.apply_transform(result.transform, source)
    distance, nearest = cKDTree(target).query(moved)
    turned = source_normals @ result.transform[:3, :3].T
    cosine = np.abs(np.einsum("ij,ij->i", turned, scan_pair["target_normals"][nearest]))
    compatible = cosine >= np.cos(np.radians(45.0))
    cut = np.sort(distance[compatible])[int(np.ceil(0.9 * compatible.sum())) - 1]
    expected = compatible & (distance <= cut)
    assert (result.inliers != expected).sum() <= 2, (result.inliers != expected).sum()   # ties at a threshold only
    # The light trim alone lets the outliers pull the answer off: the normal test is what helps.
    plain = registration.icp(source, target, **options)
    assert recovery_errors(plain.transform, scan_pair)[1] > 2 * displacement


def test_icp_normal_angle_estimates_missing_normals_and_rejects_bad_values(scan_pair):
    source, target = scan_pair["source"], scan_pair["target"]
    result = registration.icp(source, target, normal_angle=45.0, trim=0.9, max_iterations=200)   # point-to-point
    angle, displacement = recovery_errors(result.transform, scan_pair)
    assert angle < 0.5 and displacement < 0.005, (angle, displacement)
    for bad in (0.0, -5.0, 91.0, float("nan")):
        with pytest.raises(InputError, match="normal_angle"):
            registration.icp(source, target, normal_angle=bad)
    with pytest.raises(InputError, match="source_normals\\[0\\]"):
        registration.icp(source, target, normal_angle=10.0, source_normals=np.zeros_like(source))
    with pytest.raises(InputError, match="rows"):
        registration.icp(source, target, normal_angle=10.0, source_normals=np.ones((5, 3)))


# ---- several scans --------------------------------------------------------------------------

@pytest.fixture(scope="module")
def views(data_dir):
    """Four partial 'scans' of the shared bunny seen from four sides (datasets.partial_views: 4,000
    samples each, 0.2% noise, each in its own frame 25° and 5% of the diagonal from the first; the
    starts 10° and 2% of the diagonal off the truth)."""
    V, F = io.read_mesh(data_dir / "bunny.off")
    scans, poses, starts, diagonal = datasets.partial_views(V, F)
    return dict(V=V, diagonal=diagonal, scans=scans, poses=poses, starts=starts)


def pose_errors(found, truth, V, diagonal):
    """Per scan: the angle (degrees) of found⁻¹ · truth and the largest displacement of a mesh vertex / diagonal."""
    out = []
    for T, G in zip(found, truth):
        residual = np.linalg.inv(T) @ G
        moved = registration.apply_transform(residual, V)
        out.append((np.degrees(registration.rotation_angle(residual)),
                    np.linalg.norm(moved - V, axis=1).max() / diagonal))
    return np.array(out)


@pytest.mark.parametrize("method", registration.ICP_METHODS)
def test_icp_multi_recovers_known_poses_of_partial_scans(views, method):
    result = registration.icp_multi(views["scans"], method=method, initial=views["starts"], trim=0.6,
                                    max_iterations=100)
    errors = pose_errors(result.transforms, views["poses"], views["V"], views["diagonal"])
    assert np.array_equal(result.transforms[0], np.eye(4))
    assert (errors[:, 0] < 0.5).all() and (errors[:, 1] < 0.005).all(), errors
    assert result.converged and result.scan_converged.all() and 1 <= result.rounds <= 10
    assert result.transforms.shape == (4, 4, 4) and result.rms.shape == (4,)
    assert (result.rms < 0.01 * views["diagonal"]).all(), result.rms / views["diagonal"]   # noise is 0.2%
    # The start was off by 10°: the sequential pass alone is already close, the rounds do not hurt.
    start_errors = pose_errors(views["starts"], views["poses"], views["V"], views["diagonal"])
    assert (start_errors[1:, 0] > 5).all()


@pytest.mark.parametrize("method", registration.ICP_METHODS)
def test_icp_multi_pose_graph_recovers_known_poses_of_partial_scans(views, method):
    """The pose graph on the four views: the neighbouring views (0-1, 1-2, 2-3, 3-0: a loop) are
    its edges, the opposite ones (0-2, 1-3: they overlap only at the silhouette) are not, and the
    global solve puts every pose within the bounds. (Here the growing model, which registers each
    scan onto the union of all the others, is more accurate: the benchmark prints both.)"""
    options = dict(method=method, initial=views["starts"], trim=0.6, max_iterations=100)
    graph = registration.icp_multi(views["scans"], strategy="pose_graph", **options)
    errors = pose_errors(graph.transforms, views["poses"], views["V"], views["diagonal"])
    assert np.array_equal(graph.transforms[0], np.eye(4))
    assert (errors[:, 0] < 0.5).all() and (errors[:, 1] < 0.005).all(), errors
    assert graph.converged and graph.scan_converged.all() and 1 <= graph.rounds <= 10
    edges = set(map(tuple, graph.edges.tolist()))
    assert edges == {(0, 1), (1, 2), (2, 3), (0, 3)}, edges
    assert graph.edges.dtype == np.int64 and graph.edges.shape[1] == 2
    assert (graph.rms < 0.01 * views["diagonal"]).all(), graph.rms / views["diagonal"]
    # The start poses were 10° off: the spanning tree of pairwise results and the refinement fix that.
    assert (pose_errors(views["starts"], views["poses"], views["V"], views["diagonal"])[1:, 0] > 5).all()
    assert registration.icp_multi(views["scans"], **options).edges.shape == (0, 2)   # growing: no graph


def test_icp_multi_pose_graph_reports_a_disconnected_scan(views):
    """A scan out of every other's reach (10 diagonals away, pairs limited to 10% of the
    diagonal) gets no edge: it keeps its start pose and is reported, never silently placed."""
    far = views["scans"][1] + 10 * views["diagonal"]
    starts = views["starts"]
    result = registration.icp_multi([views["scans"][0], views["scans"][1], far], strategy="pose_graph",
                                    initial=np.array([starts[0], starts[1], np.eye(4)]), trim=0.6, max_iterations=30,
                                    max_distance=0.1 * views["diagonal"])
    assert not result.converged and not result.scan_converged[2] and result.scan_converged[:2].all()
    assert np.array_equal(result.transforms[2], np.eye(4))
    assert set(map(tuple, result.edges.tolist())) == {(0, 1)}
    with pytest.raises(InputError, match="strategy"):
        registration.icp_multi(views["scans"][:2], strategy="graph")
    with pytest.raises(InputError, match="min_overlap"):
        registration.icp_multi(views["scans"][:2], strategy="pose_graph", min_overlap=0.0)
    with pytest.raises(InputError, match="overlap_distance"):
        registration.icp_multi(views["scans"][:2], strategy="pose_graph", overlap_distance=0.0)
    with pytest.raises(InputError, match="rounds"):
        registration.icp_multi(views["scans"][:2], strategy="pose_graph", rounds=0)


def test_icp_multi_is_deterministic_and_reduces_once(views):
    runs = [registration.icp_multi(views["scans"], initial=views["starts"], voxel_size=0.01 * views["diagonal"],
                                   threads=threads) for threads in (1, None)]
    assert np.array_equal(runs[0].transforms, runs[1].transforms) and np.array_equal(runs[0].rms, runs[1].rms)
    errors = pose_errors(runs[0].transforms, views["poses"], views["V"], views["diagonal"])
    assert (errors[:, 0] < 0.5).all() and (errors[:, 1] < 0.005).all(), errors


def test_icp_multi_bunny_scans_as_stanford_aligned_them(data_dir):
    """bun000 and bun045 into bun000's frame: the second transform is Stanford's bun.conf pose."""
    scans = [io.read_points(data_dir / name)[0] for name in ("bun000.ply", "bun045.ply")]
    truth = np.eye(4)
    truth[:3, :3] = Rotation.from_quat([0.00548449, -0.294635, -0.0038555, 0.955586]).as_matrix().T
    truth[:3, 3] = [-0.0520211, -0.000383981, -0.0109223]
    for strategy in ("growing", "pose_graph"):
        result = registration.icp_multi(scans, trim=0.8, max_iterations=100, strategy=strategy)
        assert result.converged, strategy
        assert np.array_equal(result.transforms[0], np.eye(4))
        assert np.degrees(registration.rotation_angle(np.linalg.inv(truth) @ result.transforms[1])) < 0.2
        displacement = np.linalg.norm(registration.apply_transform(result.transforms[1], scans[1])
                                      - registration.apply_transform(truth, scans[1]), axis=1).max()
        assert displacement < 0.001 * 0.2474 * 2
        assert (result.rms < 0.0005).all(), result.rms


def test_icp_multi_reports_non_convergence_and_rejects_bad_input(views):
    scans = views["scans"][:2]
    result = registration.icp_multi(scans, initial=views["starts"][:2], max_iterations=1, rounds=0)
    assert not result.converged and not result.scan_converged[1] and result.rounds == 0
    with pytest.raises(InputError, match="at least 2"):
        registration.icp_multi(scans[:1])
    with pytest.raises(InputError, match="initial has 3 transforms for 2 scans"):
        registration.icp_multi(scans, initial=views["starts"][:3])
    with pytest.raises(InputError, match="scans\\[1\\]"):
        registration.icp_multi([scans[0], np.full((5, 3), np.nan)])
    with pytest.raises(InputError, match="scans\\[0\\] has 1 point"):
        registration.icp_multi([scans[0], scans[1]], voxel_size=10 * views["diagonal"])
    with pytest.raises(InputError, match="rounds"):
        registration.icp_multi(scans, rounds=-1)
    with pytest.raises(InputError, match="scan 1: max_distance"):
        registration.icp_multi(scans, max_distance=1e-9)
    with pytest.raises(InputError, match="voxel_size"):
        registration.icp_multi(scans, voxel_size=0.0)


# ---- command line ---------------------------------------------------------------------------

def test_register_command_writes_the_transform_and_the_moved_source(tmp_path, capsys):
    from meshsmith import cli
    V, F = datasets.icosphere(3)
    V = V * [1.0, 0.7, 0.4]                          # no rotational symmetry
    truth = random_motion(np.random.default_rng(11), 15.0, 0.1)
    io.write_mesh(tmp_path / "source.off", V, F)
    io.write_points(tmp_path / "target.xyz", registration.apply_transform(truth, V))
    status = cli.main(["register", str(tmp_path / "source.off"), str(tmp_path / "target.xyz"), "-o",
                       str(tmp_path / "T.txt"), "--method", "point_to_plane", "--apply", str(tmp_path / "moved.obj")])
    out = capsys.readouterr().out
    assert status == 0 and "converged" in out and "NOT" not in out
    T = np.loadtxt(tmp_path / "T.txt")
    assert np.abs(T - truth).max() < 1e-8
    moved, faces = io.read_mesh(tmp_path / "moved.obj")
    assert np.array_equal(faces, F) and np.abs(moved - registration.apply_transform(truth, V)).max() < 1e-5


def test_register_command_reports_bad_input_in_one_line(tmp_path, capsys):
    from meshsmith import cli
    P = RNG.normal(size=(50, 3))
    io.write_points(tmp_path / "a.xyz", P)
    assert cli.main(["register", str(tmp_path / "a.xyz"), str(tmp_path / "a.xyz"), "-o", str(tmp_path / "T.npy")]) == 2
    assert cli.main(["register", str(tmp_path / "a.xyz"), str(tmp_path / "a.xyz"), "-o", str(tmp_path / "T.txt"),
                     "--max-distance", "1e-12", "--initial", str(tmp_path / "missing.txt")]) == 1
    err = capsys.readouterr().err
    assert err.count("meshsmith: error:") == 2 and "Traceback" not in err


def test_demo_stage_aligns_the_scan_to_noise_level(tmp_path):
    from meshsmith.demo import DemoContext, stage_registration
    V, F = datasets.torus(major_radius=1.0, minor_radius=0.4, n_major=48, n_minor=24)
    section = stage_registration(DemoContext(tmp_path, "torus", V, F))
    figures = section.table
    before = figures["mean distance of the scan to the surface / diagonal, before"]
    after = figures["mean distance of the scan to the surface / diagonal, after (noise: 0.004)"]
    assert before > 0.02 and after < 0.005, (before, after)
    assert all((tmp_path / name).stat().st_size > 1000 for name, _ in section.images)
