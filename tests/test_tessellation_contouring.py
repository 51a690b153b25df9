"""Tests of the contouring half of the tessellation chapter: power diagrams (§2.1.4), the 2D
crust, medial axis and LFS (§2.1.2–2.1.3) and the 3D Cocone reconstruction."""
import re

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
    diagram = tess.power_diagram(P, w, bounds=bounds)
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
    with pytest.raises(meshsmith.InputError, match=re.escape("P[1, 1] is inf: expected finite numbers")):
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


def test_medial_axis_is_every_bounded_voronoi_edge_off_the_crust():
    # A non-convex curve: the result holds the inner axis and the bounded part of the outer axis
    # (one Voronoi edge per Delaunay edge with two triangles that is not a crust edge); the rays
    # dual to the convex hull's edges are left out.
    from scipy.spatial import Delaunay

    samples = star(400)
    vertices, edges = tess.medial_axis(samples)
    triangles = Delaunay(samples).simplices
    count = {}
    for t in triangles:
        for k in range(3):
            e = tuple(sorted((t[k], t[(k + 1) % 3])))
            count[e] = count.get(e, 0) + 1
    crust_edges = {tuple(e) for e in tess.crust(samples).tolist()}
    bounded = [e for e, c in count.items() if c == 2 and e not in crust_edges]
    rays = [e for e, c in count.items() if c == 1 and e not in crust_edges]
    assert len(edges) == len(bounded) and len(rays) > 0
    radius, angle = np.hypot(vertices[:, 0], vertices[:, 1]), np.arctan2(vertices[:, 1], vertices[:, 0])
    inside = radius < 1 + 0.3 * np.cos(5 * angle)
    assert inside.sum() > 0 and (~inside).sum() > 0  # inner and outer axis
    assert np.isfinite(vertices).all()  # (circumcentres of thin hull triangles lie far out)


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
    """Symmetric Hausdorff distance between the two surfaces, sampled on their triangles (the
    vertex-only distance is 0 between two triangulations of the same points)."""
    return meshsmith.geometry.hausdorff_distance(V, F, V0, F0, sampled=True, samples_per_face=16)


def nearest_neighbour_spacing(P):
    from scipy.spatial import cKDTree

    d, _ = cKDTree(P).query(P, k=2)
    return d[:, 1]


def mean_spacing(P):
    return float(nearest_neighbour_spacing(P).mean())


def surface_samples(V, F, per_face=16, seed=0):
    r = np.random.default_rng(seed).random((len(F), per_face, 2))
    outside = r.sum(-1) > 1
    r[outside] = 1 - r[outside]
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    Q = a[:, None] + r[..., :1] * (b - a)[:, None] + r[..., 1:] * (c - a)[:, None]
    return np.vstack([V, Q.reshape(-1, 3)])


def local_spacing_ratio(P, V, F, V0, F0):
    """Largest distance between the surfaces relative to the LOCAL sample spacing: over points
    sampled on both surfaces, the distance to the other surface divided by the mean
    nearest-neighbour spacing of the 8 samples nearest to the point."""
    from scipy.spatial import cKDTree

    spacing, tree = nearest_neighbour_spacing(P), cKDTree(P)
    worst = 0.0
    for Q, (VB, FB) in ((surface_samples(V, F), (V0, F0)), (surface_samples(V0, F0), (V, F))):
        local = spacing[tree.query(Q, k=8)[1]].mean(axis=1)
        worst = max(worst, float((point_to_mesh_distance(Q, VB, FB) / local).max()))
    return worst


def inward_triangle_count(V, F, V0, F0):
    """Triangles whose normal points against that of the nearest source triangle."""
    import igl

    def unit_normals(V, F):
        n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
        return n / np.linalg.norm(n, axis=1)[:, None]

    _, nearest, _ = igl.point_mesh_squared_distance(V[F].mean(axis=1), V0, F0)
    return int(np.sum(np.einsum("ij,ij->i", unit_normals(V, F), unit_normals(V0, F0)[nearest]) < 0))


def signed_volume(V, F):
    return polyhedron_volume(V, F)


def assert_closed_surface(V, F, genus, n_points):
    assert topology.is_manifold(F) and topology.is_oriented(F)
    assert len(topology.boundary_loops(F)) == 0 and topology.genus(F) == genus
    assert signed_volume(V, F) > 0  # outward
    assert np.array_equal(np.unique(F), np.arange(n_points))  # every sample is a vertex


# Measured (sampled symmetric Hausdorff ÷ mean spacing, largest distance ÷ local spacing):
# sphere 3k 0.22 / 0.33, 12k 0.13 / 0.19; torus 3k 0.44 / 0.66, 6k 0.44 / 0.68, 12k 0.40 / 0.38.
# On random samples of a curved surface this is the chord error of the triangles (a triangle of
# circumradius r on a surface of curvature k is k r^2 / 2 away), not a wrong triangle.
@pytest.mark.parametrize("n, by_mean, by_local", [(3000, 0.26, 0.39), (12000, 0.16, 0.23)])
def test_crust_3d_sphere_samples(n, by_mean, by_local):
    V0, F0 = meshsmith.datasets.icosphere(5)
    P, _ = meshsmith.datasets.sample_points(V0, F0, n, seed=0)
    V, F = tess.crust_3d(P)
    assert np.array_equal(V, P) and F.dtype == np.int64
    assert_closed_surface(V, F, 0, n)
    assert signed_volume(V, F) == pytest.approx(4 / 3 * np.pi, rel=0.05)
    assert hausdorff(V, F, V0, F0) < by_mean * mean_spacing(P)
    assert local_spacing_ratio(P, V, F, V0, F0) < by_local


@pytest.mark.parametrize("n, by_mean, by_local", [(3000, 0.52, 0.78), (6000, 0.52, 0.8), (12000, 0.48, 0.45)])
def test_crust_3d_torus_samples(n, by_mean, by_local):
    V0, F0 = meshsmith.datasets.torus(n_major=128, n_minor=64)
    P, _ = meshsmith.datasets.sample_points(V0, F0, n, seed=0)
    V, F = tess.crust_3d(P)
    assert_closed_surface(V, F, 1, n)
    assert hausdorff(V, F, V0, F0) < by_mean * mean_spacing(P)
    assert local_spacing_ratio(P, V, F, V0, F0) < by_local


def test_crust_3d_samples_needed():
    """Smallest uniform (random, area-weighted) sample counts for a closed, manifold, outward
    surface of the right genus using every sample, measured in steps of 25 up to 3000: the unit
    sphere from 8 samples (seeds 0-5; 4 to 7 points can fail), the torus of radii 1 and 0.35
    from 225 (seed 0 fails at 100, 150 and 200; seeds 1-5 pass from 175)."""
    S0, G0 = meshsmith.datasets.icosphere(5)
    T0, H0 = meshsmith.datasets.torus(n_major=128, n_minor=64)

    def closed(V0, F0, n, seed, genus):
        P, _ = meshsmith.datasets.sample_points(V0, F0, n, seed=seed)
        V, F = tess.crust_3d(P)
        return (topology.is_manifold(F) and topology.is_oriented(F) and not topology.boundary_loops(F)
                and topology.genus(F) == genus and signed_volume(V, F) > 0 and len(np.unique(F)) == n)

    for seed in range(6):
        for n in (8, 12, 20, 50, 200):
            assert closed(S0, G0, n, seed, 0), (n, seed)
        for n in (225, 250, 300, 400, 600, 1000):
            assert closed(T0, H0, n, seed, 1), (n, seed)
    assert not closed(T0, H0, 200, 0, 1)


def test_crust_3d_flat_faceted_torus_dense_samples():
    # 100k samples on a coarse faceted torus: many flat tetrahedra (slivers) whose candidate
    # triangles used to fold back and add two handles; sharp-edge pruning removes them.
    # Measured: Hausdorff 0.30 mean spacings, 0.58 local; 2 inward triangles (a zero-width pleat:
    # a triangle lying under its three folded-back neighbours, on the surface).
    V0, F0 = meshsmith.datasets.torus()
    P, _ = meshsmith.datasets.sample_points(V0, F0, 100000, seed=0)
    V, F = tess.crust_3d(P)
    assert_closed_surface(V, F, 1, len(P))
    assert meshsmith.geometry.volume(V, F) == pytest.approx(meshsmith.geometry.volume(V0, F0), rel=0.01)
    assert hausdorff(V, F, V0, F0) < 0.36 * mean_spacing(P)
    assert inward_triangle_count(V, F, V0, F0) <= 2


# Vertices of real meshes, unevenly spaced (the bunny's thin ears, pmp-bunny's sparse flat base).
# Measured (Hausdorff ÷ mean spacing, largest distance ÷ local spacing, inward triangles):
# torus.obj 0.0000 / 0.000 / 0, bob 0.068 / 0.098 / 0, spot 0.32 / 0.49 / 2, bunny 0.50 / 0.70 / 1,
# kitten 0.35 / 0.52 / 3 (0.61 / 0.98 before samples left on no triangle were inserted),
# pmp-bunny 0.69 / 0.70 / 7 (its sparse, slightly curved base, triangles 10 local spacings wide;
# 0.94 / 0.84 when its 18-edge hole was closed by ear cutting instead of minimum area). The
# source meshes are not Delaunay: flipping each one's edges to the Delaunay criterion alone puts
# it 0.50 (bunny), 0.31 (kitten), 0.27 (spot), 0.59 (pmp-bunny) mean spacings from itself.
MESH_CASES = [("torus.obj", 0.001, 0.001, 0), ("bob_tri.obj", 0.085, 0.12, 0), ("spot.obj", 0.38, 0.59, 2),
              ("bunny.off", 0.6, 0.84, 1), ("kitten.off", 0.42, 0.63, 3), ("pmp-bunny.off", 0.83, 0.84, 7)]


@pytest.mark.parametrize("name, by_mean, by_local, inward", MESH_CASES)
def test_crust_3d_mesh_vertices(data_dir, name, by_mean, by_local, inward):
    V0, F0 = meshsmith.io.read_mesh(str(data_dir / name))
    V, F = tess.crust_3d(V0)
    assert_closed_surface(V, F, topology.genus(F0), len(V0))
    assert hausdorff(V, F, V0, F0) < by_mean * mean_spacing(V0)
    assert local_spacing_ratio(V0, V, F, V0, F0) < by_local
    assert inward_triangle_count(V, F, V0, F0) <= inward


def test_crust_3d_progress_and_cancel():
    V0, F0 = meshsmith.datasets.torus(n_major=128, n_minor=64)
    P, _ = meshsmith.datasets.sample_points(V0, F0, 20000, seed=0)
    calls = []
    V, F = tess.crust_3d(P, progress=lambda fraction, stage: calls.append((fraction, stage)) or True)
    fractions = [f for f, _ in calls]
    assert calls[-1] == (1.0, "crust_3d") and fractions == sorted(fractions) and fractions[0] == 0.0
    assert calls[0][1] == "delaunay"  # (later stages may fall between throttled calls)
    assert np.array_equal(tess.crust_3d(P)[1], F)  # the callback changes nothing
    with pytest.raises(meshsmith.Cancelled):
        tess.crust_3d(P, progress=lambda fraction, stage: False)
    seen = []

    def cancel_after_delaunay(fraction, stage):
        seen.append(fraction)
        return fraction <= 0.35

    with pytest.raises(meshsmith.Cancelled, match="crust_3d"):  # the final call at the latest
        tess.crust_3d(P, progress=cancel_after_delaunay)
    assert seen[-1] > 0.35 and all(f <= 0.35 for f in seen[:-1])


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
