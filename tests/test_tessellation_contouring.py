"""Tests of the contouring half of the tessellation chapter: power diagrams (§2.1.4), the 2D
crust, medial axis and LFS (§2.1.2–2.1.3) and the 3D Cocone reconstruction."""
import numpy as np
import pytest

import meshsmith
from meshsmith import _contouring as tess
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
