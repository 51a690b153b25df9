"""Coordinates near the ends of the float range (issue 14, part 1): scale-invariant algorithms give
the unscaled answer, scaled exactly, for inputs scaled by a power of two (2^±997 ≈ 1e±300,
2^±498 ≈ 1e±150), and within rounding for decimal factors (1e±300); quantities that cannot fit a
double say so with InputError; degenerate point sets and small input angles terminate.

Scale factors are powers of two where the comparison is exact: the normalization
(core/normalization.h) makes the computation bit-identical, so outputs of unit length^p must equal
the unscaled ones times 2^(p·k) exactly.
"""
import math
import multiprocessing
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import meshsmith
from meshsmith import datasets

POWERS = [-997, -498, 498, 997]  # 2^-997 ≈ 1.5e-300, 2^997 ≈ 1.3e300
DECIMAL = [1e-300, 1e-150, 1e150, 1e300]


def scaled(X, k):
    return np.ldexp(np.asarray(X, dtype=float), k)


def assert_scaled_exactly(result, reference, k, power):
    """result == reference · 2^(power·k), bit for bit."""
    np.testing.assert_array_equal(result, np.ldexp(reference, power * k))


def run_child(code: str, timeout: float):
    """Runs `code` in a fresh interpreter; returns (exit code, stdout) or fails on a timeout (a hang)."""
    try:
        done = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        pytest.fail(f"did not finish within {timeout} s (a hang)")
    return done.returncode, done.stdout + done.stderr


# --- points: kd-tree ---------------------------------------------------------------------------

@pytest.mark.parametrize("k", POWERS + [1020])
def test_knn_is_exactly_scale_covariant(k):
    P, _ = datasets.sphere_points(400, seed=2)
    indices, distances = meshsmith.points.knn(P, 8)
    scaled_indices, scaled_distances = meshsmith.points.knn(scaled(P, k), 8)
    assert scaled_indices.max() < len(P)
    np.testing.assert_array_equal(scaled_indices, indices)
    assert_scaled_exactly(scaled_distances, distances, k, 1)


@pytest.mark.parametrize("factor", [1e200, 1e300, 1e-300])
def test_knn_at_decimal_scales_returns_valid_neighbours(factor):
    P, _ = datasets.sphere_points(400, seed=2)
    indices, distances = meshsmith.points.knn(P, 8)
    scaled_indices, scaled_distances = meshsmith.points.knn(P * factor, 8)
    assert scaled_indices.min() >= 0 and scaled_indices.max() < len(P)
    assert np.all(np.isfinite(scaled_distances))
    np.testing.assert_allclose(scaled_distances / factor, distances, rtol=1e-12)
    if factor < 1:
        return  # a far query of tiny points: test_knn_query_far_outside_tiny_points
    # A query given explicitly, at 1e308, far from the points.
    Q = np.array([[1e308, 0.0, 0.0]])
    far_indices, far_distances = meshsmith.points.knn(P * factor, 3, Q)
    assert far_indices.max() < len(P) and np.all(np.isfinite(far_distances))
    np.testing.assert_allclose(far_distances[0], np.linalg.norm(Q[0] / 1e300 - P[far_indices[0]] * (factor / 1e300), axis=1) * 1e300,
                               rtol=1e-12)


def test_knn_query_far_outside_tiny_points():
    """A query 1e300 away from points of size 1e-300: the neighbours are those furthest along it."""
    P, _ = datasets.sphere_points(200, seed=4)
    Q = np.array([[1e300, 0.0, 0.0]])
    indices, distances = meshsmith.points.knn(P * 1e-300, 5, Q)
    assert set(indices[0]) == set(np.argsort(-P[:, 0])[:5])
    np.testing.assert_allclose(distances[0], 1e300, rtol=1e-12)


@pytest.mark.parametrize("kind", ["zero", "one", "ulps"])
def test_a_million_coincident_points_do_not_hang_the_kd_tree(kind):
    code = f"""
        import numpy as np, meshsmith
        n = 1_000_000
        if "{kind}" == "zero":
            P = np.zeros((n, 3))
        elif "{kind}" == "one":
            P = np.full((n, 3), 1e300)
        else:  # nearly coincident: within two units in the last place of 1
            P = 1 + np.random.default_rng(0).integers(-2, 3, (n, 3)) * np.spacing(1.0)
        indices, distances = meshsmith.points.knn(P, 8)
        assert indices.min() >= 0 and indices.max() < n
        assert not np.any(indices == np.arange(n)[:, None])
        assert np.all(distances <= 8 * np.spacing(1.0) * (1e300 if "{kind}" == "one" else 1))
        N = meshsmith.points.estimate_normals(P, 8)
        assert np.all(np.isfinite(N))
        print("ok")
    """
    code_returned, output = run_child(code, timeout=120)
    assert code_returned == 0 and "ok" in output, output


def test_radius_query_at_extreme_scales():
    P, _ = datasets.sphere_points(300, seed=5)
    tree = meshsmith.points.KdTree(P)
    offsets, indices, distances = tree.query_radius(P[:20], 0.3)
    for k in (-997, 997):
        big = meshsmith.points.KdTree(scaled(P, k))
        o, i, d = big.query_radius(scaled(P[:20], k), math.ldexp(0.3, k))
        np.testing.assert_array_equal(o, offsets)
        np.testing.assert_array_equal(i, indices)
        assert_scaled_exactly(d, distances, k, 1)


# --- decimation ----------------------------------------------------------------------------------

def bumpy_sphere():
    V, F = datasets.icosphere(3)
    return V * (1 + 0.1 * np.sin(5 * V[:, :1]) * np.cos(3 * V[:, 1:2])), F


@pytest.mark.parametrize("k", POWERS + [1020])
@pytest.mark.parametrize("options", [dict(target_faces=200), dict(target_faces=200, operator="halfedge"),
                                     dict(target_faces=200, candidates=8), dict(target_faces=200, parallel=False)])
def test_decimate_is_exactly_scale_covariant(k, options):
    V, F = bumpy_sphere()
    V1, F1 = meshsmith.decimation.decimate(V, F, **options)
    Vk, Fk = meshsmith.decimation.decimate(scaled(V, k), F, **options)
    np.testing.assert_array_equal(Fk, F1)
    assert_scaled_exactly(Vk, V1, k, 1)


def test_decimate_max_error_is_in_input_units():
    V, F = bumpy_sphere()
    _, F1, report1 = meshsmith.decimation.decimate(V, F, max_error=1e-4, return_report=True)
    _, Fk, reportk = meshsmith.decimation.decimate(scaled(V, 498), F, max_error=math.ldexp(1e-4, 996),
                                                   return_report=True)
    np.testing.assert_array_equal(Fk, F1)
    assert reportk.max_error == math.ldexp(report1.max_error, 996)


@pytest.mark.parametrize("factor", DECIMAL + [1e155, 1e308 / 2])
def test_decimate_and_progressive_meshes_at_decimal_scales(factor):
    V, F = bumpy_sphere()
    V1, F1 = meshsmith.decimation.decimate(V, F, target_faces=200)
    Vk, Fk = meshsmith.decimation.decimate(V * factor, F, target_faces=200)
    assert len(Fk) == len(F1) and np.all(np.isfinite(Vk))
    pm = meshsmith.decimation.progressive_mesh(V * factor, F)
    full_V, full_F = pm.mesh(pm.max_level) if hasattr(pm, "max_level") else (None, None)
    if full_V is not None:
        np.testing.assert_array_equal(full_V, V * factor)


def test_decimate_terminates_on_coincident_and_far_vertices():
    V, F = bumpy_sphere()
    for W in (np.zeros_like(V), np.full_like(V, 1e300), np.vstack([V[:-1], [[1e300, 1e300, 1e300]]])):
        V2, F2 = meshsmith.decimation.decimate(W, F, target_faces=100)
        assert np.all(np.isfinite(V2)) and len(F2) <= len(F)


@pytest.mark.parametrize("k", [-997, 997])
def test_cluster_is_exactly_scale_covariant(k):
    V, F = bumpy_sphere()
    reference = meshsmith.decimation.cluster(V, F, target_vertices=80)
    result = meshsmith.decimation.cluster(scaled(V, k), F, target_vertices=80)
    np.testing.assert_array_equal(result.F, reference.F)
    assert_scaled_exactly(result.V, reference.V, k, 1)
    assert result.cell_size == math.ldexp(reference.cell_size, k)


# --- parametrization -------------------------------------------------------------------------

def curved_disk():
    V, F = datasets.disk(6, 24)
    V = V.copy()
    V[:, 2] = 0.3 * V[:, 0] ** 2 - 0.2 * V[:, 1] ** 2
    return V, F


@pytest.mark.parametrize("k", POWERS)
@pytest.mark.parametrize("name, call, power", [
    ("harmonic uniform", lambda V, F: meshsmith.parametrization.harmonic(V, F), 0),
    ("harmonic cotan", lambda V, F: meshsmith.parametrization.harmonic(V, F, weights="cotan"), 0),
    ("harmonic mean value", lambda V, F: meshsmith.parametrization.harmonic(V, F, weights="mean_value"), 0),
    ("lscm", lambda V, F: meshsmith.parametrization.lscm(V, F), 1),
    ("lscm spectral", lambda V, F: meshsmith.parametrization.lscm_spectral(V, F), 1),
    ("stretch", lambda V, F: meshsmith.parametrization.stretch_minimizing(V, F, iterations=3).uv, 0),
    ("abf++", lambda V, F: meshsmith.parametrization.abf(V, F).uv, 1),
    ("map_boundary", lambda V, F: meshsmith.parametrization.map_boundary(V, F)[1], 0),
])
def test_parametrizations_are_exactly_scale_covariant(k, name, call, power):
    V, F = curved_disk()
    reference = call(V, F)
    assert_scaled_exactly(call(scaled(V, k), F), reference, k, power)


@pytest.mark.parametrize("k", [-997, 997, 1020])
def test_cut_to_disk_and_parametrize_a_closed_mesh_at_extreme_scales(k):
    V, F = bumpy_sphere()
    reference = meshsmith.parametrization.cut_to_disk(V, F)
    cut = meshsmith.parametrization.cut_to_disk(scaled(V, k), F)
    np.testing.assert_array_equal(cut.F, reference.F)
    assert_scaled_exactly(cut.V, reference.V, k, 1)
    uv = meshsmith.parametrization.lscm(cut.V, cut.F)
    assert_scaled_exactly(uv, meshsmith.parametrization.lscm(reference.V, reference.F), k, 1)


# --- geometry ------------------------------------------------------------------------------

@pytest.mark.parametrize("k", POWERS)
def test_face_areas_and_volume_scale_exactly_or_say_what_overflows(k):
    V, F = bumpy_sphere()
    areas = meshsmith.geometry.face_areas(V, F)
    volume = meshsmith.geometry.volume(V, F)
    if 2 * k < 1024:
        assert_scaled_exactly(meshsmith.geometry.face_areas(scaled(V, k), F), areas, k, 2)
        assert meshsmith.geometry.surface_area(scaled(V, k), F) == math.ldexp(
            meshsmith.geometry.surface_area(V, F), 2 * k)
    else:
        with pytest.raises(meshsmith.InputError, match="area of face 0 exceeds the double range"):
            meshsmith.geometry.face_areas(scaled(V, k), F)
    if abs(3 * k) < 1020:
        assert meshsmith.geometry.volume(scaled(V, k), F) == math.ldexp(volume, 3 * k)
    elif k > 0:
        with pytest.raises(meshsmith.InputError, match="volume"):
            meshsmith.geometry.volume(scaled(V, k), F)


def test_face_areas_keep_small_faces_next_to_a_far_vertex():
    V, F = bumpy_sphere()
    areas = meshsmith.geometry.face_areas(V, F)
    far = V.copy()
    far[0] = [1e150, 0.0, 0.0]
    with_far = meshsmith.geometry.face_areas(far, F)
    untouched = ~np.any(F == 0, axis=1)
    np.testing.assert_array_equal(with_far[untouched], areas[untouched])
    assert np.all(np.isfinite(with_far))


# --- tessellation: refinement near small input angles ------------------------------------------

def test_refine_terminates_near_a_tiny_feature():
    P = np.array([[0, 0], [1, 0], [1, 1e-9], [0.5, 2]], float)
    for order in ([0, 1, 2, 3], [0, 1, 3, 2], [0, 2, 1, 3]):
        S = np.array([[order[i], order[(i + 1) % 4]] for i in range(4)])
        code = f"""
            import numpy as np, meshsmith
            P = np.array({P.tolist()}); S = np.array({S.tolist()})
            try:
                V, F = meshsmith.tessellation.refine(P, S, min_angle=25)[:2]
                assert np.all(np.isfinite(V)) and len(F) > 0
                print("ok", len(V))
            except meshsmith.SolverError as error:
                print("ok", error)
        """
        returned, output = run_child(code, timeout=120)
        assert returned == 0 and output.startswith("ok"), output


def on_segment(x, a, b):
    d, e = b - a, x - a
    return abs(d[0] * e[1] - d[1] * e[0]) <= 1e-9 * np.dot(d, d) and -1e-12 <= np.dot(d, e) <= np.dot(d, d) * (1 + 1e-12)


def test_refine_leaves_triangles_in_a_small_input_angle_alone():
    """The triangles left below the bound sit against the segments of an apex where segments meet at
    less than 60° (here a 0.06° corner at the origin and two corners of the outer triangle)."""
    P = np.array([[0, 0], [1, 0], [1, 1e-3], [0.3, 0.9]])
    S = np.array([[0, 1], [1, 2], [2, 0], [0, 3], [3, 1]])
    V, F = meshsmith.tessellation.refine(P, S, min_angle=30)[:2]
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    lengths = np.stack([np.linalg.norm(b - c, axis=1), np.linalg.norm(c - a, axis=1), np.linalg.norm(a - b, axis=1)], 1)
    doubled_area = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    shortest = lengths.argmin(axis=1)
    longer = np.prod(lengths, axis=1) / lengths.min(axis=1)
    sine = doubled_area / longer
    bad = np.flatnonzero(sine < np.sin(np.radians(30)) * (1 - 1e-9))
    assert len(bad) > 0
    apexes = []
    for v in range(len(P)):
        ends = [int(t) for s_ in S for t in s_ if v in s_ and t != v]
        for i in range(len(ends)):
            for j in range(i + 1, len(ends)):
                d0, d1 = P[ends[i]] - P[v], P[ends[j]] - P[v]
                if np.dot(d0, d1) > 0.5 * np.linalg.norm(d0) * np.linalg.norm(d1):
                    apexes.append((P[v], P[ends[i]], P[ends[j]]))
    def distance_to_segment(x, a, b):
        t = np.clip(np.dot(x - a, b - a) / np.dot(b - a, b - a), 0, 1)
        return np.linalg.norm(x - (a + t * (b - a)))
    for f in bad:
        # Next to the segments of a small-angle apex: either Triangle's rule (the shortest edge
        # joins the two segments) or CGAL's cluster rule (a circumcentre that would encroach the
        # clustered segments is not inserted) left it.
        centroid = V[F[f]].mean(axis=0)
        assert min(distance_to_segment(centroid, apex, e) for apex, e0, e1 in apexes for e in (e0, e1)) < 0.25, f
    # Triangle's rule accounts for some of them: without it, they would be split.
    assert any(any((on_segment(V[F[f, (shortest[f] + 1) % 3]], apex, e0) and on_segment(V[F[f, (shortest[f] + 2) % 3]], apex, e1))
                   or (on_segment(V[F[f, (shortest[f] + 1) % 3]], apex, e1) and on_segment(V[F[f, (shortest[f] + 2) % 3]], apex, e0))
                   for apex, e0, e1 in apexes) for f in bad)


def test_refine_stops_when_no_step_makes_progress():
    P = np.array([[0, 0], [1, 0], [1, 1e-15], [0.5, 2]])
    S = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    code = f"""
        import numpy as np, meshsmith
        try:
            meshsmith.tessellation.refine(np.array({P.tolist()}), np.array({S.tolist()}), min_angle=34)
            print("ok finished")
        except meshsmith.SolverError as error:
            print("ok", error)
    """
    returned, output = run_child(code, timeout=120)
    assert returned == 0 and output.startswith("ok"), output


# --- curves ---------------------------------------------------------------------------------------

def helix():
    theta = np.linspace(0, 4 * np.pi, 60, endpoint=False)
    return np.c_[np.cos(theta), 0.5 * np.sin(theta), 0.2 * theta]


@pytest.mark.parametrize("k", POWERS)
@pytest.mark.parametrize("name, call, power", [
    ("arc_length", lambda P: meshsmith.curves.arc_length(P, closed=True), 1),
    ("resampling", lambda P: meshsmith.curves.arc_length_parametrization(P, 40), 1),
    ("tangents", lambda P: meshsmith.curves.tangents(P), 0),
    ("normals", lambda P: meshsmith.curves.normals(P), 0),
    ("turning angle", lambda P: meshsmith.curves.curvature(P), -1),
    ("osculating circle", lambda P: meshsmith.curves.curvature(P, method="osculating_circle"), -1),
    ("second difference", lambda P: meshsmith.curves.curvature(P, method="second_difference"), -1),
    ("signed 2D", lambda P: meshsmith.curves.curvature(P[:, :2], closed=True, signed=True), -1),
])
def test_curves_are_exactly_scale_covariant(k, name, call, power):
    P = helix()
    assert_scaled_exactly(call(scaled(P, k)), call(P), k, power)


def test_curves_keep_small_edges_next_to_a_far_point():
    P = helix()
    far = P.copy()
    far[-1] = [1e300, 0.0, 0.0]
    kappa, reference = meshsmith.curves.curvature(far), meshsmith.curves.curvature(P)
    np.testing.assert_allclose(kappa[1:-3], reference[1:-3], rtol=1e-12)
    assert np.all(np.isfinite(meshsmith.curves.tangents(far))) and np.all(np.isfinite(meshsmith.curves.normals(far)))
    np.testing.assert_allclose(meshsmith.curves.arc_length(far)[:-1], meshsmith.curves.arc_length(P)[:-1], rtol=1e-12)


def test_curvature_of_a_denormal_curve_says_it_overflows():
    with pytest.raises(meshsmith.InputError, match="curvature .* exceeds the double range"):
        meshsmith.curves.curvature(helix() * 1e-310)


# --- geometry: differential quantities ------------------------------------------------------------

@pytest.mark.parametrize("k", POWERS)
@pytest.mark.parametrize("name, call, power", [
    ("face normals", lambda V, F: meshsmith.geometry.face_normals(V, F), 0),
    ("angle normals", lambda V, F: meshsmith.geometry.vertex_normals(V, F), 0),
    ("area normals", lambda V, F: meshsmith.geometry.vertex_normals(V, F, weighting="area"), 0),
    ("cotan Laplacian", lambda V, F: meshsmith.geometry.cotan_laplacian(V, F).toarray(), 0),
    ("mean value Laplacian", lambda V, F: meshsmith.geometry.mean_value_laplacian(V, F).toarray(), -1),
    ("gaussian curvature", lambda V, F: meshsmith.geometry.gaussian_curvature(V, F), 0),
    ("mean curvature", lambda V, F: meshsmith.geometry.mean_curvature(V, F)[0], -1),
    ("quadric fit k1", lambda V, F: meshsmith.geometry.principal_curvatures(V, F)[0], -1),
    ("shape operator k2", lambda V, F: meshsmith.geometry.principal_curvatures(V, F, method="shape_operator")[1], -1),
])
def test_differential_quantities_are_exactly_scale_covariant(k, name, call, power):
    V, F = bumpy_sphere()
    assert_scaled_exactly(call(scaled(V, k), F), call(V, F), k, power)


@pytest.mark.parametrize("k", POWERS)
def test_vertex_areas_scale_exactly_or_say_what_overflows(k):
    V, F = bumpy_sphere()
    areas = meshsmith.geometry.vertex_areas(V, F)
    if 2 * k < 1020:
        assert_scaled_exactly(meshsmith.geometry.vertex_areas(scaled(V, k), F), areas, k, 2)
        values, vectors = meshsmith.geometry.laplacian_eigenpairs(scaled(V, k), F, 4) if abs(k) < 500 else (None, None)
        if values is not None:
            reference_values, reference_vectors = meshsmith.geometry.laplacian_eigenpairs(V, F, 4)
            np.testing.assert_allclose(np.ldexp(values[1:], 2 * k), reference_values[1:], rtol=1e-8)
    else:
        with pytest.raises(meshsmith.InputError, match="area of vertex 0 exceeds the double range"):
            meshsmith.geometry.vertex_areas(scaled(V, k), F)


def test_a_crossing_that_rounds_onto_a_vertex_is_an_input_error():
    """Segments 1-3 and 2-0 cross 2.5e-16 from vertex 2: the rounded intersection is unusable and
    CGAL would bend segment 1-3 through vertex 2 (refine then crashed with SIGSEGV)."""
    P = np.array([[0, 0], [1, 0], [1, 1e-15], [0.5, 2]])
    S = np.array([[0, 1], [1, 3], [3, 2], [2, 0]])
    code = f"""
        import numpy as np, meshsmith
        P, S = np.array({P.tolist()}), np.array({S.tolist()})
        for call in (lambda: meshsmith.tessellation.refine(P, S, min_angle=20),
                     lambda: meshsmith.tessellation.constrained_delaunay(P, S)):
            try:
                call()
                print("no error")
            except meshsmith.InputError as error:
                assert "cross so close to vertex" in str(error), error
        print("ok")
    """
    returned, output = run_child(code, timeout=120)
    assert returned == 0 and output.strip() == "ok", output


def test_crossing_and_overlapping_segments_still_triangulate():
    P = np.array([[0, 0], [2, 0], [1, -1], [1, 1], [3, 0], [0.5, 0], [2.5, 0]])
    S = np.array([[0, 1], [2, 3], [5, 6], [1, 4]])  # 0-1 crosses 2-3; 5-6 overlaps 0-1 and 1-4
    V, F = meshsmith.tessellation.constrained_delaunay(P, S)
    assert len(V) == len(P) + 1 and np.allclose(V[-1], [1, 0])  # the crossing
    V, F = meshsmith.tessellation.refine(P, S, min_angle=20)[:2]
    assert np.all(np.isfinite(V))


@pytest.mark.parametrize("k", POWERS + [1020])
def test_triangle_angles_are_scale_invariant(k):
    P = np.random.default_rng(1).random((50, 2))
    F = meshsmith.tessellation.delaunay(P)[0]
    np.testing.assert_array_equal(meshsmith.tessellation.triangle_angles(scaled(P, k), F),
                                  meshsmith.tessellation.triangle_angles(P, F))


@pytest.mark.parametrize("k", POWERS)
def test_triangle_distortion_is_exactly_scale_covariant(k):
    V, F = curved_disk()
    UV = meshsmith.parametrization.lscm(V, F)
    reference = meshsmith.geometry.triangle_distortion(V, F, UV)
    if 2 * k >= 1024:
        with pytest.raises(meshsmith.InputError, match="surface area of face 0"):
            meshsmith.geometry.triangle_distortion(scaled(V, k), F, scaled(UV, k))
        return
    both = meshsmith.geometry.triangle_distortion(scaled(V, k), F, scaled(UV, k))  # an isometry stays one
    for name in ("jacobians", "singular_values", "isometric", "conformal", "area", "stretch_l2"):
        np.testing.assert_array_equal(getattr(both, name), getattr(reference, name))
    assert_scaled_exactly(both.surface_areas, reference.surface_areas, k, 2)
    assert both.normalized_global_stretch_l2 == reference.normalized_global_stretch_l2
    surface_only = meshsmith.geometry.triangle_distortion(scaled(V, k), F, UV)  # J grows by 2^k
    assert_scaled_exactly(surface_only.jacobians, reference.jacobians, k, 1)
    assert surface_only.normalized_global_stretch_l2 == reference.normalized_global_stretch_l2


# --- tessellation: contouring by Voronoi filtering --------------------------------------------------

def ellipse_samples():
    theta = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    return np.c_[np.cos(theta), 0.5 * np.sin(theta)]


@pytest.mark.parametrize("k", POWERS + [1020])
def test_contouring_is_exactly_scale_covariant(k):
    S = ellipse_samples()
    np.testing.assert_array_equal(meshsmith.tessellation.crust(scaled(S, k)), meshsmith.tessellation.crust(S))
    vertices, edges = meshsmith.tessellation.medial_axis(S)
    scaled_vertices, scaled_edges = meshsmith.tessellation.medial_axis(scaled(S, k))
    np.testing.assert_array_equal(scaled_edges, edges)
    assert_scaled_exactly(scaled_vertices, vertices, k, 1)
    assert_scaled_exactly(meshsmith.tessellation.local_feature_size(scaled(S, k)),
                          meshsmith.tessellation.local_feature_size(S), k, 1)
    assert meshsmith.tessellation.sampling_ratio(scaled(S, k)) == meshsmith.tessellation.sampling_ratio(S)


@pytest.mark.parametrize("k", POWERS)
def test_crust_3d_is_scale_invariant(k):
    P, _ = datasets.sphere_points(300, seed=1)
    V, F = meshsmith.tessellation.crust_3d(P)
    Vk, Fk = meshsmith.tessellation.crust_3d(scaled(P, k))
    np.testing.assert_array_equal(Fk, F)
    np.testing.assert_array_equal(Vk, scaled(P, k))


@pytest.mark.parametrize("k", POWERS)
@pytest.mark.parametrize("measure", ["hausdorff_distance", "mean_surface_distance"])
def test_surface_distances_are_exactly_scale_covariant(k, measure):
    V, F = bumpy_sphere()
    W = V * 1.1 + 0.05
    call = getattr(meshsmith.geometry, measure)
    for sampled in (False, True):
        reference = call(V, F, W, F, sampled=sampled)
        result = call(scaled(V, k), F, scaled(W, k), F, sampled=sampled)
        np.testing.assert_array_equal(np.ldexp(np.asarray(reference, dtype=float), k), np.asarray(result, dtype=float))


def test_voronoi_vertex_beyond_the_double_range_is_an_input_error():
    P = np.random.default_rng(1).random((60, 2))
    P[0] = [1e300, 1e300]
    try:
        diagram = meshsmith.tessellation.voronoi(P)
    except meshsmith.InputError as error:
        assert "beyond the double range" in str(error)
    else:
        assert np.all(np.isfinite(diagram.vertices))


# --- topology.info: area and volume beyond the double range -------------------------------------

@pytest.mark.parametrize("k", [-498, 100, 498, 997])
def test_info_scales_area_and_volume_exactly_or_notes_the_overflow(k):
    V, F = bumpy_sphere()
    reference = meshsmith.topology.info(V, F)
    result = meshsmith.topology.info(scaled(V, k), F)  # never raises for the range
    assert (result.n_vertices, result.genus, result.is_manifold) == (reference.n_vertices, reference.genus, True)
    for name, power in (("surface_area", 2), ("volume", 3)):
        value, unscaled = getattr(result, name), getattr(reference, name)
        if math.frexp(unscaled)[1] + power * k < 1024:
            assert value == math.ldexp(unscaled, power * k), name
        else:
            assert value == math.copysign(math.inf, unscaled)
            assert any(name.replace("_", " ") in note and "beyond the double range" in note for note in result.notes)
    assert bool(result.notes) == (math.frexp(reference.volume)[1] + 3 * k >= 1024)
    assert ("note" in str(result)) == bool(result.notes)


def test_info_at_decimal_1e150_gives_the_area_and_an_infinite_volume():
    V, F = bumpy_sphere()
    reference = meshsmith.topology.info(V, F)
    result = meshsmith.topology.info(V * 1e150, F)
    assert math.isclose(result.surface_area, reference.surface_area * 1e300, rel_tol=1e-12)
    assert result.volume == math.inf and len(result.notes) == 1


@pytest.mark.parametrize("far", [1e150, 1e300])
def test_triangle_distortion_keeps_small_faces_next_to_a_far_vertex(far):
    """Each face in its own frame: the faces away from the far vertex give exactly what they give
    without it, every per-vertex figure is finite (they were NaN: the whole mesh's frame flushed the
    small faces to zero area), and the thin faces at the far vertex have their true area."""
    V, F = datasets.disk(3, 12)[:2]
    UV = V[:, :2].copy()
    reference = meshsmith.geometry.triangle_distortion(V, F, UV)
    moved = V.copy()
    moved[0] = [far, 0.0, 0.0]
    result = meshsmith.geometry.triangle_distortion(moved, F, UV)
    untouched = ~np.any(F == 0, axis=1)
    for name in ("isometric", "conformal", "area", "stretch_l2", "stretch_linf", "surface_areas"):
        np.testing.assert_array_equal(getattr(result, name)[untouched], getattr(reference, name)[untouched], err_msg=name)
    away = np.setdiff1d(np.arange(len(V)), F[~untouched].ravel())
    for name in ("vertex_isometric", "vertex_conformal", "vertex_area", "vertex_stretch_l2", "vertex_stretch_linf"):
        values = getattr(result, name)
        assert not np.any(np.isnan(values)), name  # inf only where a face's own figure is (1e300² at 1e300)
        per_face = getattr(result, name.replace("vertex_", ""))
        infinite_at = np.unique(F[~np.isfinite(per_face)])
        assert np.all(np.isfinite(np.delete(values, infinite_at))), name
        np.testing.assert_array_equal(values[away], getattr(reference, name)[away], err_msg=name)
    assert len(result.degenerate_surface_faces) == 0
    # A face (far vertex p, q, r) of the flat disk (z = 0): area 0.5 |det(q - p, r - p)|, which is
    # 0.5 · far · |q_y - r_y| to a relative 1e-150 or better.
    corners = moved[F[~untouched]]
    assert np.all(corners[:, :, 2] == 0)
    others = [np.delete(face, np.flatnonzero(F[~untouched][i] == 0)[0], axis=0) for i, face in enumerate(corners)]
    np.testing.assert_allclose(result.surface_areas[~untouched] / far,
                               [0.5 * abs(q[1] - r[1]) for q, r in others], rtol=1e-12)


# --- tessellation: power diagrams ------------------------------------------------------------------

@pytest.mark.parametrize("k", [-498, 498])
@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("weight_scale", [0.0, 0.01, -0.05, 1.0])
def test_power_diagram_is_exactly_scale_covariant(k, d, weight_scale):
    """Sites times 2^k, weights (squared radii) times 2^2k, bounds times 2^k: the same regular
    triangulation and hidden sites, every cell corner times 2^k bit for bit. (At 2^±997 the
    weights themselves leave the double range.)"""
    rng = np.random.default_rng(3 + d)
    P, w = rng.random((60, d)), weight_scale * rng.random(60)
    bounds = meshsmith.tessellation.default_bounds(P)
    reference = meshsmith.tessellation.power_diagram(P, w)
    for result in (meshsmith.tessellation.power_diagram(scaled(P, k), np.ldexp(w, 2 * k)),
                   meshsmith.tessellation.power_diagram(scaled(P, k), np.ldexp(w, 2 * k), bounds=scaled(bounds, k))):
        np.testing.assert_array_equal(result.triangulation, reference.triangulation)
        np.testing.assert_array_equal(result.hidden, reference.hidden)
        for cell, unscaled in zip(result.cells, reference.cells):
            if d == 2:
                assert_scaled_exactly(cell, unscaled, k, 1)
            else:
                assert_scaled_exactly(cell[0], unscaled[0], k, 1)
                np.testing.assert_array_equal(cell[1], unscaled[1])


# --- parametrization with one far vertex: refused, with the reason ------------------------------

@pytest.mark.parametrize("method", ["lscm", "harmonic", "abf"])
def test_parametrizing_with_one_far_vertex_names_the_vertex_and_the_scales(method):
    """The maps solve one system over the whole mesh in one frame: with vertex 7 at 1e150 the unit
    faces' areas are below the double range there. The message says so (a collinear face still
    gets the plain 'zero area' message)."""
    V, F = datasets.disk(3, 12)[:2]
    far = V.copy()
    far[7] = [1e150, 0.0, 0.0]
    with pytest.raises(meshsmith.InputError, match=rf"{method}: face \d+ is about 2\^\d+ times smaller than the mesh, "
                                                   r"whose largest coordinate is at vertex 7: one linear system"):
        getattr(meshsmith.parametrization, method)(far, F)
    flat = V.copy()
    flat[F[0, 2]] = (flat[F[0, 0]] + flat[F[0, 1]]) / 2  # face 0 collinear
    with pytest.raises(meshsmith.InputError, match=r"face \d+ has zero area \(collinear corners\)"):
        getattr(meshsmith.parametrization, method)(flat, F)


@pytest.mark.parametrize("k", [0, 498, 520, 600, 997])
def test_decimation_report_states_max_error_beyond_the_double_range(k):
    """max_error is in input units (inf from ~1e154 on: a length² cost), and
    max_error_normalized · 2^max_error_exponent states it exactly at every scale."""
    V, F = bumpy_sphere()
    reference = meshsmith.decimation.decimate(V, F, target_faces=200, return_report=True).report
    report = meshsmith.decimation.decimate(scaled(V, k), F, target_faces=200, return_report=True).report
    assert report.max_error_normalized == reference.max_error_normalized > 0
    assert report.max_error_exponent == reference.max_error_exponent + 2 * k
    assert math.ldexp(reference.max_error_normalized, reference.max_error_exponent) == reference.max_error
    if math.frexp(reference.max_error)[1] + 2 * k < 1024:
        assert report.max_error == math.ldexp(reference.max_error, 2 * k)
    else:
        assert report.max_error == math.inf
