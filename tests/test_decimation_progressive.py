"""decimation.progressive_mesh (§4.3): every level a valid manifold mesh, the full level the input
bit for bit, incremental level switching equal to fresh extraction, the file format (round trip,
every corruption rejected), and selective refinement (manifold, refined only where asked)."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, decimation, topology


def canonical_faces(F):
    """Faces rotated to start at their smallest index, rows sorted: equality up to order/rotation."""
    F = np.asarray(F)
    shift = np.argmin(F, axis=1)
    rotated = np.stack([F[np.arange(len(F)), (shift + k) % 3] for k in range(3)], axis=1)
    return rotated[np.lexsort(rotated.T[::-1])]


def assert_valid(V, F, chi=None, n_boundary_loops=None):
    assert np.isfinite(V).all()
    assert F.min() >= 0 and F.max() < len(V)
    assert ((F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2])).all()
    assert topology.is_manifold(F) and topology.is_oriented(F)
    if chi is not None:
        assert topology.euler_characteristic(F) == chi
    if n_boundary_loops is not None:
        assert len(topology.boundary_loops(F)) == n_boundary_loops


@pytest.fixture(scope="module")
def sphere_pm():
    V, F = datasets.noisy(*datasets.icosphere(2), sigma=0.02, seed=1)
    return V, F, decimation.progressive_mesh(V, F)


# ---------------------------------------------------------------- levels

def test_every_level_of_a_small_mesh_is_valid(sphere_pm):
    V, F, pm = sphere_pm
    low, high = pm.face_range
    assert high == len(F) and low < 0.1 * len(F)
    for level in range(pm.n_splits + 1):
        pm.set_level(level)
        Vl, Fl = pm.mesh()
        assert len(Fl) == pm.face_count(level) == pm.n_faces
        assert len(Vl) == len(V) - (pm.n_splits - level)
        assert_valid(Vl, Fl, chi=2)


def test_at_every_face_count(sphere_pm):
    V, F, pm = sphere_pm
    low, high = pm.face_range
    for n in range(low, high + 1):
        Vl, Fl = pm.at(n)
        assert len(Fl) <= n
        assert pm.level == pm.n_splits or pm.face_count(pm.level + 1) > n, "the finest level within n"
    with pytest.raises(meshsmith.InputError, match="outside"):
        pm.at(low - 1)
    with pytest.raises(meshsmith.InputError, match="outside"):
        pm.at(high + 1)


def test_full_level_reproduces_the_input_exactly(sphere_pm):
    V, F, pm = sphere_pm
    pm.set_level(0)
    pm.set_level(pm.n_splits)
    Vf, Ff = pm.mesh()
    assert Vf.dtype == np.float64 and Ff.dtype == np.int64
    np.testing.assert_array_equal(Vf, V)          # bit-identical, input order
    np.testing.assert_array_equal(canonical_faces(Ff), canonical_faces(F))


def test_incremental_switching_equals_fresh_extraction(sphere_pm):
    V, F, pm = sphere_pm
    fresh = decimation.progressive_mesh(V, F)
    rng = np.random.default_rng(0)
    for level in rng.integers(0, pm.n_splits + 1, size=25):
        pm.set_level(int(level))
        got = pm.mesh()
        fresh.set_level(fresh.n_splits)            # always from the full level
        fresh.set_level(int(level))
        expected = fresh.mesh()
        np.testing.assert_array_equal(got[0], expected[0])
        np.testing.assert_array_equal(got[1], expected[1])
    pm.set_level(3)
    assert pm.refine(5) == 8 and pm.coarsen(2) == 6
    assert pm.coarsen(100) == 0 and pm.refine(10 ** 6) == pm.n_splits
    with pytest.raises(meshsmith.InputError, match="level"):
        pm.set_level(pm.n_splits + 1)
    with pytest.raises(meshsmith.InputError, match="level"):
        pm.set_level(-1)


@pytest.mark.parametrize("operator", ["edge", "halfedge"])
def test_mesh_with_boundary(operator):
    V, F = datasets.disk(8, 32)
    V = V + 0.05 * np.column_stack([np.zeros(len(V)), np.zeros(len(V)), np.sin(5 * V[:, 0])])
    pm = decimation.progressive_mesh(V, F, operator=operator)
    for level in np.linspace(0, pm.n_splits, 12).astype(int):
        pm.set_level(int(level))
        Vl, Fl = pm.mesh()
        assert_valid(Vl, Fl, chi=1, n_boundary_loops=1)
        if operator == "halfedge":   # half-edge collapses never move a vertex
            assert np.isin(Vl.view([("", float)] * 3), V.view([("", float)] * 3)).all()
    pm.set_level(pm.n_splits)
    np.testing.assert_array_equal(pm.mesh()[0], V)
    np.testing.assert_array_equal(canonical_faces(pm.mesh()[1]), canonical_faces(F))


def test_stop_rule_gives_the_base_mesh():
    V, F = datasets.torus(1.0, 0.4, 24, 12)
    pm = decimation.progressive_mesh(V, F, target_faces=200)
    assert pm.face_range == (200, len(F))
    pm.set_level(0)
    assert_valid(*pm.mesh(), chi=0)
    Vd, Fd = decimation.decimate(V, F, target_faces=200)
    assert len(Fd) == 200


def test_large_mesh_decimated_in_parallel_parts():
    # 327,680 faces: the collapses come from the parallel phase of decimate (spatial parts in
    # rounds), so this checks that their order is a valid sequence of vertex splits.
    V, F = datasets.icosphere(7)
    V = V * (1 + 0.05 * np.sin(5 * V[:, [0]]) * np.cos(3 * V[:, [1]]))
    pm = decimation.progressive_mesh(V, F)
    for n in (pm.face_range[0], 3000, 30000, 200000):
        assert_valid(*pm.at(n), chi=2)
    pm.set_level(pm.n_splits)
    np.testing.assert_array_equal(pm.mesh()[0], V)
    np.testing.assert_array_equal(canonical_faces(pm.mesh()[1]), canonical_faces(F))


@pytest.mark.parametrize("name", ["bunny.off", "fandisk.obj", "plane_holes.obj", "stanford-bunny.obj",
                                  "camelhead.off", "fertility.off"])
def test_shared_meshes(data_dir, name):
    # with boundaries, holes, unreferenced vertices (stanford-bunny) and genus 4 (fertility)
    V, F = meshsmith.io.read_mesh(data_dir / name)
    chi, loops = topology.euler_characteristic(F), len(topology.boundary_loops(F))
    pm = decimation.progressive_mesh(V, F)
    for n in (pm.face_range[0], len(F) // 100, len(F) // 10, len(F) // 2):
        Vl, Fl = pm.at(max(n, pm.face_range[0]))
        assert_valid(Vl, Fl, chi=chi, n_boundary_loops=loops)
    pm.set_level(pm.n_splits)
    V, F, _ = meshsmith.repair.remove_unreferenced(V, F)   # every level leaves out unreferenced vertices
    np.testing.assert_array_equal(pm.mesh()[0], V)
    np.testing.assert_array_equal(canonical_faces(pm.mesh()[1]), canonical_faces(F))
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    Vs, Fs = pm.refine_where(near=V[F[0, 0]], radius=0.1 * diagonal)
    assert_valid(Vs, Fs, chi=chi, n_boundary_loops=loops)


@pytest.mark.parametrize("name", ["cubes_complex_edge.obj", "cubes_complex_vertex.obj"])
def test_non_manifold_shared_meshes_are_rejected(data_dir, name):
    V, F = meshsmith.io.read_mesh(data_dir / name)
    with pytest.raises(meshsmith.InputError, match="not manifold"):
        decimation.progressive_mesh(V, F)


# ---------------------------------------------------------------- file format

def test_file_round_trip(sphere_pm, tmp_path):
    V, F, pm = sphere_pm
    path = tmp_path / "sphere.pm"
    pm.save(path)
    loaded = decimation.ProgressiveMesh.load(path)
    assert loaded.n_splits == pm.n_splits and loaded.face_range == pm.face_range
    for level in (0, 1, pm.n_splits // 2, pm.n_splits):
        pm.set_level(level)
        loaded.set_level(level)
        for a, b in zip(pm.mesh(), loaded.mesh()):
            np.testing.assert_array_equal(a, b)
    again = tmp_path / "again.pm"
    loaded.save(again)
    assert again.read_bytes() == path.read_bytes()
    # transmission order: header, then the base mesh (its first position) before any split
    data = path.read_bytes()
    assert data[:4] == b"MSPM"
    assert len(data) == 32 + pm.face_range[0] * 12 + (len(V) - pm.n_splits) * 28 + pm.n_splits * 64


def test_corrupt_files_are_rejected(sphere_pm, tmp_path):
    _, _, pm = sphere_pm
    good = tmp_path / "good.pm"
    pm.save(good)
    data = bytearray(good.read_bytes())

    def load(content, name):
        path = tmp_path / name
        path.write_bytes(bytes(content))
        return decimation.ProgressiveMesh.load(path)

    with pytest.raises(meshsmith.InputError, match="truncated"):
        load(data[:-1], "truncated.pm")
    with pytest.raises(meshsmith.InputError, match="truncated"):
        load(data[:10], "header.pm")
    with pytest.raises(meshsmith.InputError, match="trailing"):
        load(data + b"\0", "long.pm")
    with pytest.raises(meshsmith.InputError, match="magic"):
        load(b"PLYX" + data[4:], "magic.pm")
    with pytest.raises(meshsmith.InputError, match="version"):
        load(data[:4] + (99).to_bytes(4, "little") + data[8:], "version.pm")
    with pytest.raises(meshsmith.InputError, match="corrupt progressive mesh header"):
        load(data[:8] + (2 ** 62).to_bytes(8, "little") + data[16:], "count.pm")
    with pytest.raises(meshsmith.InputError, match="bytes"):
        load(data[:16] + (10 ** 6).to_bytes(8, "little") + data[24:], "faces.pm")
    split_start = len(data) - pm.n_splits * 64
    for offset, value, what in [(0, 10 ** 6, "active"), (4, -7, "active"), (12, 10 ** 6, "permutation")]:
        bad = bytearray(data)
        bad[split_start + offset:split_start + offset + 4] = value.to_bytes(4, "little", signed=True)
        with pytest.raises(meshsmith.InputError, match=what):
            load(bad, f"split{offset}.pm")
    bad = bytearray(data)
    bad[split_start + 16:split_start + 24] = np.array([np.nan]).tobytes()
    with pytest.raises(meshsmith.InputError, match="NaN"):
        load(bad, "nan.pm")
    with pytest.raises(meshsmith.InputError, match="cannot open"):
        decimation.ProgressiveMesh.load(tmp_path / "missing.pm")


def test_split_with_wrong_neighbours_is_rejected(sphere_pm, tmp_path):
    _, _, pm = sphere_pm
    good = tmp_path / "good.pm"
    pm.save(good)
    data = bytearray(good.read_bytes())
    split_start = len(data) - pm.n_splits * 64
    # the last split's v_l replaced by a vertex far from v_s: not a neighbour
    last = split_start + (pm.n_splits - 1) * 64
    kept = int.from_bytes(data[last:last + 4], "little", signed=True)
    candidates = [v for v in range(pm.face_range[0] // 2) if v != kept]
    rejected = 0
    for v in candidates[:6]:
        bad = bytearray(data)
        bad[last + 4:last + 8] = v.to_bytes(4, "little", signed=True)
        path = tmp_path / "neighbour.pm"
        path.write_bytes(bytes(bad))
        try:
            decimation.ProgressiveMesh.load(path)
        except meshsmith.InputError as error:
            assert "vertex split" in str(error)
            rejected += 1
    assert rejected >= 1


# ---------------------------------------------------------------- selective refinement

def test_selective_refinement_near_a_point():
    V, F = datasets.icosphere(4)
    pm = decimation.progressive_mesh(V, F)
    point, radius = np.array([0.0, 0.0, 1.0]), 0.4
    Vs, Fs = pm.refine_where(near=point, radius=radius)
    assert_valid(Vs, Fs, chi=2)
    selected = V[np.linalg.norm(V - point, axis=1) <= radius]
    # every selected vertex is there, at its input position
    present = {tuple(v) for v in Vs.tolist()}
    assert all(tuple(v) in present for v in selected.tolist())
    # the faces inside the region are the input's
    inside = lambda W, G: G[np.all(np.linalg.norm(W[G] - point, axis=2) <= 0.8 * radius, axis=1)]  # noqa: E731
    assert len(inside(Vs, Fs)) == len(inside(V, F))
    # refined only where asked: far from the point the mesh stays coarse
    far = lambda W: (np.linalg.norm(W - point, axis=1) > 2 * radius).sum()  # noqa: E731
    assert far(Vs) < 0.05 * far(V)
    assert len(Fs) < 0.15 * len(F)
    assert pm.level == pm.n_splits, "selective refinement leaves the current level alone"


def test_selective_refinement_box_and_predicate_agree():
    V, F = datasets.torus(1.0, 0.35, 60, 24)
    pm = decimation.progressive_mesh(V, F)
    box = ((0.5, -0.5, -1.0), (2.0, 0.5, 1.0))
    Vb, Fb = pm.refine_where(box=box)
    Vp, Fp = pm.refine_where(lambda P: (P[:, 0] >= 0.5) & (np.abs(P[:, 1]) <= 0.5))
    np.testing.assert_array_equal(Vb, Vp)
    np.testing.assert_array_equal(Fb, Fp)
    assert_valid(Vb, Fb, chi=0)
    in_box = np.all((V >= box[0]) & (V <= box[1]), axis=1)
    present = {tuple(v) for v in Vb.tolist()}
    assert all(tuple(v) in present for v in V[in_box].tolist())
    assert len(Fb) < 0.45 * len(F)
    far = lambda W: (W[:, 0] < -0.3).sum()  # noqa: E731  (the opposite side of the ring)
    assert far(Vb) < 0.1 * far(V)
    # whole stars: also valid, with every selected vertex, and refined at least as much
    Vw, Fw = pm.refine_where(box=box, whole_stars=True)
    assert_valid(Vw, Fw, chi=0)
    present = {tuple(v) for v in Vw.tolist()}
    assert all(tuple(v) in present for v in V[in_box].tolist())
    assert len(Fb) < len(Fw) < len(F)
    # nothing selected: the base mesh; everything: the full mesh
    pm.set_level(0)
    V0, F0 = pm.refine_where(lambda P: np.zeros(len(P), bool))
    np.testing.assert_array_equal(V0, pm.mesh()[0])
    Vall, Fall = pm.refine_where(lambda P: np.ones(len(P), bool))
    np.testing.assert_array_equal(Vall, V)
    np.testing.assert_array_equal(canonical_faces(Fall), canonical_faces(F))


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("operator", ["edge", "halfedge"])
@pytest.mark.parametrize("whole_stars", [False, True])
def test_selective_refinement_of_random_regions_is_manifold(seed, operator, whole_stars):
    V, F = datasets.disk(10, 40)
    V = V + 0.03 * np.column_stack([np.zeros((len(V), 2)), np.random.default_rng(seed).standard_normal(len(V))])
    pm = decimation.progressive_mesh(V, F, operator=operator)
    rng = np.random.default_rng(seed)
    for fraction in (0.01, 0.05, 0.2):
        chosen = rng.random(len(V)) < fraction
        Vs, Fs = pm.refine_where(lambda P: chosen, whole_stars=whole_stars)
        assert_valid(Vs, Fs, chi=1, n_boundary_loops=1)
        present = {tuple(v) for v in Vs.tolist()}
        assert all(tuple(v) in present for v in V[chosen].tolist())


# ---------------------------------------------------------------- bad input

def test_bad_input(sphere_pm):
    V, F, pm = sphere_pm
    with pytest.raises(meshsmith.InputError, match="exactly one"):
        pm.refine_where()
    with pytest.raises(meshsmith.InputError, match="exactly one"):
        pm.refine_where(near=(0, 0, 1))
    with pytest.raises(meshsmith.InputError, match="bool"):
        pm.refine_where(lambda P: P[:, 0])
    with pytest.raises(meshsmith.InputError, match="box"):
        pm.refine_where(box=(0, 1))
    with pytest.raises(meshsmith.InputError, match="integer"):
        pm.at(10.5)
    Fd = F.copy()
    Fd[5] = [Fd[5, 0], Fd[5, 0], Fd[5, 1]]
    with pytest.raises(meshsmith.InputError, match="face 5 repeats"):
        decimation.progressive_mesh(V, Fd)
    # two tetrahedra sharing a vertex: a non-manifold (pinched) vertex
    T = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    Vn = np.vstack([np.eye(3), np.zeros(3), -np.eye(3)])
    Fn = np.vstack([T, np.array([4, 5, 6, 3])[T]])
    assert not topology.is_manifold(Fn)
    with pytest.raises(meshsmith.InputError, match="manifold"):
        decimation.progressive_mesh(Vn, Fn)
    with pytest.raises(meshsmith.InputError, match="set by progressive_mesh"):
        decimation.progressive_mesh(V, F, record_collapses=False)
