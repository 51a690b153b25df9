"""decimation.cluster (§4.1): vertex clustering on a uniform grid, checked against a numpy
reference of the same grid, analytic truth for the quadric representative (§4.1.1: planes,
creases and corners), invariants of the output, and bad input."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, decimation, topology


# ---------------------------------------------------------------- numpy reference of the grid

def reference_cells(V, F, cell_size):
    """Cell index (n, 3) of every referenced vertex (others: None) and the grid origin."""
    referenced = np.zeros(len(V), dtype=bool)
    referenced[np.asarray(F).ravel()] = True
    origin = V[referenced].min(axis=0)
    cells = np.floor((V - origin) / cell_size).astype(np.int64)
    return cells, referenced, origin


def reference_groups(V, F, cell_size):
    """{cell tuple: array of its referenced vertices}."""
    cells, referenced, origin = reference_cells(V, F, cell_size)
    groups = {}
    for v in np.flatnonzero(referenced):
        groups.setdefault(tuple(cells[v]), []).append(v)
    return {cell: np.array(members) for cell, members in groups.items()}, cells, origin


def noisy_sphere():
    V, F = datasets.icosphere(3)
    V = V * (1.0 + 0.02 * np.random.default_rng(3).standard_normal((len(V), 1)))
    return V, F


# ---------------------------------------------------------------- representatives vs numpy

@pytest.mark.parametrize("representative", ["center", "centroid", "median"])
def test_representatives_match_numpy_reference(representative):
    V, F = noisy_sphere()
    h = 0.37
    result = decimation.cluster(V, F, cell_size=h, representative=representative)
    groups, cells, origin = reference_groups(V, F, h)
    checked = 0
    for cell, members in groups.items():
        outputs = set(result.vertex_cluster[members].tolist())
        assert len(outputs) == 1, "all vertices of a cell map to one output vertex"
        out = outputs.pop()
        if out < 0:
            continue   # every triangle of this cell vanished
        if representative == "center":
            expected = origin + (np.array(cell) + 0.5) * h
        elif representative == "centroid":
            expected = V[members].mean(axis=0)
        else:
            expected = np.median(V[members], axis=0)
        np.testing.assert_allclose(result.V[out], expected, rtol=0, atol=1e-12)
        checked += 1
    assert checked == len(result.V) > 20
    assert result.cell_size == h


def test_faces_match_numpy_reference():
    V, F = noisy_sphere()
    h = 0.29
    result = decimation.cluster(V, F, cell_size=h, representative="centroid")
    groups, _, _ = reference_groups(V, F, h)
    cell_id = {cell: i for i, cell in enumerate(sorted(groups))}
    vertex_cell = np.full(len(V), -1)
    for cell, members in groups.items():
        vertex_cell[members] = cell_id[cell]
    C = vertex_cell[F]
    distinct = (C[:, 0] != C[:, 1]) & (C[:, 1] != C[:, 2]) & (C[:, 0] != C[:, 2])
    expected = {tuple(sorted(t)) for t in C[distinct].tolist()}
    # Output faces in terms of cells: through any input vertex of each output vertex.
    out_to_cell = np.full(len(result.V), -1)
    has = result.vertex_cluster >= 0
    out_to_cell[result.vertex_cluster[has]] = vertex_cell[has]
    got = [tuple(sorted(t)) for t in out_to_cell[result.F].tolist()]
    assert len(got) == len(set(got)), "duplicate triangles are removed"
    assert set(got) == expected
    assert result.F.dtype == np.int64 and result.V.dtype == np.float64


def test_cell_size_for_target_vertices():
    V, F = noisy_sphere()
    for target in (30, 120, 400):
        result = decimation.cluster(V, F, target_vertices=target, representative="centroid")
        assert len(result.V) <= target
        assert len(result.V) >= 0.5 * target
        # the chosen size does give an occupied-cell count within the target
        groups, _, _ = reference_groups(V, F, result.cell_size)
        assert len(result.V) <= len(groups) <= target


# ---------------------------------------------------------------- quadric representative (§4.1.1)

def test_quadric_representative_lands_on_cube_corners_and_edges():
    V, F = datasets.cube(8, size=1.0)
    h = 0.3      # corner cells hold the corner and parts of three faces
    result = decimation.cluster(V, F, cell_size=h, representative="quadric")
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    for corner in corners:
        v = int(np.flatnonzero(np.all(V == corner, axis=1))[0])
        np.testing.assert_allclose(result.V[result.vertex_cluster[v]], corner, rtol=0, atol=1e-12)
    # Every representative lies on the cube's surface, those of crease cells on the crease.
    on_face = np.isclose(np.abs(result.V), 0.5, atol=1e-12)
    assert on_face.any(axis=1).all()
    centroid = decimation.cluster(V, F, cell_size=h, representative="centroid")
    assert not np.isclose(np.abs(centroid.V), 0.5, atol=1e-6).any(axis=1).all(), \
        "the centroid cuts corners: the quadric must do better"
    # Crease cells (vertices on exactly one cube edge): two coordinates at ±0.5.
    on_edge = np.isclose(np.abs(V), 0.5).sum(axis=1) == 2
    for v in np.flatnonzero(on_edge):
        out = result.V[result.vertex_cluster[v]]
        if np.isclose(np.abs(out), 0.5).sum() < 3:   # not a corner cell
            assert np.isclose(np.abs(out), 0.5, atol=1e-12).sum() == 2


def test_quadric_on_planar_cells_stays_at_the_centroid():
    # Rank-1 quadrics (every plane the same): the pseudo-inverse keeps the centroid in the plane
    # instead of flying off.
    V, F = datasets.grid(20, 20)
    V = np.column_stack([V[:, :2], np.full(len(V), 0.25)]) if V.shape[1] == 3 else V
    rotation, _ = np.linalg.qr(np.random.default_rng(5).normal(size=(3, 3)))
    V = V @ rotation.T
    quadric = decimation.cluster(V, F, cell_size=0.13, representative="quadric")
    centroid = decimation.cluster(V, F, cell_size=0.13, representative="centroid")
    assert np.isfinite(quadric.V).all()
    np.testing.assert_allclose(quadric.V, centroid.V, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(quadric.F, centroid.F)


def test_quadric_keeps_features_the_other_representatives_cut():
    V, F = datasets.cube(10, size=1.0)
    V = V + np.array([0.013, -0.021, 0.007])   # cells not aligned with the cube
    errors = {}
    for representative in decimation.CLUSTER_REPRESENTATIVES:
        result = decimation.cluster(V, F, cell_size=0.17, representative=representative)
        # distance of a point near the surface to the cube's surface: | max_i |p_i - c_i| - 1/2 |
        offset = np.abs(result.V - np.array([0.013, -0.021, 0.007])).max(axis=1) - 0.5
        errors[representative] = np.abs(offset).max()
    assert errors["quadric"] < 1e-9
    assert errors["centroid"] > 1e-3 and errors["center"] > 1e-3


# ---------------------------------------------------------------- invariants

@pytest.mark.parametrize("h", [0.05, 0.15, 0.4, 1.5])
def test_output_invariants(h):
    V, F = noisy_sphere()
    result = decimation.cluster(V, F, cell_size=h)
    Fo = result.F
    if len(Fo):
        assert Fo.min() >= 0 and Fo.max() < len(result.V)
        assert ((Fo[:, 0] != Fo[:, 1]) & (Fo[:, 1] != Fo[:, 2]) & (Fo[:, 0] != Fo[:, 2])).all()
        assert len({tuple(sorted(t)) for t in Fo.tolist()}) == len(Fo)
        assert np.unique(Fo).size == len(result.V), "every output vertex is used"
        assert result.is_manifold == topology.is_manifold(Fo)
    assert len(result.V) <= len(reference_groups(V, F, h)[0])
    assert result.vertex_cluster.shape == (len(V),)


def test_fine_grid_keeps_the_mesh():
    V, F = datasets.icosphere(2)
    result = decimation.cluster(V, F, cell_size=1e-4, representative="centroid")
    assert result.is_manifold
    np.testing.assert_array_equal(result.V[result.vertex_cluster], V)
    assert len(result.F) == len(F)


def test_non_manifold_result_is_reported():
    # A thin torus on a coarse grid pinches: clustering does not guarantee a manifold.
    V, F = datasets.torus(1.0, 0.1, 48, 12)
    reports = [decimation.cluster(V, F, cell_size=h).is_manifold for h in (0.12, 0.17, 0.23, 0.31)]
    assert not all(reports)


def test_unreferenced_vertices_are_ignored():
    V, F = datasets.icosphere(2)
    V2 = np.vstack([V, [[50.0, 50.0, 50.0]]])
    a = decimation.cluster(V, F, cell_size=0.3)
    b = decimation.cluster(V2, F, cell_size=0.3)
    np.testing.assert_array_equal(a.V, b.V)
    np.testing.assert_array_equal(a.F, b.F)
    assert b.vertex_cluster[-1] == -1


@pytest.mark.parametrize("name", ["stanford-bunny.obj", "plane_holes.obj", "cubes_complex_edge.obj",
                                  "cubes_complex_vertex.obj", "fandisk.obj"])
def test_shared_meshes(data_dir, name):
    # holes, unreferenced vertices, non-manifold input: clustering takes them all
    V, F = meshsmith.io.read_mesh(data_dir / name)
    for representative in decimation.CLUSTER_REPRESENTATIVES:
        result = decimation.cluster(V, F, target_vertices=max(8, len(V) // 30), representative=representative)
        assert 0 < len(result.F) and np.isfinite(result.V).all()
        assert result.F.max() < len(result.V)
        assert result.is_manifold == topology.is_manifold(result.F)
        assert len(result.V) <= max(8, len(V) // 30)
        box_low, box_high = V.min(axis=0), V.max(axis=0)
        slack = result.cell_size * 1.001
        assert (result.V >= box_low - slack).all() and (result.V <= box_high + slack).all()


# ---------------------------------------------------------------- bad input

def test_bad_input():
    V, F = datasets.icosphere(1)
    V0, F0 = V.copy(), F.copy()
    with pytest.raises(meshsmith.InputError, match="exactly one"):
        decimation.cluster(V, F)
    with pytest.raises(meshsmith.InputError, match="exactly one"):
        decimation.cluster(V, F, cell_size=0.1, target_vertices=10)
    for bad in (0.0, -1.0, np.nan, np.inf):
        with pytest.raises(meshsmith.InputError, match="cell_size"):
            decimation.cluster(V, F, cell_size=bad)
    with pytest.raises(meshsmith.InputError, match="2\\^21"):
        decimation.cluster(V, F, cell_size=1e-300)
    with pytest.raises(meshsmith.InputError, match="target_vertices"):
        decimation.cluster(V, F, target_vertices=0)
    with pytest.raises(meshsmith.InputError, match="target_vertices"):
        decimation.cluster(V, F, target_vertices=2.5)
    with pytest.raises(meshsmith.InputError, match="representative = 'mean'"):
        decimation.cluster(V, F, cell_size=0.1, representative="mean")
    Vn = V.copy()
    Vn[4, 1] = np.nan
    with pytest.raises(meshsmith.InputError, match="V\\[4, 1\\]"):
        decimation.cluster(Vn, F, cell_size=0.1)
    Fb = F.copy()
    Fb[2, 0] = len(V)
    with pytest.raises(meshsmith.InputError, match="F\\[2\\]"):
        decimation.cluster(V, Fb, cell_size=0.1)
    with pytest.raises(meshsmith.InputError):
        decimation.cluster(V[:, :2], F, cell_size=0.1)
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(F, F0)
