"""geometry metrics: parametrization distortion (§1.2.2, §5) and surface distances (Hausdorff,
mean surface distance, AABB closest points) against numpy, libigl and analytic truth."""
import igl
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets
from meshsmith.geometry import (SurfaceDistance, hausdorff_distance, mean_surface_distance,
                                triangle_distortion)


# ---------------------------------------------------------------- helpers (independent of the core)

def reference_jacobians(V, F, UV):
    """J of the affine map UV triangle -> 3D triangle in the frame x = e1/|e1|, y = n x x."""
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    n = np.cross(e1, e2)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    x = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
    y = np.cross(n, x)
    D3 = np.stack([np.stack([(e1 * x).sum(1), (e2 * x).sum(1)], -1),
                   np.stack([(e1 * y).sum(1), (e2 * y).sum(1)], -1)], 1)
    Duv = np.stack([UV[F[:, 1]] - UV[F[:, 0]], UV[F[:, 2]] - UV[F[:, 0]]], -1)
    return D3 @ np.linalg.inv(Duv)


def jittered_grid(n=12, amount=0.25, seed=1):
    V, F = datasets.grid(n, n)
    rng = np.random.default_rng(seed)
    V = V.copy()
    V[:, :2] += rng.uniform(-amount, amount, size=(len(V), 2)) / n
    return V, F


def rotation(seed):
    Q, R = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(R))
    return Q if np.linalg.det(Q) > 0 else -Q


def area_weighted_vertex_average(F, n, weights, values):
    total, weight = np.zeros(n), np.zeros(n)
    for k in range(3):
        np.add.at(total, F[:, k], weights * values)
        np.add.at(weight, F[:, k], weights)
    return total / weight


# ---------------------------------------------------------------- triangle_distortion

def test_identity_map_has_unit_singular_values_and_measures():
    V, F = jittered_grid()
    d = triangle_distortion(V, F, V[:, :2])
    assert d.jacobians.shape == (len(F), 2, 2) and d.singular_values.shape == (len(F), 2)
    np.testing.assert_allclose(d.singular_values, 1.0, atol=1e-12)
    np.testing.assert_allclose(np.einsum("fki,fkj->fij", d.jacobians, d.jacobians),
                               np.broadcast_to(np.eye(2), (len(F), 2, 2)), atol=1e-12)
    for measure in (d.isometric, d.conformal, d.area, d.stretch_l2, d.stretch_linf,
                    d.vertex_isometric, d.vertex_conformal, d.vertex_area, d.vertex_stretch_l2):
        np.testing.assert_allclose(measure, 1.0, atol=1e-12)
    assert d.global_stretch_l2 == pytest.approx(1.0, abs=1e-12)
    assert d.normalized_global_stretch_l2 == pytest.approx(1.0, abs=1e-12)
    assert not d.flipped.any() and d.flipped_faces.size == 0
    assert d.degenerate_parameter_faces.size == 0 and d.degenerate_surface_faces.size == 0


@pytest.mark.parametrize("s", [0.5, 3.0])
def test_uniform_scaling(s):
    V, F = jittered_grid()
    d = triangle_distortion(s * V, F, V[:, :2])
    np.testing.assert_allclose(d.singular_values, s, rtol=1e-12)
    np.testing.assert_allclose(d.conformal, 1.0, rtol=1e-12)
    np.testing.assert_allclose(d.area, s * s, rtol=1e-12)
    np.testing.assert_allclose(d.stretch_l2, s, rtol=1e-12)
    np.testing.assert_allclose(d.stretch_linf, s, rtol=1e-12)
    np.testing.assert_allclose(d.isometric, (2 * s**2 + 2 / s**2) / 4, rtol=1e-12)
    assert d.global_stretch_l2 == pytest.approx(s, rel=1e-12)
    assert d.global_stretch_linf == pytest.approx(s, rel=1e-12)
    assert d.normalized_global_stretch_l2 == pytest.approx(1.0, rel=1e-12)  # scale-invariant


def test_non_uniform_scale_and_shear_have_analytic_singular_values():
    V, F = jittered_grid()
    UV = V[:, :2]
    d = triangle_distortion(np.c_[3.0 * UV[:, 0], 0.5 * UV[:, 1], np.zeros(len(V))], F, UV)
    np.testing.assert_allclose(d.singular_values, np.broadcast_to([3.0, 0.5], (len(F), 2)), rtol=1e-12)
    np.testing.assert_allclose(d.conformal, 6.0, rtol=1e-12)
    np.testing.assert_allclose(d.area, 1.5, rtol=1e-12)
    np.testing.assert_allclose(d.stretch_l2, np.sqrt((9 + 0.25) / 2), rtol=1e-12)

    k = 0.7  # shear [[1, k], [0, 1]]: sigma^2 = (2 + k^2 +- k sqrt(k^2 + 4)) / 2
    sheared = np.c_[UV[:, 0] + k * UV[:, 1], UV[:, 1], np.zeros(len(V))]
    d = triangle_distortion(sheared, F, UV)
    expected = np.sqrt([(2 + k * k + k * np.sqrt(k * k + 4)) / 2, (2 + k * k - k * np.sqrt(k * k + 4)) / 2])
    np.testing.assert_allclose(d.singular_values, np.broadcast_to(expected, (len(F), 2)), rtol=1e-12)
    np.testing.assert_allclose(d.area, 1.0, rtol=1e-12)  # a shear preserves area
    np.testing.assert_allclose(d.conformal, expected[0] / expected[1], rtol=1e-12)


def test_rotation_invariance_in_space_and_in_the_parameter_plane():
    V, F = datasets.icosphere(2)
    UV = V[:, :2] + 0.1 * V[:, 2:] ** 2  # some map; only its faces with a valid UV matter
    base = triangle_distortion(V, F, UV)
    moved = triangle_distortion(V @ rotation(3).T + [1.0, -2.0, 5.0], F, UV)
    c, s = np.cos(0.8), np.sin(0.8)
    turned = triangle_distortion(V, F, UV @ np.array([[c, -s], [s, c]]).T + [4.0, 1.0])
    for other in (moved, turned):
        np.testing.assert_allclose(other.singular_values, base.singular_values, rtol=1e-9)
        np.testing.assert_array_equal(other.flipped, base.flipped)
        assert other.global_stretch_l2 == pytest.approx(base.global_stretch_l2, rel=1e-12)


def test_jacobian_and_singular_values_match_numpy_svd_on_a_curved_surface():
    V, F = datasets.noisy(*datasets.grid(10, 10), sigma=0.0)
    V = V.copy()
    V[:, 2] = np.sin(3 * V[:, 0]) * np.cos(2 * V[:, 1])
    rng = np.random.default_rng(4)
    UV = 1.7 * V[:, :2] + rng.uniform(-0.02, 0.02, size=(len(V), 2))
    V = V @ rotation(5).T
    d = triangle_distortion(V, F, UV)
    J = reference_jacobians(V, F, UV)
    np.testing.assert_allclose(d.jacobians, J, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(d.singular_values, np.linalg.svd(J, compute_uv=False), rtol=1e-10)
    s1, s2 = d.singular_values.T
    np.testing.assert_allclose(d.stretch_l2, np.sqrt((s1**2 + s2**2) / 2), rtol=1e-12)
    np.testing.assert_allclose(d.isometric, (s1**2 + s2**2 + s1**-2 + s2**-2) / 4, rtol=1e-12)
    np.testing.assert_allclose(d.area, np.abs(np.linalg.det(J)), rtol=1e-10)
    areas = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    np.testing.assert_allclose(d.surface_areas, areas, rtol=1e-12)
    np.testing.assert_allclose(d.vertex_stretch_l2, area_weighted_vertex_average(F, len(V), areas, d.stretch_l2),
                               rtol=1e-12)
    np.testing.assert_allclose(d.vertex_conformal, area_weighted_vertex_average(F, len(V), areas, d.conformal),
                               rtol=1e-12)
    assert d.global_stretch_l2 == pytest.approx(np.sqrt((areas * d.stretch_l2**2).sum() / areas.sum()), rel=1e-12)
    # J^T J is the first fundamental form, computed here without any frame (§1.2.2).
    e = np.stack([V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]], -1)
    Duv_inv = np.linalg.inv(np.stack([UV[F[:, 1]] - UV[F[:, 0]], UV[F[:, 2]] - UV[F[:, 0]]], -1))
    first_form = np.transpose(Duv_inv, (0, 2, 1)) @ np.transpose(e, (0, 2, 1)) @ e @ Duv_inv
    np.testing.assert_allclose(np.transpose(J, (0, 2, 1)) @ J, first_form, rtol=1e-9, atol=1e-12)


def test_flipped_triangles_are_flagged():
    V, F = datasets.grid(6, 6)
    UV = V[:, :2].copy()
    centre = 3 * 7 + 3  # interior vertex (x index 3, y index 3)
    UV[centre] += [0.4, 0.0]  # pushed over its right neighbour's edges: some UV triangles turn clockwise
    d = triangle_distortion(V, F, UV)
    e1, e2 = UV[F[:, 1]] - UV[F[:, 0]], UV[F[:, 2]] - UV[F[:, 0]]
    signed = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    assert (signed < 0).any()
    np.testing.assert_array_equal(d.flipped, signed < 0)
    np.testing.assert_array_equal(d.flipped_faces, np.flatnonzero(signed < 0))
    np.testing.assert_allclose(d.parameter_areas, signed, atol=1e-15)
    assert (np.linalg.det(d.jacobians)[d.flipped] < 0).all()
    assert (np.linalg.det(d.jacobians)[~d.flipped] > 0).all()
    mirrored = triangle_distortion(V, F, V[:, :2] * [-1.0, 1.0])  # a mirror flips every triangle
    assert mirrored.flipped.all()
    np.testing.assert_allclose(mirrored.singular_values, 1.0, atol=1e-12)


def test_degenerate_parameter_triangle_is_infinite_and_listed_never_nan():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    F = np.array([[0, 1, 2], [1, 3, 2]])
    UV = np.array([[0.0, 0], [1, 0], [2, 0], [1, 1]])  # face 0 collinear in UV
    d = triangle_distortion(V, F, UV)
    np.testing.assert_array_equal(d.degenerate_parameter_faces, [0])
    for measure in (d.isometric, d.conformal, d.area, d.stretch_l2, d.stretch_linf):
        assert measure[0] == np.inf and np.isfinite(measure[1])
    assert np.isinf(d.singular_values[0]).all() and np.isinf(d.jacobians[0]).all()
    assert np.isinf(d.vertex_stretch_l2[[0, 1, 2]]).all() and np.isfinite(d.vertex_stretch_l2[3])
    assert d.global_stretch_l2 == np.inf
    for name, value in vars(d).items():
        assert not np.isnan(np.asarray(value, dtype=float)).any(), name


def test_degenerate_surface_triangle_has_zero_weight():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]])
    F = np.array([[0, 1, 2], [0, 3, 1]])  # face 1 has collinear 3D corners
    UV = np.array([[0.0, 0], [1, 0], [0, 1], [0.5, -1]])
    d = triangle_distortion(V, F, UV)
    np.testing.assert_array_equal(d.degenerate_surface_faces, [1])
    assert d.singular_values[1, 1] == 0 and d.singular_values[1, 0] > 0
    assert d.area[1] == 0 and d.conformal[1] == np.inf and d.isometric[1] == np.inf
    assert not d.flipped[1]
    np.testing.assert_allclose(d.singular_values[1, 0], np.linalg.svd(
        np.array([[2.0, 1.0], [0.0, 0.0]]) @ np.linalg.inv(np.array([[0.5, 1.0], [-1.0, 0.0]])),
        compute_uv=False)[0], rtol=1e-12)
    assert d.global_stretch_l2 == pytest.approx(1.0)  # only face 0, an isometry, has weight
    assert np.isnan(d.vertex_stretch_l2[3])  # documented: no incident face of positive area
    np.testing.assert_allclose(d.vertex_stretch_l2[:3], 1.0)


@pytest.mark.parametrize("UV, message", [
    (np.zeros((4, 3)), "UV has shape (4, 3)"),
    (np.zeros((3, 2)), "UV has 3 rows but V has 4"),
    (np.array([[0.0, 0], [1, 0], [0, np.nan], [1, 1]]), "UV[2, 1] is not finite"),
    (None, "UV is None"),
])
def test_distortion_bad_parameters(UV, message):
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    F = np.array([[0, 1, 2], [1, 3, 2]])
    with pytest.raises(meshsmith.InputError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")):
        triangle_distortion(V, F, UV)


def test_distortion_bad_mesh():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    with pytest.raises(meshsmith.InputError, match="F"):
        triangle_distortion(V, [[0, 1, 5]], V[:, :2])
    with pytest.raises(meshsmith.InputError, match="V"):
        triangle_distortion(np.where(V == 1, np.nan, V), [[0, 1, 2]], V[:, :2])


# ---------------------------------------------------------------- closest points, Hausdorff

def on_reported_face(V, F, faces, points, tolerance=1e-9):
    a, b, c = V[F[faces, 0]], V[F[faces, 1]], V[F[faces, 2]]
    T = np.stack([b - a, c - a], -1)
    coefficients, *_ = zip(*[np.linalg.lstsq(T[i], points[i] - a[i], rcond=None) for i in range(len(faces))])
    coefficients = np.array(coefficients)
    residual = np.linalg.norm(np.einsum("nij,nj->ni", T, coefficients) - (points - a), axis=1)
    bary = np.c_[1 - coefficients.sum(1), coefficients]
    return (residual < tolerance).all() and (bary > -tolerance).all()


def test_closest_points_agree_with_libigl(data_dir):
    V, F = meshsmith.io.read_mesh(data_dir / "bunny.off")
    lower, upper = V.min(0), V.max(0)
    rng = np.random.default_rng(0)
    Q = np.r_[rng.uniform(lower - 0.2 * (upper - lower), upper + 0.2 * (upper - lower), size=(3000, 3)),
              V[::7] + rng.normal(scale=1e-3, size=V[::7].shape)]
    tree = SurfaceDistance(V, F)
    assert tree.face_count == len(F)
    distance, face, point = tree.closest_points(Q)
    squared, igl_face, igl_point = igl.point_mesh_squared_distance(Q, V, F)
    scale = np.linalg.norm(upper - lower)
    np.testing.assert_allclose(distance**2, squared, rtol=1e-10, atol=1e-10 * scale**2)
    np.testing.assert_allclose(point, igl_point, atol=1e-10 * scale)
    assert face.dtype == np.int64 and face.shape == (len(Q),)
    assert on_reported_face(V, F, face, point, 1e-9 * scale)
    np.testing.assert_array_equal(tree.distances(Q), distance)
    for leaf_size in (1, 16):  # the tree shape changes, the distances do not
        np.testing.assert_allclose(SurfaceDistance(V, F, leaf_size=leaf_size).distances(Q), distance, rtol=0, atol=1e-14 * scale)


def test_closest_points_analytic_and_empty():
    V, F = datasets.grid(4, 4)  # unit square in z = 0
    tree = SurfaceDistance(V, F)
    Q = np.array([[0.3, 0.6, 2.0], [0.3, 0.6, -0.5], [2.0, 0.5, 0.0], [-1.0, -1.0, 1.0], [0.25, 0.5, 0.0]])
    distance, face, point = tree.closest_points(Q)
    np.testing.assert_allclose(distance, [2.0, 0.5, 1.0, np.sqrt(3.0), 0.0], atol=1e-15)
    np.testing.assert_allclose(point, [[0.3, 0.6, 0], [0.3, 0.6, 0], [1, 0.5, 0], [0, 0, 0], [0.25, 0.5, 0]],
                               atol=1e-15)
    distance, face, point = tree.closest_points(np.zeros((0, 3)))
    assert distance.shape == (0,) and face.shape == (0,) and point.shape == (0, 3)


def test_hausdorff_agrees_with_libigl_on_bunny(data_dir):
    V, F = meshsmith.io.read_mesh(data_dir / "bunny.off")
    Vn, Fn = datasets.noisy(V, F, sigma=0.2, seed=3, direction="isotropic")
    ours = hausdorff_distance(V, F, Vn, Fn)
    reference = igl.hausdorff(V, F, Vn, Fn)
    assert ours == pytest.approx(reference, rel=1e-10)
    symmetric, a_to_b, b_to_a = hausdorff_distance(V, F, Vn, Fn, one_sided=True)
    assert symmetric == ours == max(a_to_b, b_to_a)
    assert a_to_b == pytest.approx(np.sqrt(igl.point_mesh_squared_distance(V, Vn, Fn)[0].max()), rel=1e-10)
    assert b_to_a == pytest.approx(np.sqrt(igl.point_mesh_squared_distance(Vn, V, F)[0].max()), rel=1e-10)


def test_hausdorff_agrees_with_libigl_on_different_meshes():
    VA, FA = datasets.icosphere(4)
    VB, FB = datasets.torus(1.0, 0.4, 48, 24)
    assert hausdorff_distance(VA, FA, VB, FB) == pytest.approx(igl.hausdorff(VA, FA, VB, FB), rel=1e-10)


def test_hausdorff_of_a_mesh_to_itself_is_zero():
    V, F = datasets.icosphere(3)
    assert hausdorff_distance(V, F, V, F) == 0.0
    assert mean_surface_distance(V, F, V, F) == 0.0
    assert hausdorff_distance(V, F, V, F, sampled=True, samples_per_face=4) < 1e-15


def test_concentric_spheres_differ_by_the_radii_up_to_discretization():
    V, F = datasets.icosphere(4)
    outer = 1.2 * V
    normals = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    inradius = np.abs((normals / np.linalg.norm(normals, axis=1, keepdims=True) * V[F[:, 0]]).sum(1)).min()
    h = hausdorff_distance(V, F, outer, F)
    # Vertices of the outer sphere (radius 1.2) to the inner polyhedron, which lies between the
    # spheres of radius `inradius` and 1: at least 0.2, at most 1.2 - inradius.
    assert 0.2 - 1e-12 <= h <= 1.2 - inradius
    assert 1.2 - inradius < 0.21  # the bound is tight: "difference of radii up to discretization"
    mean = mean_surface_distance(V, F, outer, F, sampled=True, samples_per_face=4)
    assert 0.2 * inradius - 1e-12 <= mean <= 1.2 - inradius


def test_translated_copy():
    V, F = datasets.icosphere(3)
    t = np.array([0.03, -0.02, 0.05])
    h = hausdorff_distance(V, F, V + t, F)
    assert 0.0 < h <= np.linalg.norm(t) + 1e-15
    # A plane moved along its normal: every sample is exactly |t| away, both ways.
    G, FG = datasets.grid(8, 8)
    for sampled in (False, True):
        assert hausdorff_distance(G, FG, G + [0, 0, 0.3], FG, sampled=sampled) == pytest.approx(0.3, abs=1e-15)
        assert mean_surface_distance(G, FG, G + [0, 0, 0.3], FG, sampled=sampled) == pytest.approx(0.3, abs=1e-15)


def test_sampled_hausdorff_is_a_tighter_deterministic_bound():
    VA, FA = datasets.icosphere(3)
    VB, FB = datasets.noisy(VA, FA, sigma=0.3, seed=2)
    vertices_only = hausdorff_distance(VA, FA, VB, FB, one_sided=True)
    sampled = hausdorff_distance(VA, FA, VB, FB, sampled=True, samples_per_face=32, one_sided=True)
    assert all(s >= v for s, v in zip(sampled, vertices_only))
    assert sampled[1] > vertices_only[1] or sampled[2] > vertices_only[2]  # face interiors count
    assert hausdorff_distance(VA, FA, VB, FB, sampled=True, samples_per_face=32, one_sided=True) == sampled
    assert hausdorff_distance(VA, FA, VB, FB, sampled=True, samples_per_face=32, seed=9, one_sided=True) != sampled


def test_mean_surface_distance_vertex_mode_matches_numpy():
    VA, FA = datasets.icosphere(3)
    VB, FB = datasets.noisy(VA, FA, sigma=0.3, seed=2, direction="isotropic")

    def lumped(V, F):
        areas = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
        w = np.zeros(len(V))
        for k in range(3):
            np.add.at(w, F[:, k], areas / 3)
        return w

    wa, wb = lumped(VA, FA), lumped(VB, FB)
    da = np.sqrt(igl.point_mesh_squared_distance(VA, VB, FB)[0])
    db = np.sqrt(igl.point_mesh_squared_distance(VB, VA, FA)[0])
    symmetric, a_to_b, b_to_a = mean_surface_distance(VA, FA, VB, FB, one_sided=True)
    assert a_to_b == pytest.approx((wa * da).sum() / wa.sum(), rel=1e-10)
    assert b_to_a == pytest.approx((wb * db).sum() / wb.sum(), rel=1e-10)
    assert symmetric == pytest.approx(((wa * da).sum() + (wb * db).sum()) / (wa.sum() + wb.sum()), rel=1e-10)
    # Face samples: a Monte-Carlo estimate of the integral, checked against an independent one
    # (area-uniform points from datasets.sample_points, distances from libigl).
    _, sampled_a_to_b, _ = mean_surface_distance(VA, FA, VB, FB, sampled=True, samples_per_face=64,
                                                 one_sided=True)
    P, _ = datasets.sample_points(VA, FA, 200_000, seed=5)
    independent = np.sqrt(igl.point_mesh_squared_distance(P, VB, FB)[0]).mean()
    assert sampled_a_to_b == pytest.approx(independent, rel=0.01)


def test_distance_bad_input():
    V, F = datasets.icosphere(1)
    with pytest.raises(meshsmith.InputError, match="FB"):
        hausdorff_distance(V, F, V, F[:, :2])
    with pytest.raises(meshsmith.InputError, match="index"):
        hausdorff_distance(V, F, V, F + len(V))
    with pytest.raises(meshsmith.InputError, match=r"mesh A: V\[0, 0\]"):
        mean_surface_distance(np.full_like(V, np.nan), F, V, F)
    with pytest.raises(meshsmith.InputError, match="samples_per_face"):
        hausdorff_distance(V, F, V, F, sampled=True, samples_per_face=0)
    with pytest.raises(meshsmith.InputError, match=r"more than 2\^27 samples"):  # not a huge allocation
        hausdorff_distance(V, F, V, F, sampled=True, samples_per_face=10**9)
    tree = SurfaceDistance(V, F)
    with pytest.raises(meshsmith.InputError, match=r"Q\[1, 2\] is not finite"):
        tree.closest_points([[0.0, 0, 0], [1, 1, np.inf]])
    with pytest.raises(meshsmith.InputError, match="Q has shape"):
        tree.distances(np.zeros((3, 2)))
    with pytest.raises(meshsmith.InputError, match="leaf_size"):
        SurfaceDistance(V, F, leaf_size=0)
    with pytest.raises(meshsmith.InputError, match="F is empty"):
        SurfaceDistance(V, np.zeros((0, 3), int))
    flat = np.zeros((3, 3))
    with pytest.raises(meshsmith.InputError, match="zero total area"):
        mean_surface_distance(flat, [[0, 1, 2]], V, F)


def test_progress_is_reported_and_can_cancel():
    V, F = datasets.icosphere(3)
    stages = []
    hausdorff_distance(V, F, 1.1 * V, F, progress=lambda fraction, stage: stages.append((fraction, stage)))
    assert stages and stages[-1][0] == 1.0
    with pytest.raises(meshsmith.Cancelled):
        hausdorff_distance(V, F, 1.1 * V, F, progress=lambda fraction, stage: False)
    with pytest.raises(meshsmith.Cancelled):
        SurfaceDistance(V, F).closest_points(V, progress=lambda fraction, stage: False)
