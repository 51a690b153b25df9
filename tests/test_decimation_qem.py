"""Incremental QEM decimation (§4.2): stop rules, invariants (link condition, no flips, boundary,
Euler characteristic), robustness on defective input, collapse records, progress, and quality
against libigl's qslim and fast_simplification (symmetric sampled Hausdorff / bbox diagonal)."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, decimation, geometry, io, topology


def relative_hausdorff(V, F, V2, F2):
    diagonal = np.linalg.norm(V.max(0) - V.min(0))
    return geometry.hausdorff_distance(V, F, V2, F2, sampled=True, samples_per_face=4) / diagonal


def face_normals(V, F):
    return np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])


def bumpy_sphere(subdivisions=4):
    V, F = datasets.icosphere(subdivisions)
    return V * (1 + 0.05 * np.sin(5 * V[:, [0]]) * np.cos(3 * V[:, [1]])), F


@pytest.fixture(scope="module")
def armadillo(data_dir):
    return io.read_mesh(data_dir / "armadillo.obj")


# --- stop rules and invariants -----------------------------------------------------------------

@pytest.mark.parametrize("operator", ["edge", "halfedge"])
def test_target_reached_manifold_oriented_same_euler(armadillo, operator):
    V, F = armadillo
    target = len(F) // 10
    V2, F2, report = decimation.decimate(V, F, target_faces=target, operator=operator, return_report=True)
    assert target - 2 <= len(F2) <= target and report.target_reached
    assert topology.is_manifold(F2) and topology.is_oriented(F2)
    assert topology.euler_characteristic(F2) == topology.euler_characteristic(F) == 2
    assert len(V2) == len(np.unique(F2)) == len(report.vertex_origin)
    assert report.collapse_count == len(V) - len(V2)
    if operator == "halfedge":  # vertices never move: each output vertex is its input vertex
        np.testing.assert_array_equal(V2, V[report.vertex_origin])
    assert relative_hausdorff(V, F, V2, F2) < 0.01


def test_ratio_matches_target_faces(armadillo):
    V, F = armadillo
    by_ratio = decimation.decimate(V, F, ratio=0.05)
    by_target = decimation.decimate(V, F, target_faces=int(round(0.05 * len(F))))
    np.testing.assert_array_equal(by_ratio[1], by_target[1])


def test_max_error_stops_before_the_bound():
    V, F = bumpy_sphere(4)
    bound = 1e-6
    V2, F2, report = decimation.decimate(V, F, max_error=bound, return_report=True)
    assert 0 < report.collapse_count and len(F2) < len(F)
    assert report.max_error <= bound and not report.target_reached
    # A looser bound removes more.
    _, F3, report3 = decimation.decimate(V, F, max_error=100 * bound, return_report=True)
    assert len(F3) < len(F2) and report3.max_error > bound


def test_no_flipped_faces_on_a_sphere():
    V, F = bumpy_sphere(5)
    for ratio in (0.1, 0.01):
        V2, F2 = decimation.decimate(V, F, ratio=ratio)
        centroids = V2[F2].mean(axis=1)
        assert np.all(np.einsum("ij,ij->i", face_normals(V2, F2), centroids) > 0)


def test_flip_prevention_against_the_input_normals(armadillo):
    igl = pytest.importorskip("igl")
    V, F = armadillo
    V2, F2 = decimation.decimate(V, F, ratio=0.1)
    # Each output face agrees with the input face nearest to its centroid (tiny slivers aside).
    _, nearest, _ = igl.point_mesh_squared_distance(V2[F2].mean(axis=1), V, F.astype(np.int64))
    agree = np.einsum("ij,ij->i", face_normals(V2, F2), face_normals(V, F)[nearest]) > 0
    assert agree.mean() > 0.99


def test_boundary_is_kept(data_dir):
    V, F = io.read_mesh(data_dir / "plane_holes.obj")
    loops = topology.boundary_loops(F)
    boundary = np.unique(np.concatenate(loops))
    V2, F2, report = decimation.decimate(V, F, ratio=0.1, operator="halfedge", return_report=True)
    loops2 = topology.boundary_loops(F2)
    assert len(loops2) == len(loops)
    assert topology.euler_characteristic(F2) == topology.euler_characteristic(F)
    # Half-edge collapses along the boundary: every output boundary vertex is an input boundary
    # vertex, and the interior never reaches the boundary.
    assert np.isin(report.vertex_origin[np.concatenate(loops2)], boundary).all()
    # With the edge operator the boundary vertices slide only along the boundary planes.
    V3, F3 = decimation.decimate(V, F, ratio=0.1)
    assert len(topology.boundary_loops(F3)) == len(loops)
    b3 = np.unique(np.concatenate(topology.boundary_loops(F3)))
    edges = np.concatenate([np.stack([loop, np.roll(loop, -1)], 1) for loop in loops])
    d = _distance_to_segments(V3[b3], V[edges[:, 0]], V[edges[:, 1]])
    assert d.max() < 1e-3 * np.linalg.norm(V.max(0) - V.min(0))


def _distance_to_segments(P, A, B):
    AB = B - A
    t = np.clip(np.einsum("pij,ij->pi", P[:, None, :] - A[None], AB) / np.einsum("ij,ij->i", AB, AB), 0, 1)
    closest = A[None] + t[..., None] * AB[None]
    return np.linalg.norm(P[:, None, :] - closest, axis=2).min(axis=1)


def test_keep_boundary_off_may_move_the_boundary(data_dir):
    V, F = io.read_mesh(data_dir / "plane_holes.obj")
    V2, F2 = decimation.decimate(V, F, ratio=0.05, keep_boundary=False)
    assert topology.is_manifold(F2) and len(F2) <= int(round(0.05 * len(F)))


def test_closed_mesh_stops_at_a_tetrahedron():
    V, F = datasets.icosphere(2)
    V2, F2, report = decimation.decimate(V, F, target_faces=1, return_report=True)
    assert len(F2) == 4 and len(V2) == 4 and not report.target_reached
    assert topology.is_manifold(F2) and topology.euler_characteristic(F2) == 2


# --- options ----------------------------------------------------------------------------------

@pytest.mark.parametrize("cost", ["quadric", "plane_distance", "volume_change"])
@pytest.mark.parametrize("candidates", [None, 8])
def test_costs_and_multiple_choice_give_valid_meshes(cost, candidates):
    V, F = bumpy_sphere(4)
    V2, F2 = decimation.decimate(V, F, ratio=0.1, cost=cost, candidates=candidates, seed=3)
    assert len(F2) <= int(round(0.1 * len(F))) and topology.is_manifold(F2)
    assert topology.euler_characteristic(F2) == 2
    assert relative_hausdorff(V, F, V2, F2) < 0.05


def test_multiple_choice_close_to_the_full_queue(armadillo):
    V, F = armadillo
    full = relative_hausdorff(V, F, *decimation.decimate(V, F, ratio=0.1))
    mc = relative_hausdorff(V, F, *decimation.decimate(V, F, ratio=0.1, candidates=8, seed=1))
    assert mc < 2 * full
    again = decimation.decimate(V, F, ratio=0.1, candidates=8, seed=1)
    np.testing.assert_array_equal(again[1], decimation.decimate(V, F, ratio=0.1, candidates=8, seed=1)[1])


def test_max_valence_and_quality_criteria():
    V, F = bumpy_sphere(4)
    _, F2 = decimation.decimate(V, F, ratio=0.1, max_valence=8)
    assert np.bincount(topology.edges(F2).ravel()).max() <= 8
    V3, F3 = decimation.decimate(V, F, ratio=0.1, min_quality=0.4)
    V4, F4 = decimation.decimate(V, F, ratio=0.1)

    def quality(V, F):
        e = sum(np.sum((V[F[:, i]] - V[F[:, (i + 1) % 3]]) ** 2, axis=1) for i in range(3))
        return 2 * np.sqrt(3) * np.linalg.norm(face_normals(V, F), axis=1) / e
    assert quality(V3, F3).min() >= min(0.4, quality(V, F).min()) - 1e-9
    assert quality(V3, F3).min() > quality(V4, F4).min()


def test_max_normal_deviation_limits_each_turn():
    V, F = bumpy_sphere(4)
    _, F_free, free = decimation.decimate(V, F, target_faces=40, return_report=True)
    _, F_tight, tight = decimation.decimate(V, F, target_faces=40, max_normal_deviation=2,
                                            return_report=True)
    assert free.target_reached and len(F_free) <= 40
    assert not tight.target_reached and len(F_tight) > 40
    assert topology.is_manifold(F_tight)


# --- collapse records (the vertex splits of §4.3) ---------------------------------------------

def test_collapse_records_replay_to_the_output():
    V, F = bumpy_sphere(3)
    V2, F2, report = decimation.decimate(V, F, ratio=0.1, record_collapses=True, return_report=True)
    c = report.collapses
    assert len(c["removed"]) == report.collapse_count
    positions = V.copy()
    faces = {tuple(np.roll(f, -np.argmin(f))) for f in F.tolist()}

    def canonical(face):
        k = face.index(min(face))
        return tuple(face[k:] + face[:k])
    for i in range(report.collapse_count):
        a, b, left, right = (int(c[key][i]) for key in ("removed", "kept", "left", "right"))
        np.testing.assert_array_equal(positions[a], c["removed_position"][i])
        np.testing.assert_array_equal(positions[b], c["kept_position_before"][i])
        # Orientation convention of CollapseRecord: (removed, kept, left) and (kept, removed, right).
        if left >= 0:
            assert canonical([a, b, left]) in faces
        if right >= 0:
            assert canonical([b, a, right]) in faces
        faces = {canonical([b if v == a else v for v in f]) for f in faces}
        faces = {f for f in faces if len(set(f)) == 3}
        positions[b] = c["kept_position_after"][i]
    origin = report.vertex_origin
    assert faces == {canonical(origin[f].tolist()) for f in F2}
    np.testing.assert_array_equal(V2, positions[origin])


# --- the parallel phase (meshes of 100,000 faces or more) --------------------------------------

@pytest.fixture(scope="module")
def large_sphere():
    return bumpy_sphere(7)  # 327,680 faces


@pytest.mark.parametrize("ratio", [0.1, 0.01])
def test_parallel_phase_keeps_the_invariants_and_the_quality(large_sphere, ratio):
    V, F = large_sphere
    distances = {}
    for parallel in (True, False):
        V2, F2, report = decimation.decimate(V, F, ratio=ratio, parallel=parallel, return_report=True)
        target = round(ratio * len(F))
        assert target - 2 <= len(F2) <= target and report.target_reached
        assert topology.is_manifold(F2) and topology.is_oriented(F2)
        assert topology.euler_characteristic(F2) == 2
        assert report.collapse_count == len(V) - len(V2)
        # No face turned over: each output face agrees with the input normal at its corners.
        normals = geometry.vertex_normals(V, F)[report.vertex_origin]
        assert (np.einsum("ij,ij->i", face_normals(V2, F2), normals[F2].sum(axis=1)) > 0).all()
        distances[parallel] = relative_hausdorff(V, F, V2, F2)
    # Measured: equal at 10%, +6% at 1%; on five upsampled shared meshes the geometric mean of
    # parallel / serial is 0.98 (the Hausdorff distance of one greedy run moves by up to 19% when
    # the input moves by 1e-7).
    assert distances[True] <= 1.15 * distances[False], distances


@pytest.mark.parametrize("operator", ["edge", "halfedge"])
def test_parallel_phase_keeps_the_boundary_and_the_error_bound(operator):
    # A 198,000-face disk with a bumpy height field, stopped by max_error alone.
    V, F = datasets.disk(n_rings=180, n_segments=1100)
    V = V.copy()
    V[:, 2] = 0.1 * np.sin(4 * V[:, 0]) * np.cos(3 * V[:, 1])
    loop = topology.boundary_loops(F)[0]
    for parallel in (True, False):
        V2, F2, report = decimation.decimate(V, F, max_error=1e-4, operator=operator, parallel=parallel,
                                             return_report=True)
        assert 0 < report.max_error <= 1e-4 and len(F2) < len(F) // 5
        assert topology.is_manifold(F2) and topology.euler_characteristic(F2) == 1
        loops2 = topology.boundary_loops(F2)
        assert len(loops2) == 1
        if operator == "halfedge":
            assert np.isin(report.vertex_origin[loops2[0]], loop).all()
        else:  # boundary vertices stay on the boundary circle (radius 1)
            assert np.abs(np.linalg.norm(V2[loops2[0], :2], axis=1) - 1).max() < 1e-3


def test_parallel_result_does_not_depend_on_the_thread_count(large_sphere):
    import subprocess
    import sys
    V, F = large_sphere
    V2, F2 = decimation.decimate(V, F, ratio=0.05)
    digest = f"{V2.sum():.17g} {F2.sum()} {len(F2)}"
    one_core = subprocess.run([sys.executable, "-c", (
        "import os; os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})\n"
        "import numpy as np\n"
        "from meshsmith import datasets, decimation\n"
        "V, F = datasets.icosphere(7)\n"
        "V = V * (1 + 0.05 * np.sin(5 * V[:, [0]]) * np.cos(3 * V[:, [1]]))\n"
        "V2, F2 = decimation.decimate(V, F, ratio=0.05)\n"
        "print(f'{V2.sum():.17g} {F2.sum()} {len(F2)}')")], capture_output=True, text=True, check=True)
    assert one_core.stdout.strip() == digest


def test_parallel_collapse_records_replay_to_the_output(large_sphere):
    # The parts' collapses are recorded round by round; replayed in that order they must give
    # the output (checked per collapse on positions and the faces that die).
    V, F = large_sphere
    V2, F2, report = decimation.decimate(V, F, ratio=0.1, record_collapses=True, return_report=True)
    c = report.collapses
    positions = [tuple(p) for p in V.tolist()]
    alive = [True] * len(V)
    for a, b, p_removed, p_before, p_after in zip(
            c["removed"].tolist(), c["kept"].tolist(), c["removed_position"].tolist(),
            c["kept_position_before"].tolist(), c["kept_position_after"].tolist()):
        assert alive[a] and alive[b]
        assert positions[a] == tuple(p_removed) and positions[b] == tuple(p_before)
        alive[a] = False
        positions[b] = tuple(p_after)
    np.testing.assert_array_equal(np.flatnonzero(alive), np.sort(report.vertex_origin))
    np.testing.assert_array_equal(V2, np.array(positions)[report.vertex_origin])


# --- robustness -------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["cubes_complex_edge.obj", "cubes_complex_vertex.obj"])
def test_non_manifold_input_is_split_not_torn(data_dir, name):
    V, F = io.read_mesh(data_dir / name)
    assert not topology.is_manifold(F)
    V2, F2, report = decimation.decimate(V, F, target_faces=8, return_report=True)
    assert len(report.split_vertex_origin) > len(V)
    assert topology.is_manifold(F2) and len(F2) >= 8
    assert np.isfinite(V2).all()
    assert (V2 >= V.min(0) - 1e-9).all() and (V2 <= V.max(0) + 1e-9).all()


def test_large_pinched_input_is_split_by_the_parallel_build():
    # Two spheres pinched at one vertex, large enough (164k faces) for the chunked, parallel
    # half-edge build and the parallel phase: the pinch becomes one vertex per sphere, nothing
    # else is split, and both spheres stay closed surfaces.
    V, F = bumpy_sphere(6)
    n = len(V)
    top, bottom = int(np.argmax(V[:, 2])), int(np.argmin(V[:, 2]))
    F_upper = F + n
    F_upper[F_upper == bottom + n] = top  # the upper sphere's bottom is the lower one's top
    V_all, F_all = np.vstack([V, V + (V[top] - V[bottom])]), np.vstack([F, F_upper])
    assert not topology.is_manifold(F_all)
    V2, F2, report = decimation.decimate(V_all, F_all, ratio=0.1, return_report=True)
    assert len(report.split_vertex_origin) == len(V_all) + 1 and report.split_vertex_origin[-1] == top
    assert len(F2) == int(round(0.1 * len(F_all)))
    assert topology.is_manifold(F2) and topology.connected_components(F2).count == 2
    assert len(np.unique(F2)) - len(topology.edges(F2)) + len(F2) == 4  # χ = 2 per sphere


def test_defects_zero_area_duplicates_components_and_holes(data_dir):
    V, F = bumpy_sphere(3)
    n = len(V)
    # A second component, a duplicated vertex (same position, its own index), a zero-area face
    # and a face with a repeated index.
    V = np.vstack([V, V + [3, 0, 0], V[:1]])
    F = np.vstack([F, F + n, [[F[0, 0], F[0, 1], 2 * n]], [[0, 0, 1]]])
    V[2 * n] = V[F[0, 0]]
    V2, F2 = decimation.decimate(V, F, ratio=0.1)
    assert len(F2) <= int(round(0.1 * len(F))) + 2
    # The zero-area face sits on a sphere edge that thereby has three faces: the split detaches it,
    # a lone triangle that cannot be decimated further, beside the two spheres.
    assert topology.connected_components(F2).count == 3
    assert topology.is_manifold(F2) and np.isfinite(V2).all()
    Vb, Fb = io.read_mesh(data_dir / "stanford-bunny.obj")
    Vb2, Fb2 = decimation.decimate(Vb, Fb, ratio=0.05)
    assert len(topology.boundary_loops(Fb2)) == len(topology.boundary_loops(Fb))
    assert topology.is_manifold(Fb2)


def test_impossible_requests_raise():
    V, F = datasets.icosphere(1)
    with pytest.raises(meshsmith.InputError, match="stop rule"):
        decimation.decimate(V, F)
    with pytest.raises(meshsmith.InputError, match="target_faces"):
        decimation.decimate(V, F, target_faces=0)
    with pytest.raises(meshsmith.InputError, match="ratio"):
        decimation.decimate(V, F, ratio=1.5)
    with pytest.raises(meshsmith.InputError, match="not both"):
        decimation.decimate(V, F, ratio=0.5, target_faces=10)
    with pytest.raises(meshsmith.InputError, match="operator"):
        decimation.decimate(V, F, ratio=0.5, operator="vertex")
    with pytest.raises(meshsmith.InputError, match="cost"):
        decimation.decimate(V, F, ratio=0.5, cost="area")
    with pytest.raises(meshsmith.InputError, match="candidates"):
        decimation.decimate(V, F, ratio=0.5, candidates=0)
    with pytest.raises(meshsmith.InputError, match="max_error"):
        decimation.decimate(V, F, max_error=-1)
    with pytest.raises(meshsmith.InputError):
        decimation.decimate(V, F + 1000, ratio=0.5)
    with pytest.raises(meshsmith.InputError, match="repeated vertex index"):
        decimation.decimate(V, np.array([[0, 1, 1], [2, 2, 3]]), target_faces=1)


def test_progress_and_cancellation():
    V, F = bumpy_sphere(5)
    fractions = []
    decimation.decimate(V, F, ratio=0.1, progress=lambda fraction, stage: fractions.append(fraction))
    assert fractions and fractions[-1] == 1.0 and all(0 <= f <= 1 for f in fractions)
    with pytest.raises(meshsmith.Cancelled):
        decimation.decimate(V, F, ratio=0.1, progress=lambda fraction, stage: fraction < 0.3)


# --- quality against libigl's qslim and fast_simplification ------------------------------------

QUALITY_MESHES = ["armadillo.obj", "pmp-bunny.off", "nefertiti-lowres.obj", "fandisk.obj", "bumpy-cube.obj"]


@pytest.fixture(scope="module")
def quality_table(data_dir):
    """{(mesh, ratio): (meshsmith, qslim, fast_simplification)} relative Hausdorff distances."""
    igl = pytest.importorskip("igl")
    fast_simplification = pytest.importorskip("fast_simplification")
    table = {}
    for name in QUALITY_MESHES:
        V, F = io.read_mesh(data_dir / name)
        for ratio in (0.1, 0.01):
            target = int(round(ratio * len(F)))
            ours = decimation.decimate(V, F, target_faces=target)
            qslim = igl.qslim(V, np.asfortranarray(F, dtype=np.int32), target)[:2]
            fast = fast_simplification.simplify(V, F, target_count=target)
            table[name, ratio] = tuple(relative_hausdorff(V, F, np.asarray(W, float), np.asarray(G))
                                       for W, G in (ours, qslim, fast))
            assert len(ours[1]) <= target and topology.is_manifold(ours[1])
    return table


def test_quality_no_worse_than_qslim_and_fast_simplification(quality_table):
    ratios = []
    for (name, ratio), (ours, qslim, fast) in quality_table.items():
        best_peer = min(qslim, fast)
        ratios.append(ours / best_peer)
        # Per case within 20% of the better peer: the Hausdorff distance is a maximum over the
        # surface, so one unlucky collapse moves it; measured worst case +19% (nefertiti at 1%,
        # where qslim is 0.0073 and fast_simplification 0.0107 of the diagonal).
        assert ours <= 1.2 * best_peer, (name, ratio, ours, qslim, fast)
    # And on the whole at least as good as the better peer of each case (geometric mean).
    assert np.exp(np.mean(np.log(ratios))) <= 1.0
