"""Registration chapter benchmarks: ICP against Open3D and small_gicp, from the same start.

Case 1 and 2: the raw Stanford scans bun045 → bun000 (40,097 and 40,256 points; shared data)
from a 45° start, pairs farther apart than `MAX_DISTANCE` rejected (Open3D's
max_correspondence_distance, small_gicp's too). The start (issue 16: "from a 45° start"):
bun045 was scanned with the bunny turned on the turntable; Stanford's bun.conf gives its true
pose, a rotation of 34.28° about (−0.019, 1.000, 0.013) (the turntable's vertical axis) and a
translation. bun045's own frame (the identity) is thus a 34° start; the start used here is the
identity turned back by a further 10.72° about that same axis through the source's centroid,
so that the misalignment ICP must undo is exactly 45° (`start_45`, checked at run time). Every
library starts from that same 4×4 transform. Point-to-plane: each runs until its own
relative-change test says 1e-6 (meshsmith: an update below 1e-6 rad and 1e-6 diagonals, or a
relative change of the inlier RMS and count below 1e-6, or a stall; Open3D: relative fitness and
RMSE 1e-6; small_gicp: its rotation/translation epsilons set to the same), at most 100
iterations; from 45° no library falls into a wrong minimum, all reach bun.conf's pose to about
0.2°. Point-to-point creeps (its steps shrink as it nears the answer), and a relative test stops
the creep at a place that depends on the library's rule (1.83–1.86° short in one run, 3.3–3.4° on
the quick input): for the same accuracy every library runs exactly `P2P_ITERATIONS` iterations
(meshsmith with its stopping tests off), the same work to the same transform.
Point-to-plane times include the target normals (PCA, 16 neighbours) and every kd-tree: each
library does the whole job from raw arrays. Quick mode: both scans reduced first to one point per
2 mm voxel (meshsmith's voxel_downsample, the same input for every library).

Case 3: datasets.scan_pair on the shared bunny.off (4000 noisy points with 1% of the diagonal
Gaussian noise and 1000 outliers, onto 8000 clean samples) under a rotation of 30° and a
translation of 10% of the diagonal: meshsmith's trimmed ICP (trim 0.75) next to Open3D with a
distance limit (it has no trimming).

Case 4: icp_multi on four partial views of bunny.off with known poses, the pose graph against
the growing model (no peer), and on the Stanford pair bun000 + bun045 against bun.conf.

Threads: each library once with all cores and once with one (meshsmith threads=1, Open3D
utility.set_max_threads(1), small_gicp num_threads=1).

Result checks (tolerances): against Stanford's own alignment of the scans (bun.conf), rotation
error and the largest displacement of a source point; meshsmith no worse than Open3D by more than
0.05° / 0.05% of the diagonal; case 3: meshsmith within 0.5° and 0.5% of the diagonal.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, check, optional, shared_data_dir, size  # noqa: E402

from meshsmith import datasets, io, registration  # noqa: E402

o3d = optional("open3d")
small_gicp = optional("small_gicp")

MAX_DISTANCE = 0.02      # 8% of the scans' diagonal (0.25)
MAX_ITERATIONS, TOLERANCE = 100, 1e-6
P2P_ITERATIONS = 100     # point-to-point: this many iterations for every library, no early stop
START_ANGLE = 45.0       # degrees of misalignment at the start


def bun_conf_truth() -> np.ndarray:
    """Stanford's bun.conf line for bun045 (translation, quaternion x y z w; the rotation conjugated:
    the convention that maps bun045 into bun000's frame)."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_quat([0.00548449, -0.294635, -0.0038555, 0.955586]).as_matrix().T
    T[:3, 3] = [-0.0520211, -0.000383981, -0.0109223]
    return T


def errors(T: np.ndarray, truth: np.ndarray, P: np.ndarray, diagonal: float) -> tuple[float, float]:
    """Rotation error (degrees) and largest point displacement / diagonal of T against truth."""
    angle = np.degrees(registration.rotation_angle(np.linalg.inv(truth) @ T))
    moved = np.linalg.norm(registration.apply_transform(T, P) - registration.apply_transform(truth, P), axis=1)
    return float(angle), float(moved.max() / diagonal)


def start_45(truth: np.ndarray, source: np.ndarray) -> np.ndarray:
    """The identity turned back about bun.conf's rotation axis (through the source's centroid)
    by START_ANGLE − 34.28°, so that the rotation from the start to the truth is START_ANGLE."""
    rotvec = Rotation.from_matrix(truth[:3, :3]).as_rotvec()
    angle = float(np.linalg.norm(rotvec))
    back = Rotation.from_rotvec(-(np.radians(START_ANGLE) - angle) * rotvec / angle).as_matrix()
    centre = source.mean(axis=0)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = back, centre - back @ centre
    return T


def open3d_icp(source, target, method, max_distance, threads, start):
    o3d.utility.set_max_threads(threads)
    src = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(source))
    tgt = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(target))
    reg = o3d.pipelines.registration
    if method == "point_to_plane":
        tgt.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(16))
        estimation = reg.TransformationEstimationPointToPlane()
    else:
        estimation = reg.TransformationEstimationPointToPoint()
    if method == "point_to_plane":
        criteria = reg.ICPConvergenceCriteria(relative_fitness=TOLERANCE, relative_rmse=TOLERANCE,
                                              max_iteration=MAX_ITERATIONS)
    else:   # every iteration runs
        criteria = reg.ICPConvergenceCriteria(relative_fitness=0.0, relative_rmse=0.0, max_iteration=P2P_ITERATIONS)
    return reg.registration_icp(src, tgt, max_distance, start, estimation, criteria).transformation


def small_gicp_icp(source, target, kind, max_distance, threads, start, voxel=None):
    if voxel is None:
        tgt, src = small_gicp.PointCloud(target), small_gicp.PointCloud(source)
        tree = small_gicp.KdTree(tgt, num_threads=threads)
        if kind == "PLANE_ICP":
            small_gicp.estimate_normals(tgt, tree, num_neighbors=16, num_threads=threads)
    else:
        tgt, tree = small_gicp.preprocess_points(target, voxel, num_neighbors=16, num_threads=threads)
        src, _ = small_gicp.preprocess_points(source, voxel, num_neighbors=16, num_threads=threads)
    fixed = kind == "ICP"   # point-to-point: every iteration runs
    result = small_gicp.align(tgt, src, tree, start, registration_type=kind, max_correspondence_distance=max_distance,
                              num_threads=threads, max_iterations=P2P_ITERATIONS if fixed else MAX_ITERATIONS,
                              rotation_epsilon=1e-300 if fixed else TOLERANCE,
                              translation_epsilon=1e-300 if fixed else TOLERANCE * 0.25)
    return result.T_target_source


def scan_pair_cases(data: Path) -> None:
    source = io.read_points(data / "bun045.ply")[0]
    target = io.read_points(data / "bun000.ply")[0]
    quick_voxel = size(None, 0.002)
    if quick_voxel is not None:
        source, target = registration.voxel_downsample(source, quick_voxel), registration.voxel_downsample(target, quick_voxel)
    truth = bun_conf_truth()
    start = start_45(truth, source)
    misalignment = np.degrees(registration.rotation_angle(np.linalg.inv(truth) @ start))
    check("registration", "bun045 → bun000 start", "start's misalignment minus 45 (degrees)", abs(misalignment - 45), 1e-9)
    diagonal = float(np.linalg.norm(target.max(0) - target.min(0)))
    for method in registration.ICP_METHODS:
        plane = method == "point_to_plane"
        rule = f"stop at 1e-6, at most {MAX_ITERATIONS} iterations" if plane else f"{P2P_ITERATIONS} iterations each"
        bench = Benchmark("registration", f"ICP {method} bun045 → bun000 ({len(source):,} → {len(target):,} points), "
                          f"{START_ANGLE:.0f}° start, max distance {MAX_DISTANCE}, {rule}", repeats=5)
        options = dict(method=method, max_distance=MAX_DISTANCE, initial=start)
        if plane:
            options.update(max_iterations=MAX_ITERATIONS, tolerance=TOLERANCE)
        else:
            options.update(max_iterations=P2P_ITERATIONS, tolerance=1e-300, relative_rmse=0.0, patience=0)
        for threads, label in ((None, ""), (1, ", 1 thread")):
            bench.time(f"meshsmith{label}", lambda threads=threads: registration.icp(
                source, target, threads=threads, **options).transform)
        if o3d is not None:
            for threads, label in ((0, ""), (1, ", 1 thread")):
                bench.time(f"open3d registration_icp{label}",
                           lambda threads=threads: open3d_icp(source, target, method, MAX_DISTANCE, threads, start))
        kind = "PLANE_ICP" if method == "point_to_plane" else "ICP"
        if small_gicp is not None:
            for threads, label in ((2, ", 2 threads"), (1, ", 1 thread")):
                bench.time(f"small_gicp {kind}{label}",
                           lambda threads=threads: small_gicp_icp(source, target, kind, MAX_DISTANCE, threads, start))
            if method == "point_to_plane":
                bench.time("small_gicp GICP on a 2 mm voxel reduction, 2 threads",
                           lambda: small_gicp_icp(source, target, "GICP", MAX_DISTANCE, 2, start, voxel=0.002),
                           same_work=False)
        bench.report()
        result = registration.icp(source, target, **options)
        print(f"  meshsmith {method}: RMS {result.rms:.4g} over {100 * result.inlier_fraction:.3g}% of the points, "
              f"{result.iterations} iterations, converged {result.converged} ({result.stop}), rotation "
              f"{np.degrees(registration.rotation_angle(result.transform)):.4f}° (bun.conf: "
              f"{np.degrees(registration.rotation_angle(truth)):.4f}°)")
        mine = errors(bench.output("meshsmith"), truth, source, diagonal)
        if plane:   # point-to-point runs a fixed count, with no convergence test
            bench.check(f"meshsmith {method} converged", 0 if result.converged else 1, 0)
            assert result.iterations < MAX_ITERATIONS
        else:
            assert result.iterations == P2P_ITERATIONS
        if plane:
            bound = (0.25, 0.003) if quick_voxel is None else (0.5, 0.005)   # the 2 mm reduction costs accuracy
            bench.check("meshsmith rotation error vs bun.conf (degrees)", mine[0], bound[0])
            bench.check("meshsmith displacement vs bun.conf / diagonal", mine[1], bound[1])
        assert np.array_equal(bench.output("meshsmith"), bench.output("meshsmith, 1 thread")), "thread count changed the result"
        peers = ["open3d registration_icp", f"small_gicp {kind}, 2 threads"]
        if method == "point_to_plane":
            peers.append("small_gicp GICP on a 2 mm voxel reduction, 2 threads")
        for peer in peers:
            try:
                theirs = errors(bench.output(peer), truth, source, diagonal)
            except KeyError:
                continue
            print(f"  {peer}: rotation error {theirs[0]:.4f}°, displacement {100 * theirs[1]:.4f}% of the diagonal "
                  f"(meshsmith {mine[0]:.4f}°, {100 * mine[1]:.4f}%)")
            if peer.startswith("open3d"):
                bench.check("meshsmith rotation error minus Open3D's (degrees)", mine[0] - theirs[0], 0.05)
                bench.check("meshsmith displacement minus Open3D's / diagonal", mine[1] - theirs[1], 0.0005)


def outlier_case(data: Path) -> None:
    V, F = io.read_mesh(data / "bunny.off")
    source, target, normals, motion, _, diagonal = datasets.scan_pair(V, F, seed=3)
    bench = Benchmark("registration", "ICP point_to_plane, bunny.off samples: 30° + 10% diagonal, 1% noise, "
                      "20% outliers (5,000 → 8,000 points); meshsmith trimmed (0.75)", repeats=5)
    bench.time("meshsmith", lambda: registration.icp(source, target, method="point_to_plane", trim=0.75,
                                                                  target_normals=normals, max_iterations=100).transform)
    if o3d is not None:
        bench.time("open3d (max distance 5% of the diagonal)",
                   lambda: open3d_icp(source, target, "point_to_plane", 0.05 * diagonal, 0, np.eye(4)))
    bench.report()

    def recovery(T):
        residual = T @ motion
        moved = registration.apply_transform(residual, V)
        return np.degrees(registration.rotation_angle(residual)), np.linalg.norm(moved - V, axis=1).max() / diagonal

    angle, shift = recovery(bench.output("meshsmith"))
    bench.check("meshsmith rotation error (degrees)", angle, 0.5)
    bench.check("meshsmith largest vertex displacement / diagonal", shift, 0.005)
    if o3d is not None:
        angle, shift = recovery(bench.output("open3d (max distance 5% of the diagonal)"))
        print(f"  open3d: rotation error {angle:.3f}°, displacement {100 * shift:.3f}% of the diagonal")


def multi_scan_case(data: Path) -> None:
    """icp_multi on four partial views of bunny.off (the samples whose normal faces each of four
    horizontal directions, 0.2% noise, each in its own frame 25° and 5% of the diagonal from the
    first; starts 10° and 2% off the truth). No peer runs the same multi-view job (Open3D's pose
    graph needs its pairwise edges set up by hand): figures and checks against the known poses."""
    V, F = io.read_mesh(data / "bunny.off")
    scans, poses, starts, diagonal = datasets.partial_views(V, F)
    bench = Benchmark("registration", "icp_multi, 4 partial views of bunny.off (4,000 points each, 0.2% noise), "
                      "starts 10° off, point_to_plane, trim 0.6: pose graph vs growing model", repeats=5,
                      reference="meshsmith pose_graph")
    for strategy in ("pose_graph", "growing"):
        bench.time(f"meshsmith {strategy}", lambda strategy=strategy: registration.icp_multi(
            scans, initial=starts, trim=0.6, max_iterations=100, strategy=strategy))
    bench.report()
    for strategy in ("pose_graph", "growing"):
        result = bench.output(f"meshsmith {strategy}")
        worst_angle, worst_shift = pose_errors(result.transforms, poses, V, diagonal)
        print(f"  icp_multi {strategy}: {result.rounds} rounds, converged {result.converged}, edges "
              f"{result.edges.tolist()}, worst pose error {worst_angle:.3f}° and {100 * worst_shift:.3f}% of the "
              f"diagonal, RMS / diagonal {np.round(result.rms / diagonal, 5).tolist()}")
        bench.check(f"icp_multi {strategy} worst rotation error (degrees)", worst_angle, 0.5)
        bench.check(f"icp_multi {strategy} worst vertex displacement / diagonal", worst_shift, 0.005)
    # The Stanford pair as two views: bun045's pose against bun.conf's.
    bun = [io.read_points(data / name)[0] for name in ("bun000.ply", "bun045.ply")]
    bun_diagonal = float(np.linalg.norm(bun[0].max(0) - bun[0].min(0)))
    bench = Benchmark("registration", "icp_multi, bun000 + bun045 (identity starts, 34° apart), point_to_plane, "
                      "trim 0.8: pose graph vs growing model", repeats=3,
                      reference="meshsmith pose_graph")
    for strategy in ("pose_graph", "growing"):
        bench.time(f"meshsmith {strategy}", lambda strategy=strategy: registration.icp_multi(
            bun, trim=0.8, max_iterations=100, strategy=strategy))
    bench.report()
    truth = bun_conf_truth()
    for strategy in ("pose_graph", "growing"):
        result = bench.output(f"meshsmith {strategy}")
        angle, shift = errors(result.transforms[1], truth, bun[1], bun_diagonal)
        print(f"  icp_multi {strategy} on the Stanford pair: bun045 pose error {angle:.4f}° and {100 * shift:.4f}% "
              f"of the diagonal vs bun.conf, converged {result.converged}")
        bench.check(f"icp_multi {strategy} bun045 rotation error vs bun.conf (degrees)", angle, 0.2)


def pose_errors(found, truth, V, diagonal) -> tuple[float, float]:
    """The worst angle (degrees) of found⁻¹ · truth over the scans, and the worst displacement of a mesh vertex / diagonal."""
    worst_angle = worst_shift = 0.0
    for T, G in zip(found, truth):
        residual = np.linalg.inv(T) @ G
        worst_angle = max(worst_angle, float(np.degrees(registration.rotation_angle(residual))))
        worst_shift = max(worst_shift, float(np.linalg.norm(registration.apply_transform(residual, V) - V, axis=1).max()
                                             / diagonal))
    return worst_angle, worst_shift


def main() -> None:
    data = shared_data_dir()
    if data is None:
        print("registration: shared data not found (set MESHSMITH_DATA); nothing to measure")
        check("registration", "shared data", "missing shared data (skipped)", 0, 0)
        return
    scan_pair_cases(data)
    outlier_case(data)
    multi_scan_case(data)


if __name__ == "__main__":
    main()
