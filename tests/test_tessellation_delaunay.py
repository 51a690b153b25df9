"""2D tessellations: Delaunay, constrained Delaunay, Voronoi, Lawson flips, Delaunay refinement.

Delaunay-ness is checked with an exact rational incircle test (fractions.Fraction), triangle sets
against scipy.spatial.Delaunay and libigl's CGAL wrapper, and the rest by invariants (areas,
Euler characteristic, segment conformity, nearest-site membership).
"""
from fractions import Fraction

import numpy as np
import pytest
from scipy.spatial import ConvexHull
from scipy.spatial import Delaunay as ScipyDelaunay

from meshsmith import InputError, SolverError
from meshsmith.tessellation import (constrained_delaunay, delaunay, flip_to_delaunay, refine,
                                 voronoi)


# --- exact helpers ------------------------------------------------------------------------------
def _exact(P):
    return [(Fraction(float(x)), Fraction(float(y))) for x, y in P]


def _orient(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _incircle(a, b, c, d):
    """> 0 iff d is strictly inside the circle through the CCW triangle (a, b, c)."""
    rows = []
    for p in (a, b, c):
        dx, dy = p[0] - d[0], p[1] - d[1]
        rows.append((dx, dy, dx * dx + dy * dy))
    (a1, a2, a3), (b1, b2, b3), (c1, c2, c3) = rows
    return a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1)


def assert_empty_circles(P, F):
    """Every triangle is CCW and no point of P lies strictly inside its circumcircle (exact)."""
    Q = _exact(P)
    used = sorted(set(np.asarray(F).ravel().tolist()))
    for t in F:
        a, b, c = (Q[i] for i in t)
        assert _orient(a, b, c) > 0, f"triangle {t} is not counter-clockwise"
        for i in used:
            if i in t:
                continue
            assert _incircle(a, b, c, Q[i]) <= 0, f"point {i} inside the circumcircle of {t}"


def triangle_set(F):
    return {tuple(sorted(t)) for t in np.asarray(F).tolist()}


def signed_areas(V, F):
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def min_angles_degrees(V, F):
    """Smallest angle of each triangle, in degrees."""
    corners = V[F]
    angles = []
    for k in range(3):
        u = corners[:, (k + 1) % 3] - corners[:, k]
        w = corners[:, (k + 2) % 3] - corners[:, k]
        cos = (u * w).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.min(angles, axis=0)


def edge_set(F):
    F = np.asarray(F)
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    return {tuple(e) for e in E.tolist()}


def assert_segments_are_edges(V, F, P, segments, tolerance=0.0):
    """Each segment of the PSLG is the union of the result's edges along it: exact collinearity,
    or within `tolerance` × length² (constructed split points are rounded to float64)."""
    edges = edge_set(F)
    Q = _exact(V)
    used = sorted(set(np.asarray(F).ravel().tolist()))
    for s, (i, j) in enumerate(np.asarray(segments).tolist()):
        a, b = Q[i], Q[j]
        length2 = (b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2
        on = []
        for k in used:
            p = Q[k]
            if abs(_orient(a, b, p)) > tolerance * length2:
                continue
            t = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]))
            if 0 <= t <= (b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2:
                on.append((t, k))
        chain = [k for _, k in sorted(on)]
        assert chain[0] == i and chain[-1] == j, f"segment {s} endpoints missing"
        for u, v in zip(chain, chain[1:]):
            assert (min(u, v), max(u, v)) in edges, f"segment {s}: ({u}, {v}) is not an edge"


def euler_characteristic(F):
    F = np.asarray(F)
    return len(np.unique(F)) - len(edge_set(F)) + len(F)


# --- delaunay -----------------------------------------------------------------------------------
def test_delaunay_random_points_empty_circles_and_scipy():
    rng = np.random.default_rng(1)
    P = rng.random((80, 2))
    F, merged = delaunay(P)
    assert F.dtype == np.int64 and F.shape[1] == 3
    np.testing.assert_array_equal(merged, np.arange(80))
    assert_empty_circles(P, F)
    assert triangle_set(F) == triangle_set(ScipyDelaunay(P).simplices)
    # The triangles tile the convex hull.
    assert signed_areas(P, F).sum() == pytest.approx(ConvexHull(P).volume, rel=1e-12)


def test_delaunay_matches_scipy_on_many_points():
    P = np.random.default_rng(2).normal(size=(5000, 2))
    F, _ = delaunay(P)
    assert triangle_set(F) == triangle_set(ScipyDelaunay(P).simplices)


def test_delaunay_matches_libigl_cgal():
    try:
        import igl.copyleft.cgal as igl_cgal
    except ImportError:
        pytest.skip("igl.copyleft.cgal is not installed")
    if not hasattr(igl_cgal, "delaunay_triangulation"):
        pytest.skip("igl.copyleft.cgal has no delaunay_triangulation")
    P = np.random.default_rng(3).random((300, 2))
    F, _ = delaunay(P)
    assert triangle_set(F) == triangle_set(igl_cgal.delaunay_triangulation(P))


def test_delaunay_grid_is_cocircular_but_valid():
    x, y = np.meshgrid(np.arange(7.0), np.arange(6.0))
    P = np.column_stack([x.ravel(), y.ravel()])
    F, _ = delaunay(P)
    assert len(F) == 2 * 6 * 5
    assert_empty_circles(P, F)
    assert signed_areas(P, F).sum() == pytest.approx(30.0)
    assert np.all(signed_areas(P, F) > 0)


def test_delaunay_points_on_a_circle():
    angles = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    P = np.column_stack([np.cos(angles), np.sin(angles)])
    P = np.vstack([P, [[0.0, 0.0]]])
    F, _ = delaunay(P)
    assert_empty_circles(P, F)
    assert len(F) == 12


def test_delaunay_merges_and_reports_duplicates():
    rng = np.random.default_rng(4)
    unique = rng.random((30, 2))
    P = np.vstack([unique, unique[[3, 7, 3]]])  # rows 30, 31, 32 repeat rows 3, 7, 3
    F, merged = delaunay(P)
    expected = np.arange(33)
    expected[[30, 31, 32]] = [3, 7, 3]
    np.testing.assert_array_equal(merged, expected)
    assert not np.isin(F, [30, 31, 32]).any()
    assert triangle_set(F) == triangle_set(delaunay(unique)[0])


@pytest.mark.parametrize("P, message", [
    ([[0, 0], [1, 1], [2, 2], [3, 3]], "collinear"),
    ([[0, 0], [1, 1], [0, 0]], "3 distinct"),
    ([[0, 0], [1, 0]], "3 distinct"),
    ([[0, 0], [1, 0], [np.nan, 1]], "row 2"),
    (np.zeros((4, 3)), "shape"),
])
def test_delaunay_bad_input(P, message):
    with pytest.raises(InputError, match=message):
        delaunay(np.asarray(P, dtype=float))


# --- constrained Delaunay -----------------------------------------------------------------------
def square_with_hole():
    P = np.array([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3], [0.5, 2.1],
                  [3.7, 0.4], [2.0, 3.6]], dtype=float)
    segments = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
    return P, segments, np.array([[2.0, 2.0]])


def letter_e():
    outline = np.array([[0, 0], [5, 0], [5, 1], [1.2, 1], [1.2, 2], [4, 2], [4, 3], [1.2, 3],
                        [1.2, 4], [5, 4], [5, 5], [0, 5]], dtype=float)
    n = len(outline)
    return outline, np.array([[i, (i + 1) % n] for i in range(n)])


def sharp_wedge():
    """A right triangle whose corner at the origin has a 5° angle (the others: 90°, 85°)."""
    P = np.array([[0, 0], [10, 0], [10, 10 * np.tan(np.radians(5.0))]])
    return P, np.array([[0, 1], [1, 2], [2, 0]])


def test_constrained_delaunay_square_with_hole():
    P, segments, holes = square_with_hole()
    V, F = constrained_delaunay(P, segments, holes)
    np.testing.assert_array_equal(V, P)
    assert np.all(signed_areas(V, F) > 0)
    assert signed_areas(V, F).sum() == pytest.approx(16 - 4)
    centroids = V[F].mean(axis=1)
    inside_hole = np.all((centroids > 1) & (centroids < 3), axis=1)
    assert not inside_hole.any()
    assert_segments_are_edges(V, F, P, segments)
    assert euler_characteristic(F) == 0  # an annulus


def test_constrained_delaunay_without_seed_meshes_the_hole():
    P, segments, _ = square_with_hole()
    V, F = constrained_delaunay(P, segments)
    assert signed_areas(V, F).sum() == pytest.approx(16)
    assert euler_characteristic(F) == 1


def test_constrained_delaunay_concave_outline_removes_outside():
    P, segments = letter_e()
    V, F = constrained_delaunay(P, segments)
    assert signed_areas(V, F).sum() == pytest.approx(25 - 2 * 3.8 - 1)
    assert_segments_are_edges(V, F, P, segments)
    assert euler_characteristic(F) == 1


def test_constrained_delaunay_crossing_segments_add_intersections():
    P = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [0.5, 1.0], [1.5, 1.0]], dtype=float)
    segments = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [0, 2], [1, 3], [4, 5]])
    V, F = constrained_delaunay(P, segments)
    assert len(V) == len(P) + 1  # the diagonals and the horizontal segment all cross at (1, 1)
    np.testing.assert_allclose(V[-1], [1.0, 1.0])
    assert signed_areas(V, F).sum() == pytest.approx(4)
    assert_segments_are_edges(V, F, P, segments)


def test_constrained_delaunay_is_delaunay_without_constraints():
    P = np.random.default_rng(5).random((40, 2))
    V, F = constrained_delaunay(P, np.empty((0, 2), dtype=int))
    assert triangle_set(F) == triangle_set(delaunay(P)[0])


@pytest.mark.parametrize("segments, message", [
    ([[0, 9]], "outside"),
    ([[0, 3]], "zero length"),
    ([[0, 1.0]], "dtype"),
])
def test_constrained_delaunay_bad_segments(segments, message):
    P = np.array([[0, 0], [1, 0], [0, 1], [0, 0]], dtype=float)
    with pytest.raises(InputError, match=message):
        constrained_delaunay(P, np.asarray(segments))


# --- Voronoi ------------------------------------------------------------------------------------
def point_in_convex_polygon(polygon, q, tolerance=1e-9):
    edges = np.roll(polygon, -1, axis=0) - polygon
    rel = q - polygon
    cross = edges[:, 0] * rel[:, 1] - edges[:, 1] * rel[:, 0]
    return np.all(cross >= -tolerance)


def polygon_area(polygon):
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def test_voronoi_cells_tile_the_box_and_hold_their_sites():
    rng = np.random.default_rng(6)
    P = rng.random((60, 2))
    bounds = (-0.2, -0.3, 1.1, 1.4)
    diagram = voronoi(P, bounds=bounds)
    areas = np.array([polygon_area(c) for c in diagram.cells])
    assert np.all(areas > 0)  # CCW
    assert areas.sum() == pytest.approx(1.3 * 1.7, rel=1e-12)
    for site, cell in zip(P, diagram.cells):
        assert point_in_convex_polygon(cell, site)
    # Grid points lie in the cell of their nearest site (ties have measure zero here).
    gx, gy = np.meshgrid(np.linspace(-0.15, 1.05, 40), np.linspace(-0.25, 1.35, 40))
    queries = np.column_stack([gx.ravel(), gy.ravel()])
    nearest = np.argmin(((queries[:, None, :] - P[None]) ** 2).sum(-1), axis=1)
    for q, i in zip(queries, nearest):
        assert point_in_convex_polygon(diagram.cells[i], q)


def test_voronoi_vertices_and_edges():
    rng = np.random.default_rng(7)
    P = rng.random((40, 2))
    d = voronoi(P)
    assert len(d.vertices) == len(d.triangles)
    # Vertex t is equidistant from the three sites of triangle t, and no site is closer.
    dist = np.linalg.norm(P[d.triangles] - d.vertices[:, None, :], axis=2)
    np.testing.assert_allclose(dist, dist[:, :1].repeat(3, axis=1), rtol=1e-9)
    all_dist = np.linalg.norm(d.vertices[:, None, :] - P[None], axis=2).min(axis=1)
    np.testing.assert_allclose(all_dist, dist[:, 0], rtol=1e-9)
    # Every edge is equidistant from its two sites; rays point away from the hull.
    finite = d.edges[:, 1] >= 0
    assert (~finite).sum() == len(ConvexHull(P).simplices)
    for (a, b), (s, t), direction in zip(d.edges, d.edge_sites, d.directions):
        for point in ([d.vertices[a]] if b < 0 else [d.vertices[a], d.vertices[b]]):
            assert np.linalg.norm(point - P[s]) == pytest.approx(np.linalg.norm(point - P[t]))
        if b < 0:
            assert np.linalg.norm(direction) == pytest.approx(1)
            far = d.vertices[a] + 100 * direction
            nearest_two = np.sort(np.linalg.norm(P - far, axis=1))[:2]
            assert nearest_two[0] == pytest.approx(np.linalg.norm(P[s] - far))
            assert nearest_two[1] == pytest.approx(np.linalg.norm(P[t] - far))


def test_voronoi_of_a_grid_gives_square_cells():
    x, y = np.meshgrid(np.arange(6.0), np.arange(5.0))
    P = np.column_stack([x.ravel(), y.ravel()])
    d = voronoi(P, bounds=(-0.5, -0.5, 5.5, 4.5))
    for site, cell in zip(P, d.cells):
        assert polygon_area(cell) == pytest.approx(1.0)
        np.testing.assert_allclose(cell.min(axis=0), site - 0.5, atol=1e-12)
        np.testing.assert_allclose(cell.max(axis=0), site + 0.5, atol=1e-12)


def test_voronoi_default_bounds_and_duplicates():
    P = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5], [1, 0]], dtype=float)
    d = voronoi(P)
    areas = [polygon_area(c) for c in d.cells]
    assert sum(areas[:5]) == pytest.approx(1.2 * 1.2)
    np.testing.assert_array_equal(d.cells[5], d.cells[1])
    with pytest.raises(InputError, match="bounds"):
        voronoi(P, bounds=(1, 0, 0, 1))


# --- Lawson flips -------------------------------------------------------------------------------
def cross2(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def fan_of_convex_polygon(n, rng):
    """Points in convex position (on an ellipse) and the fan triangulation from point 0."""
    t = np.sort(rng.random(n)) * 2 * np.pi
    P = np.column_stack([2 * np.cos(t), np.sin(t)])
    F = np.array([[0, i + 1, i] for i in range(1, n - 1)])  # clockwise: reoriented
    return P, F


def test_flip_to_delaunay_fan():
    P, F = fan_of_convex_polygon(25, np.random.default_rng(8))
    F_flipped, flips = flip_to_delaunay(P, F)
    assert flips > 0
    assert len(F_flipped) == len(F)
    assert_empty_circles(P, F_flipped)
    assert triangle_set(F_flipped) == triangle_set(ScipyDelaunay(P).simplices)


def test_flip_to_delaunay_of_scrambled_triangulation():
    rng = np.random.default_rng(9)
    P = rng.random((50, 2))
    F = ScipyDelaunay(P).simplices.copy()
    # Scramble: flip random interior edges whose quad is convex, making it non-Delaunay.
    for _ in range(300):
        f = rng.integers(len(F))
        c = rng.integers(3)
        p, q = F[f, (c + 1) % 3], F[f, (c + 2) % 3]
        others = [g for g in range(len(F)) if g != f and p in F[g] and q in F[g]]
        if not others:
            continue
        g = others[0]
        a, d = F[f, c], [v for v in F[g] if v not in (p, q)][0]
        t1, t2 = np.array([a, p, d]), np.array([a, d, q])
        o1 = cross2(P[t1[1]] - P[t1[0]], P[t1[2]] - P[t1[0]])
        o2 = cross2(P[t2[1]] - P[t2[0]], P[t2[2]] - P[t2[0]])
        if np.sign(o1) == np.sign(o2) and o1 != 0 and o2 != 0:
            s = np.sign(cross2(P[p] - P[a], P[q] - P[a]))
            if np.sign(o1) == s:
                F[f], F[g] = t1, t2
    assert triangle_set(F) != triangle_set(ScipyDelaunay(P).simplices)
    F_flipped, flips = flip_to_delaunay(P, F)
    assert flips > 0 and len(F_flipped) == len(F)
    assert_empty_circles(P, F_flipped)
    assert triangle_set(F_flipped) == triangle_set(ScipyDelaunay(P).simplices)


def test_flip_to_delaunay_cocircular_terminates_without_flips():
    x, y = np.meshgrid(np.arange(5.0), np.arange(5.0))
    P = np.column_stack([x.ravel(), y.ravel()])
    F, _ = delaunay(P)
    F2, flips = flip_to_delaunay(P, F)
    assert flips == 0
    assert triangle_set(F2) == triangle_set(F)
    # A square split by either diagonal is already Delaunay (cocircular): no flip back and forth.
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    for F in ([[0, 1, 2], [0, 2, 3]], [[0, 1, 3], [1, 2, 3]]):
        assert flip_to_delaunay(square, np.array(F))[1] == 0


@pytest.mark.parametrize("F, message", [
    ([[0, 1, 5]], "outside"),
    ([[0, 1, 1]], "degenerate"),
    ([[0, 1, 2], [0, 1, 3], [0, 1, 4]], "more than two"),
    ([[0, 1, 2], [0, 1, 4]], "overlap"),
])
def test_flip_to_delaunay_bad_input(F, message):
    V = np.array([[0, 0], [1, 0], [0, 1], [1, -1], [0.5, 1]], dtype=float)
    with pytest.raises(InputError, match=message):
        flip_to_delaunay(V, np.array(F))


# --- refinement ---------------------------------------------------------------------------------
def near_small_input_angle(V, F, corner, radius):
    """Triangles with a vertex within `radius` of the small-angle input corner."""
    return np.any(np.linalg.norm(V[F] - corner, axis=2) < radius, axis=1)


@pytest.mark.parametrize("min_angle", [20.7, 30.0])
@pytest.mark.parametrize("domain", ["square_with_hole", "letter_e"])
def test_refine_meets_min_angle(domain, min_angle):
    if domain == "square_with_hole":
        P, segments, holes = square_with_hole()
        area = 12.0
    else:
        (P, segments), holes = letter_e(), None
        area = 25 - 2 * 3.8 - 1
    V, F, steiner = refine(P, segments, holes, min_angle=min_angle)
    assert steiner == len(V) - len(P) > 0
    np.testing.assert_array_equal(V[: len(P)], P)
    assert np.all(signed_areas(V, F) > 0)
    assert signed_areas(V, F).sum() == pytest.approx(area)
    assert min_angles_degrees(V, F).min() >= min_angle - 1e-9
    assert_segments_are_edges(V, F, P, segments)
    assert flip_to_delaunay(V, F)[1] == 0  # every interior edge is locally Delaunay (exact)
    assert euler_characteristic(F) == (0 if domain == "square_with_hole" else 1)


@pytest.mark.parametrize("min_angle", [20.7, 30.0])
def test_refine_small_input_angle(min_angle):
    P, segments = sharp_wedge()
    V, F, _ = refine(P, segments, None, min_angle=min_angle)
    assert signed_areas(V, F).sum() == pytest.approx(abs(polygon_area(P)))
    assert_segments_are_edges(V, F, P, segments, tolerance=1e-12)
    # Up to and including the concentric shell at half the segment length: Triangle's rule leaves
    # a skinny triangle whose shortest edge spans the wedge between two points of one shell.
    away = ~near_small_input_angle(V, F, P[0], radius=0.501 * np.linalg.norm(P[1] - P[0]))
    assert min_angles_degrees(V, F)[away].min() >= min_angle - 1e-9


def test_refine_max_area():
    P, segments = letter_e()
    V, F, _ = refine(P, segments, max_area=0.05)
    assert signed_areas(V, F).max() <= 0.05
    assert signed_areas(V, F).sum() == pytest.approx(25 - 2 * 3.8 - 1)


def test_refine_bad_input_and_guard():
    P, segments = letter_e()
    for bad in (0.0, -5.0, 40.0, np.nan):
        with pytest.raises(InputError, match="min_angle"):
            refine(P, segments, min_angle=bad)
    with pytest.raises(InputError, match="max_area"):
        refine(P, segments, max_area=-1.0)
    with pytest.raises(SolverError, match="max_steiner_points"):
        refine(P, segments, max_area=1e-4, max_steiner_points=100)
    with pytest.raises(InputError, match="outside"):
        refine(P, np.array([[0, 99]]))


@pytest.mark.parametrize("seed", range(3))
def test_refine_random_points_fills_the_hull(seed):
    P = np.random.default_rng(seed).random((40, 2))
    for bound in (20.7, 30.0, 33.0):
        V, F, steiner = refine(P, None, min_angle=bound)
        assert steiner > 0
        assert signed_areas(V, F).sum() == pytest.approx(ConvexHull(P).volume, rel=1e-12)
        assert min_angles_degrees(V, F).min() >= bound - 1e-9
        assert flip_to_delaunay(V, F)[1] == 0


def test_refine_crossing_segments():
    P = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [0.3, 0.2], [1.7, 1.9]], dtype=float)
    segments = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [0, 2], [1, 3], [4, 5]])
    V, F, steiner = refine(P, segments, min_angle=25.0)
    assert signed_areas(V, F).sum() == pytest.approx(4)
    assert_segments_are_edges(V, F, P, segments, tolerance=1e-12)
    # Segment 4-5 crosses both diagonals at 5.5°: those two crossings are small input angles.
    d = P[5] - P[4]
    crossings = [P[4] + d * (P[4, 1] - P[4, 0]) / (d[0] - d[1]),                 # with y = x
                 P[4] + d * (2 - P[4, 0] - P[4, 1]) / (d[0] + d[1])]          # with y = 2 - x
    for c in crossings:
        assert np.min(np.linalg.norm(V - c, axis=1)) < 1e-12
    bad = min_angles_degrees(V, F) < 25.0 - 1e-9
    centroids = V[F[bad]].mean(axis=1)
    near = np.min([np.linalg.norm(centroids - c, axis=1) for c in crossings], axis=0)
    assert np.all(near < 0.4)


def test_refine_progress_and_cancel():
    from meshsmith import Cancelled

    P, segments = letter_e()
    calls = []
    refine(P, segments, max_area=1e-3, progress=lambda f, stage: calls.append((f, stage)))
    assert calls and calls[-1] == (1.0, "refine")
    with pytest.raises(Cancelled):
        refine(P, segments, max_area=1e-4, progress=lambda f, stage: False)


# --- refinement near small input angles: it terminates, and only the clusters keep bad angles ----
def small_input_angles(P, segments):
    """(apex, end0, end1) for every two segments sharing an endpoint and meeting at less than 60°."""
    found = []
    for v in range(len(P)):
        ends = [int(t) for s in np.asarray(segments).tolist() for t in s if v in s and t != v]
        for i in range(len(ends)):
            for j in range(i + 1, len(ends)):
                d0, d1 = P[ends[i]] - P[v], P[ends[j]] - P[v]
                if d0 @ d1 > 0.5 * np.linalg.norm(d0) * np.linalg.norm(d1):
                    found.append((P[v], P[ends[i]], P[ends[j]]))
    return found


def on_closed_segment(x, a, b, tolerance=1e-12):
    d, e = b - a, x - a
    length2 = d @ d
    return abs(d[0] * e[1] - d[1] * e[0]) <= tolerance * length2 and -tolerance * length2 <= d @ e <= length2 * (1 + tolerance)


def assert_refined(V, F, P, segments, holes, min_angle):
    """A valid conforming mesh of the domain whose triangles meet min_angle, except those lying in
    the cluster of a small input angle (all three vertices on its two segments). Returns the
    number of those exceptions."""
    np.testing.assert_array_equal(V[: len(P)], P)
    assert np.all(np.isfinite(V)) and len(F) > 0
    assert np.all(signed_areas(V, F) > 0)
    reference = constrained_delaunay(P, segments, holes)
    assert signed_areas(V, F).sum() == pytest.approx(signed_areas(*reference).sum(), rel=1e-9)
    assert_segments_are_edges(V, F, P, segments, tolerance=1e-14)
    angles = min_angles_degrees(V, F)
    clusters = small_input_angles(P, segments)
    exceptions = np.flatnonzero(angles < min_angle - 1e-9)
    for f in exceptions:
        corners = V[F[f]]
        assert any(all(on_closed_segment(x, apex, e0) or on_closed_segment(x, apex, e1) for x in corners)
                   for apex, e0, e1 in clusters), \
            f"triangle {F[f]} ({angles[f]:.3g}°) is below the bound outside every small-angle cluster: {corners.tolist()}"
    return len(exceptions)


def issue_domain(order):
    """Issue 14's domain: a 1e-9 feature; orders 0132 and 0213 make segments cross 2.5e-10 from
    vertex 2, which leaves two slivers with 1e-9 rad and 1.2e-10 rad apexes (0132) or a 14°
    corner next to a 1e-9 triangle (0213)."""
    P = np.array([[0, 0], [1, 0], [1, 1e-9], [0.5, 2]], dtype=float)
    o = [int(c) for c in order]
    return P, np.array([[o[i], o[(i + 1) % 4]] for i in range(4)]), None


def wedge(degrees):
    """Two unit segments meeting at `degrees`, closed into a thin triangle."""
    a = np.radians(degrees)
    return np.array([[0, 0], [1, 0], [np.cos(a), np.sin(a)]]), np.array([[0, 1], [1, 2], [2, 0]]), None


def crack(degrees):
    """Two unit segments meeting at `degrees` inside a 3 x 3 square (meshed on both sides)."""
    a = np.radians(degrees)
    P = np.array([[-1, -1], [2, -1], [2, 2], [-1, 2], [0, 0], [1, 0], [np.cos(a), np.sin(a)]])
    return P, np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [4, 6]]), None


def star(points=12, inner=0.3):
    """A star polygon: 12 tips of 12.5° and 12 reflex corners."""
    t = np.linspace(0, 2 * np.pi, 2 * points, endpoint=False)
    r = np.where(np.arange(2 * points) % 2 == 0, 1.0, inner)
    n = 2 * points
    return np.c_[r * np.cos(t), r * np.sin(t)], np.array([[i, (i + 1) % n] for i in range(n)]), None


def fan(count=20, spread=40.0):
    """`count` segments from the centre of a square spread over `spread` degrees (2.1° apart)."""
    a = np.radians(np.linspace(0, spread, count))
    P = np.vstack([[[-2, -2], [2, -2], [2, 2], [-2, 2], [0, 0]], np.c_[np.cos(a), np.sin(a)]])
    return P, np.array([[0, 1], [1, 2], [2, 3], [3, 0]] + [[4, 5 + i] for i in range(count)]), None


def hole_near_boundary(gap=1e-9):
    """A square with a diamond hole whose lowest corner is `gap` above the square's bottom side."""
    P = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, gap], [0.7, 0.3], [0.5, 0.6], [0.3, 0.3]])
    S = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
    return P, S, np.array([[0.5, 0.3]])


@pytest.mark.parametrize("min_angle", [25.0, 30.0])
@pytest.mark.parametrize("order", ["0123", "0132", "0213"])
def test_refine_terminates_on_the_issue_domain(order, min_angle):
    import time

    P, segments, holes = issue_domain(order)
    start = time.perf_counter()
    V, F, steiner = refine(P, segments, holes, min_angle=min_angle)
    elapsed = time.perf_counter() - start
    assert elapsed < 2.0  # measured: under 0.02 s each (Triangle and CGAL's mesher do not finish on 0132)
    exceptions = assert_refined(V, F, P, segments, holes, min_angle)
    # Measured Steiner counts (exceptions): 0123: 117 (0) at 25°, 199 (1: the 28° input angle at
    # vertex 3) at 30°; 0132: 1 (2, the two slivers); 0213: 3 (2) and 7 (4).
    assert steiner <= {"0123": 400, "0132": 10, "0213": 20}[order]
    if order == "0123" and min_angle == 25.0:
        assert exceptions == 0  # no input angle below 25° there: the bound holds everywhere
    if order == "0132":
        assert len(F) == 2 and steiner == 1  # each sliver is one triangle: its small angle is its apex's


@pytest.mark.parametrize("min_angle", [20.7, 25.0, 30.0, 33.0])
@pytest.mark.parametrize("name, domain", [
    ("wedge 1e-3 degrees", wedge(1e-3)), ("wedge 1 degree", wedge(1.0)), ("wedge 5 degrees", wedge(5.0)),
    ("crack 1e-3 degrees", crack(1e-3)), ("crack 1 degree", crack(1.0)), ("crack 5 degrees", crack(5.0)),
    ("star", star()), ("fan of 2.1-degree angles", fan()), ("hole 1e-9 from the boundary", hole_near_boundary()),
])
def test_refine_terminates_near_small_angles_and_keeps_the_bound_elsewhere(name, domain, min_angle):
    P, segments, holes = domain
    V, F, steiner = refine(P, segments, holes, min_angle=min_angle)
    exceptions = assert_refined(V, F, P, segments, holes, min_angle)
    # Measured, at 20.7 / 25 / 30 / 33°: at most 122 / 168 / 468 / 3106 points (the 1e-3° crack; a
    # high bound grades slowly away from its 1.7e-5 wide mouth), in at most 16 ms.
    assert steiner < 5000
    if name.startswith("hole"):
        assert exceptions == 0  # a small feature, no small angle: graded, and the bound holds
    if name == "wedge 1e-3 degrees":
        assert steiner == 0 and exceptions == 1  # narrower than 0.5°: the wedge stays one triangle
    # The smallest angle is never far below the smallest input angle (measured: at most 0.03% below).
    smallest_input = min((np.degrees(np.arccos(np.clip((e0 - a) @ (e1 - a) / np.linalg.norm(e0 - a) /
                                                         np.linalg.norm(e1 - a), -1, 1)))
                          for a, e0, e1 in small_input_angles(P, segments)), default=min_angle)
    assert min_angles_degrees(V, F).min() >= 0.75 * min(smallest_input, min_angle)


def test_refine_with_an_area_bound_near_a_tiny_angle_meets_the_area_everywhere():
    P, segments, holes = crack(1e-3)
    V, F, steiner = refine(P, segments, holes, min_angle=30.0, max_area=0.01)
    assert signed_areas(V, F).max() <= 0.01
    assert_refined(V, F, P, segments, holes, 30.0)


def test_refine_cancels_within_a_second_of_the_callback_saying_so():
    """A refinement that would take minutes (letter E down to areas of 1e-7: 160M triangles)
    stops soon after the callback returns False or raises (the loop polls every 256 steps, the
    Progress throttle lets a call through every 50 ms)."""
    import time

    from meshsmith import Cancelled

    P, segments = letter_e()
    for answer in ("false", "raise"):
        calls, stopped_at = [], []

        def callback(fraction, stage):
            calls.append(fraction)
            if len(calls) < 5:
                return True
            stopped_at.append(time.perf_counter())
            if answer == "raise":
                raise KeyboardInterrupt  # what Ctrl-C raises inside the callback
            return False

        with pytest.raises(KeyboardInterrupt if answer == "raise" else Cancelled):
            refine(P, segments, max_area=1e-7, progress=callback)
        assert len(stopped_at) == 1 and time.perf_counter() - stopped_at[0] < 2.0
        assert all(0 <= f < 1 for f in calls) and calls == sorted(calls)


def test_refine_stops_on_sigint_without_a_callback():
    """Ctrl-C (SIGINT) during a long refinement with progress=None: KeyboardInterrupt within a
    second, in a child interpreter so a late signal cannot hit the test runner."""
    import subprocess
    import sys
    import textwrap

    code = textwrap.dedent("""
        import os, signal, threading, time
        import numpy as np
        from meshsmith.tessellation import refine
        outline = np.array([[0, 0], [5, 0], [5, 1], [1.2, 1], [1.2, 2], [4, 2], [4, 3], [1.2, 3],
                            [1.2, 4], [5, 4], [5, 5], [0, 5]], dtype=float)
        segments = np.array([[i, (i + 1) % 12] for i in range(12)])
        sent = []
        def interrupt():
            sent.append(time.perf_counter())
            os.kill(os.getpid(), signal.SIGINT)
        threading.Timer(0.5, interrupt).start()
        try:
            refine(outline, segments, max_area=1e-7)
            print("finished")
        except KeyboardInterrupt:
            print("interrupted after %.3f s" % (time.perf_counter() - sent[0]))
    """)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.stdout.startswith("interrupted after"), done.stdout + done.stderr
    assert float(done.stdout.split()[2]) < 2.0


def test_bad_hole_seeds_and_collinear_voronoi():
    P, segments, _ = square_with_hole()
    with pytest.raises(InputError, match="holes"):
        constrained_delaunay(P, segments, np.array([[np.inf, 0.0]]))
    with pytest.raises(InputError, match="collinear"):
        voronoi(np.array([[0, 0], [1, 1], [2, 2]], dtype=float))


@pytest.mark.parametrize("scale", [2.0 ** 700, 2.0 ** -700])
def test_constructions_are_scale_invariant(scale):
    """Huge or tiny coordinates: squared lengths would overflow / underflow in float64; the
    constructions work on exactly rescaled points, so the result is the scaled unit result."""
    P, segments = letter_e()
    V, F, steiner = refine(P, segments, min_angle=30.0)
    V2, F2, steiner2 = refine(P * scale, segments, min_angle=30.0)
    assert steiner2 == steiner
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_array_equal(V2, V * scale)
    rng = np.random.default_rng(10)
    Q = rng.random((30, 2))
    cells = voronoi(Q * scale).cells
    box_area = np.prod(1.2 * (Q.max(axis=0) - Q.min(axis=0)))  # default bounds: +10% each side
    assert sum(polygon_area(c / scale) for c in cells) == pytest.approx(box_area, rel=1e-9)
