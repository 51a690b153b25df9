"""Tests of the contouring half of the tessellation chapter: power diagrams (§2.1.4), the 2D
crust, medial axis and LFS (§2.1.2–2.1.3) and the 3D Cocone reconstruction."""
import numpy as np
import pytest

import meshsmith
from meshsmith import tessellation as tess
from meshsmith import topology


# ---------------------------------------------------------------------------------------------
# Power diagrams

def polygon_area(polygon):
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def polyhedron_volume(vertices, faces):
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    return float(np.sum(np.einsum("ij,ij->i", a, np.cross(b, c)))) / 6.0


def point_in_polygon(q, polygon, tolerance=1e-9):
    """q inside (or on) a CCW convex polygon."""
    d = np.roll(polygon, -1, axis=0) - polygon
    r = q - polygon
    return bool(np.all(d[:, 0] * r[:, 1] - d[:, 1] * r[:, 0] >= -tolerance))


def point_in_polyhedron(q, vertices, faces, tolerance=1e-9):
    """q inside (or on) a convex polyhedron with outward triangles."""
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    normals = np.cross(b - a, c - a)
    lengths = np.linalg.norm(normals, axis=1)
    keep = lengths > 1e-14
    normals = normals[keep] / lengths[keep, None]
    return bool(np.all(np.einsum("ij,ij->i", q - a[keep], normals) <= tolerance))


def power_owner(q, P, w):
    return int(np.argmin(np.sum((P - q) ** 2, axis=1) - w))


def test_power_diagram_equal_weights_is_voronoi_2d():
    from scipy.spatial import Voronoi

    rng = np.random.default_rng(1)
    P = rng.random((40, 2))
    diagram = tess.power_diagram(P, np.zeros(len(P)), bounds=(-1, -1, 2, 2))
    vor = Voronoi(P)
    compared = 0
    for i, cell in enumerate(diagram.cells):
        region = vor.regions[vor.point_region[i]]
        if -1 in region or np.abs(vor.vertices[region] - 0.5).max() > 1.5:
            continue  # unbounded, or clipped by the box
        expected = vor.vertices[region]
        compared += 1
        assert len(cell) == len(expected)
        # every scipy Voronoi vertex is a corner of our cell, and vice versa
        distances = np.linalg.norm(cell[:, None, :] - expected[None, :, :], axis=2)
        assert distances.min(axis=1).max() < 1e-9
        assert distances.min(axis=0).max() < 1e-9
    assert compared >= 20
    assert len(diagram.hidden) == 0
    assert diagram.triangulation.shape[1] == 3 and diagram.triangulation.dtype == np.int64


def test_power_diagram_2d_triangulation_is_delaunay_for_equal_weights():
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(2)
    P = rng.random((60, 2))
    ours = {tuple(sorted(t)) for t in tess.power_diagram(P, np.zeros(60)).triangulation.tolist()}
    theirs = {tuple(sorted(t)) for t in Delaunay(P).simplices.tolist()}
    assert ours == theirs


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_power_diagram_2d_cells_hold_their_grid_points(seed):
    rng = np.random.default_rng(seed)
    P = rng.random((50, 2))
    w = 0.02 * rng.random(50)
    diagram = tess.power_diagram(P, w)
    xmin, ymin, xmax, ymax = diagram.bounds
    for cell in diagram.cells:
        if len(cell):
            assert polygon_area(cell) > 0  # counter-clockwise
    grid = np.stack(np.meshgrid(np.linspace(xmin, xmax, 41)[1:-1], np.linspace(ymin, ymax, 41)[1:-1]),
                    axis=-1).reshape(-1, 2)
    for q in grid:
        owner = power_owner(q, P, w)
        assert point_in_polygon(q, diagram.cells[owner])
    total = sum(polygon_area(c) for c in diagram.cells if len(c))
    assert total == pytest.approx((xmax - xmin) * (ymax - ymin), rel=1e-10)


def test_power_diagram_3d_cells_hold_their_grid_points_and_tile_the_box():
    rng = np.random.default_rng(3)
    P = rng.random((40, 3))
    w = 0.03 * rng.random(40)
    bounds = (-0.1, -0.1, 1.1, 1.1, -0.1, 1.1)
    diagram = tess.power_diagram(P, w, bounds)
    assert diagram.triangulation.shape[1] == 4
    volumes = []
    for vertices, faces in diagram.cells:
        if len(vertices):
            volumes.append(polyhedron_volume(vertices, faces))
            assert volumes[-1] > 0  # outward faces
            assert topology.is_manifold(faces) and topology.euler_characteristic(faces) == 2
    assert sum(volumes) == pytest.approx(1.2 ** 3, rel=1e-10)
    axis = np.linspace(-0.1, 1.1, 13)[1:-1]
    grid = np.stack(np.meshgrid(axis, axis, axis), axis=-1).reshape(-1, 3)
    for q in grid:
        vertices, faces = diagram.cells[power_owner(q, P, w)]
        assert point_in_polyhedron(q, vertices, faces)


def test_power_diagram_3d_equal_weights_match_scipy_voronoi():
    from scipy.spatial import Voronoi

    rng = np.random.default_rng(4)
    P = rng.random((30, 3))
    diagram = tess.power_diagram(P, np.zeros(30), bounds=(-5, -5, 5, 5, -5, 5))
    vor = Voronoi(P)
    compared = 0
    for i, (vertices, faces) in enumerate(diagram.cells):
        region = vor.regions[vor.point_region[i]]
        if -1 in region or np.abs(vor.vertices[region]).max() > 5:
            continue
        expected = vor.vertices[region]
        distances = np.linalg.norm(vertices[:, None, :] - expected[None, :, :], axis=2)
        assert distances.min(axis=1).max() < 1e-8 and distances.min(axis=0).max() < 1e-8
        compared += 1
    assert compared >= 1


@pytest.mark.parametrize("dimension", [2, 3])
def test_power_diagram_reports_hidden_sites(dimension):
    rng = np.random.default_rng(5)
    P = rng.random((20, dimension))
    w = np.full(20, 0.001)
    # Site 7 sits at the centroid of a small simplex of heavy sites 0..d: its lifted point
    # (p, |p|^2 - w) lies above the lifted simplex, so its power cell is empty.
    simplex = (np.array([[1.0, 0.0], [-0.5, 0.866], [-0.5, -0.866]]) if dimension == 2 else
               np.array([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]))
    P[: dimension + 1] = P[7] + 0.05 * simplex
    w[: dimension + 1] = 0.25
    w[7] = 0.0
    diagram = tess.power_diagram(P, w)
    assert 7 in diagram.hidden.tolist()
    cell = diagram.cells[7] if dimension == 2 else diagram.cells[7][0]
    assert len(cell) == 0
    assert 7 not in set(diagram.triangulation.ravel().tolist())
    # brute force: no grid point is owned by a hidden site
    lower, upper = P.min(axis=0), P.max(axis=0)
    grid = rng.uniform(lower, upper, size=(2000, dimension))
    owners = np.argmin(((grid[:, None, :] - P[None]) ** 2).sum(-1) - w, axis=1)
    assert not np.isin(owners, diagram.hidden).any()


def test_power_diagram_single_and_collinear_sites():
    one = tess.power_diagram(np.array([[0.5, 0.5]]), [1.0], bounds=(0, 0, 1, 1))
    assert polygon_area(one.cells[0]) == pytest.approx(1.0)
    line = np.c_[np.arange(5.0), np.zeros(5)]
    diagram = tess.power_diagram(line, np.zeros(5), bounds=(-1, -1, 5, 1))
    assert len(diagram.triangulation) == 0
    areas = [polygon_area(c) for c in diagram.cells]
    assert areas == pytest.approx([3.0, 2.0, 2.0, 2.0, 3.0])


def test_power_diagram_coplanar_sites_3d_and_many_collinear_sites():
    rng = np.random.default_rng(8)
    P = np.c_[rng.random((12, 2)), np.full(12, 0.5)]
    w = 0.01 * rng.random(12)
    diagram = tess.power_diagram(P, w, bounds=(0, 0, 1, 1, 0, 1))
    assert len(diagram.triangulation) == 0
    total = sum(polyhedron_volume(v, f) for v, f in diagram.cells if len(v))
    assert total == pytest.approx(1.0, rel=1e-10)
    for q in rng.random((300, 3)):
        vertices, faces = diagram.cells[power_owner(q, P, w)]
        assert point_in_polyhedron(q, vertices, faces)
    # many collinear sites: neighbours come from the 1D regular triangulation, not all pairs
    n = 20000
    line = np.c_[np.arange(n, dtype=float), np.zeros(n)]
    cells = tess.power_diagram(line, np.zeros(n), bounds=(-1, -1, n, 1)).cells
    assert polygon_area(cells[n // 2]) == pytest.approx(2.0)


def test_power_diagram_default_bounds_enlarge_the_bounding_box_by_ten_percent():
    P = np.array([[0.0, 0.0, 0.0], [2.0, 1.0, 4.0], [1.0, 3.0, 1.0], [0.5, 0.5, 2.0]])
    diagram = tess.power_diagram(P, np.zeros(4))
    assert diagram.bounds == pytest.approx([-0.2, -0.3, 2.2, 3.3, -0.4, 4.4])
    total = sum(polyhedron_volume(v, f) for v, f in diagram.cells if len(v))
    assert total == pytest.approx(2.4 * 3.6 * 4.8, rel=1e-10)


def test_power_diagram_bad_input():
    with pytest.raises(meshsmith.InputError, match="weights"):
        tess.power_diagram(np.zeros((3, 2)), np.zeros(2))
    with pytest.raises(meshsmith.InputError, match="not finite"):
        tess.power_diagram(np.array([[0, 0], [1, np.nan], [0, 1]]), np.zeros(3), bounds=(0, 0, 1, 1))
    with pytest.raises(meshsmith.InputError, match=r"\(n, 2\) or \(n, 3\)"):
        tess.power_diagram(np.zeros((3, 4)), np.zeros(3), bounds=(0, 0, 1, 1))
    with pytest.raises(meshsmith.InputError, match="bounds"):
        tess.power_diagram(np.random.default_rng(0).random((4, 2)), np.zeros(4), bounds=(0, 0, 1))
    with pytest.raises(meshsmith.InputError, match="empty along axis 0"):
        tess.power_diagram(np.random.default_rng(0).random((4, 2)), np.zeros(4), bounds=(1, 0, 0, 1))
    with pytest.raises(meshsmith.InputError, match="empty"):
        tess.power_diagram(np.zeros((0, 2)), np.zeros(0), bounds=(0, 0, 1, 1))
    with pytest.raises(meshsmith.InputError, match="empty"):
        tess.power_diagram(np.zeros((0, 2)), np.zeros(0))
    with pytest.raises(meshsmith.InputError, match="not finite"):
        tess.power_diagram(np.array([[0, 0], [1, np.inf]]), np.zeros(2))
    with pytest.raises(meshsmith.InputError, match="weight 1 is not finite"):
        tess.power_diagram(np.array([[0, 0], [1, 1.0]]), [0, np.nan])


# ---------------------------------------------------------------------------------------------
# Voronoi filtering in 2D: crust, medial axis, LFS, R-samples

def circle(n, radius=1.0, centre=(0.0, 0.0)):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.c_[centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)]


def ellipse(n, a=2.0, b=1.0):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.c_[a * np.cos(t), b * np.sin(t)]


def star(n):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 1 + 0.3 * np.cos(5 * t)
    return np.c_[r * np.cos(t), r * np.sin(t)]


def bean(n):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 1 + 0.25 * np.cos(2 * t) + 0.1 * np.sin(3 * t)
    return np.c_[r * np.cos(t), r * np.sin(t)]


def closed_polygon_edges(n, offset=0):
    return {tuple(sorted((offset + i, offset + (i + 1) % n))) for i in range(n)}


SHAPES = {"circle": circle, "ellipse": ellipse, "star": star, "bean": bean}


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_crust_reconstructs_dense_closed_curves(name):
    n = 200
    samples = SHAPES[name](n)
    assert tess.is_r_sample(samples, 0.25)
    E = tess.crust(samples)
    assert E.dtype == np.int64 and E.shape[1] == 2
    assert {tuple(e) for e in E.tolist()} == closed_polygon_edges(n)


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_crust_of_shuffled_jittered_samples(name):
    rng = np.random.default_rng(7)
    n = 300
    t = np.linspace(0, 2 * np.pi, n, endpoint=False) + rng.uniform(-0.3, 0.3, n) * 2 * np.pi / n
    ordered = SHAPES[name](n)  # reference ordering of the parameter grid
    # the same curve evaluated at the jittered parameters
    scale = {"circle": lambda u: np.c_[np.cos(u), np.sin(u)],
             "ellipse": lambda u: np.c_[2 * np.cos(u), np.sin(u)],
             "star": lambda u: (1 + 0.3 * np.cos(5 * u))[:, None] * np.c_[np.cos(u), np.sin(u)],
             "bean": lambda u: (1 + 0.25 * np.cos(2 * u) + 0.1 * np.sin(3 * u))[:, None]
             * np.c_[np.cos(u), np.sin(u)]}[name]
    samples = scale(t)
    assert len(samples) == len(ordered)
    permutation = rng.permutation(n)
    shuffled = samples[permutation]
    E = tess.crust(shuffled)
    original = {tuple(sorted((int(permutation[a]), int(permutation[b])))) for a, b in E.tolist()}
    assert original == closed_polygon_edges(n)


def test_crust_reconstructs_several_disjoint_curves():
    parts = [circle(80, 1.0, (0, 0)), circle(60, 0.5, (3, 0)), ellipse(120) + np.array([0.0, 4.0])]
    samples = np.vstack(parts)
    expected, offset = set(), 0
    for part in parts:
        expected |= closed_polygon_edges(len(part), offset)
        offset += len(part)
    assert {tuple(e) for e in tess.crust(samples).tolist()} == expected


def test_crust_sample_counts_needed():
    """Smallest uniform sample counts from which the crust is exact (measured; kept as a
    regression bound): circle 6, ellipse 6, bean 6, star 17."""
    needed = {"circle": 6, "ellipse": 6, "bean": 6, "star": 17}
    for name, n in needed.items():
        for m in range(n, n + 30):
            assert {tuple(e) for e in tess.crust(SHAPES[name](m)).tolist()} == closed_polygon_edges(m)
    assert {tuple(e) for e in tess.crust(star(12)).tolist()} != closed_polygon_edges(12)


def test_medial_axis_of_circle_is_its_centre():
    vertices, edges = tess.medial_axis(circle(100, 2.0, (1.0, -1.0)))
    assert len(vertices) > 0 and edges.shape[1] == 2
    assert np.abs(vertices - [1.0, -1.0]).max() < 1e-9


def test_medial_axis_of_ellipse_lies_between_the_centres_of_curvature():
    a, b = 2.0, 1.0
    vertices, edges = tess.medial_axis(ellipse(400, a, b))
    end = (a * a - b * b) / a  # the medial axis is the segment [-end, end] x {0}
    assert np.abs(vertices[:, 1]).max() < 0.02
    assert np.abs(vertices[:, 0]).max() < end + 0.02
    assert vertices[:, 0].max() > end - 0.05 and vertices[:, 0].min() < -end + 0.05
    assert edges.min() >= 0 and edges.max() < len(vertices)


def test_local_feature_size_circle_and_ellipse():
    assert tess.local_feature_size(circle(64, 3.0)) == pytest.approx(np.full(64, 3.0), rel=1e-9)
    samples = ellipse(800)
    lfs = tess.local_feature_size(samples)
    # exact LFS: at (2, 0) the distance to the axis end (1.5, 0); at (0, 1) the distance to (0, 0)
    assert lfs[0] == pytest.approx(0.5, rel=0.02)
    assert lfs[200] == pytest.approx(1.0, rel=0.02)


def test_sampling_ratio_and_r_sample():
    # circle: LFS = radius, edge length 2 sin(pi/n); ratio = sin(pi/n) / (1 - sin(pi/n))
    n = 100
    half = np.sin(np.pi / n)
    assert tess.sampling_ratio(circle(n)) == pytest.approx(half / (1 - half), rel=1e-9)
    assert tess.is_r_sample(circle(n), 0.05)
    assert not tess.is_r_sample(circle(n), 0.01)
    assert tess.sampling_ratio(star(400)) < tess.sampling_ratio(star(100))


def test_crust_bad_input():
    with pytest.raises(meshsmith.InputError, match="coincides"):
        tess.crust(np.vstack([circle(10), circle(10)[:1]]))
    with pytest.raises(meshsmith.InputError, match="collinear"):
        tess.crust(np.c_[np.arange(5.0), np.zeros(5)])
    with pytest.raises(meshsmith.InputError, match="at least 3"):
        tess.crust(np.zeros((2, 2)))
    with pytest.raises(meshsmith.InputError, match=r"\(n, 2\)"):
        tess.crust(np.zeros((5, 3)))
    with pytest.raises(meshsmith.InputError, match="sample 1 is not finite"):
        tess.medial_axis(np.array([[0, 0], [np.inf, 0], [0, 1.0]]))
    with pytest.raises(meshsmith.InputError, match="positive"):
        tess.is_r_sample(circle(10), 0)


# ---------------------------------------------------------------------------------------------
# Cocone in 3D

def point_to_mesh_distance(Q, V, F):
    import igl

    d2, _, _ = igl.point_mesh_squared_distance(np.ascontiguousarray(Q, float), V, F)
    return np.sqrt(d2)


def hausdorff(V, F, V0, F0):
    """Symmetric Hausdorff distance estimate between two meshes: vertices and face centroids of
    each to the other surface."""
    a = point_to_mesh_distance(np.vstack([V, V[F].mean(1)]), V0, F0).max()
    b = point_to_mesh_distance(np.vstack([V0, V0[F0].mean(1)]), V, F).max()
    return max(a, b)


def mean_spacing(P):
    from scipy.spatial import cKDTree

    d, _ = cKDTree(P).query(P, k=2)
    return float(d[:, 1].mean())


def signed_volume(V, F):
    return polyhedron_volume(V, F)


@pytest.mark.parametrize("n", [3000, 12000])
def test_crust_3d_sphere_samples(n):
    V0, F0 = meshsmith.datasets.icosphere(5)
    P, _ = meshsmith.datasets.sample_points(V0, F0, n, seed=0)
    V, F = tess.crust_3d(P)
    assert np.array_equal(V, P) and F.dtype == np.int64
    assert topology.is_manifold(F) and topology.is_oriented(F)
    assert len(topology.boundary_loops(F)) == 0 and topology.euler_characteristic(F) == 2
    assert signed_volume(V, F) == pytest.approx(4 / 3 * np.pi, rel=0.05)  # outward
    assert hausdorff(V, F, V0, F0) < 0.5 * mean_spacing(P)


@pytest.mark.parametrize("n", [3000, 6000, 12000])
def test_crust_3d_torus_samples(n):
    V0, F0 = meshsmith.datasets.torus(n_major=128, n_minor=64)
    P, _ = meshsmith.datasets.sample_points(V0, F0, n, seed=0)
    V, F = tess.crust_3d(P)
    assert topology.is_manifold(F) and topology.is_oriented(F)
    assert len(topology.boundary_loops(F)) == 0 and topology.genus(F) == 1
    assert signed_volume(V, F) > 0
    assert hausdorff(V, F, V0, F0) < 0.5 * mean_spacing(P)


def test_crust_3d_flat_faceted_torus_dense_samples():
    # 100k samples on a coarse faceted torus: many flat tetrahedra (slivers) whose candidate
    # triangles used to fold back and add two handles; sharp-edge pruning removes them.
    V0, F0 = meshsmith.datasets.torus()
    P, _ = meshsmith.datasets.sample_points(V0, F0, 100000, seed=0)
    V, F = tess.crust_3d(P)
    assert topology.is_manifold(F) and topology.is_oriented(F)
    assert len(topology.boundary_loops(F)) == 0 and topology.genus(F) == 1
    assert meshsmith.geometry.volume(V, F) == pytest.approx(meshsmith.geometry.volume(V0, F0), rel=0.01)


def test_crust_3d_mesh_vertices(data_dir):
    # Vertices of real meshes, unevenly spaced (the bunny's thin ears, pmp-bunny's sparse flat
    # base): closed, outward, of the source's genus. Hausdorff distances measured, in mean
    # spacings: torus.obj 0.00001, bob 0.05, bunny 0.49, kitten 0.61, spot 0.22, pmp-bunny 0.86
    # (its flat base, where a hole of 18 edges is closed by ear cutting).
    cases = [("torus.obj", 0.01), ("bob_tri.obj", 0.1), ("bunny.off", 0.6), ("kitten.off", 0.7),
             ("spot.obj", 0.3), ("pmp-bunny.off", 1.0)]
    for name, spacing_fraction in cases:
        V0, F0 = meshsmith.io.read_mesh(str(data_dir / name))
        V, F = tess.crust_3d(V0)
        assert topology.is_manifold(F) and topology.is_oriented(F), name
        assert len(topology.boundary_loops(F)) == 0, name
        assert topology.genus(F) == topology.genus(F0), name
        assert meshsmith.geometry.volume(V, F) > 0, name
        assert hausdorff(V, F, V0, F0) < spacing_fraction * mean_spacing(V0), name


def test_crust_3d_bad_input():
    with pytest.raises(meshsmith.InputError, match="coplanar"):
        tess.crust_3d(np.c_[np.random.default_rng(0).random((10, 2)), np.zeros(10)])
    with pytest.raises(meshsmith.InputError, match="coincides"):
        P = np.random.default_rng(0).random((10, 3))
        tess.crust_3d(np.vstack([P, P[3:4]]))
    with pytest.raises(meshsmith.InputError, match="at least 4"):
        tess.crust_3d(np.zeros((3, 3)))
    with pytest.raises(meshsmith.InputError, match=r"\(n, 3\)"):
        tess.crust_3d(np.zeros((5, 2)))
    with pytest.raises(meshsmith.InputError, match="cocone_angle"):
        tess.crust_3d(np.random.default_rng(0).random((10, 3)), cocone_angle=2.0)
