"""geometry (differential part): normals, Laplacians, mass matrices, curvatures, eigenpairs.

Three tiers, as DESIGN.md asks: agreement with libigl on the shared meshes (to 1e-10), analytic
truth and invariants on procedural shapes (Gauss-Bonnet, linear precision, sphere and torus
curvature, sphere harmonics), and bad input.
"""
import re

import igl
import numpy as np
import pytest
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg
import scipy.spatial
import scipy.stats

from meshsmith.datasets import icosphere
import meshsmith
from meshsmith import geometry

SHARED_MESHES = ["bunny.off", "armadillo.obj", "camelhead.off", "fertility.off"]
CLOSED_MESHES = ["bunny.off", "armadillo.obj", "fertility.off"]


# --- procedural meshes ----------------------------------------------------------------------

def torus(n_major: int, n_minor: int, R: float = 2.0, r: float = 1.0):
    """Regular torus grid; also returns each vertex's angles (phi around the axis, theta around the tube)."""
    i, j = np.meshgrid(np.arange(n_major), np.arange(n_minor), indexing="ij")
    phi, theta = 2 * np.pi * i / n_major, 2 * np.pi * j / n_minor
    V = np.stack([(R + r * np.cos(theta)) * np.cos(phi), (R + r * np.cos(theta)) * np.sin(phi),
                  r * np.sin(theta)], -1).reshape(-1, 3)

    def index(a, b):
        return (a % n_major) * n_minor + (b % n_minor)

    a, b, c, d = index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return V, F, phi.ravel(), theta.ravel()


def planar_mesh(seed: int = 0, count: int = 300):
    """Delaunay triangulation of random points in the unit square (z = 0), counter-clockwise."""
    rng = np.random.default_rng(seed)
    corners = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    points = np.vstack([corners, rng.random((count, 2))])
    F = scipy.spatial.Delaunay(points).simplices
    V = np.column_stack([points, np.zeros(len(points))])
    flipped = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])[:, 2] < 0
    F[flipped] = F[flipped][:, [0, 2, 1]]
    return V, F


def boundary_vertices(F):
    edges = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return np.unique(unique[counts == 1])


def euler_characteristic(V, F):
    edges = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)
    return len(V) - len(edges) + len(F)


@pytest.fixture(scope="module", params=SHARED_MESHES)
def shared_mesh(request, data_dir):
    V, F = igl.read_triangle_mesh(str(data_dir / request.param))
    return request.param, V, F


def relative_sparse_difference(A, B):
    return abs(A - B).max() / abs(B).max()


# --- agreement with libigl ------------------------------------------------------------------

def test_face_normals_match_libigl(shared_mesh):
    _, V, F = shared_mesh
    expected = igl.per_face_normals(V, F, np.zeros(3))
    assert np.abs(geometry.face_normals(V, F) - expected).max() <= 1e-10


@pytest.mark.parametrize("weighting, igl_type", [
    ("uniform", igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_UNIFORM),
    ("area", igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_AREA),
    ("angle", igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_ANGLE),
])
def test_vertex_normals_match_libigl(shared_mesh, weighting, igl_type):
    _, V, F = shared_mesh
    N = geometry.vertex_normals(V, F, weighting=weighting)
    assert N.shape == V.shape
    assert np.abs(N - igl.per_vertex_normals(V, F, igl_type)).max() <= 1e-10
    np.testing.assert_allclose(np.linalg.norm(N, axis=1), 1.0, atol=1e-12)


def test_cotan_laplacian_matches_libigl(shared_mesh):
    _, V, F = shared_mesh
    L = geometry.cotan_laplacian(V, F)
    assert isinstance(L, scipy.sparse.csc_matrix) and L.shape == (len(V), len(V))
    assert L.has_sorted_indices and L.has_canonical_format
    assert relative_sparse_difference(L, igl.cotmatrix(V, F)) <= 1e-10
    assert relative_sparse_difference(L, L.T) <= 1e-14
    assert np.abs(L @ np.ones(len(V))).max() <= 1e-10 * abs(L).max()
    # negative semi-definite: x^T L x <= 0 for random x
    x = np.random.default_rng(1).standard_normal((len(V), 4))
    assert np.all(np.einsum("ij,ij->j", x, L @ x) < 0)


@pytest.mark.parametrize("kind, igl_type", [
    ("voronoi", igl.MASSMATRIX_TYPE_VORONOI), ("barycentric", igl.MASSMATRIX_TYPE_BARYCENTRIC)])
def test_mass_matrix_matches_libigl(shared_mesh, kind, igl_type):
    _, V, F = shared_mesh
    M = geometry.mass_matrix(V, F, kind=kind)
    assert isinstance(M, scipy.sparse.csc_matrix) and M.shape == (len(V), len(V))
    assert relative_sparse_difference(M, igl.massmatrix(V, F, igl_type)) <= 1e-10
    area = 0.5 * igl.doublearea(V, F).sum()
    assert M.diagonal().sum() == pytest.approx(area, rel=1e-12)
    np.testing.assert_array_equal(geometry.vertex_areas(V, F, kind=kind), M.diagonal())


def test_gaussian_curvature_matches_libigl(shared_mesh):
    _, V, F = shared_mesh
    assert np.abs(geometry.gaussian_curvature(V, F) - igl.gaussian_curvature(V, F)).max() <= 1e-10
    pointwise = geometry.gaussian_curvature(V, F, pointwise=True)
    areas = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI).diagonal()
    np.testing.assert_allclose(pointwise * areas, igl.gaussian_curvature(V, F), rtol=0, atol=1e-10)


def test_mean_curvature_normal_matches_libigl_operators(shared_mesh):
    _, V, F = shared_mesh
    H, Hn = geometry.mean_curvature(V, F)
    M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)
    expected = -0.5 * scipy.sparse.diags(1.0 / M.diagonal()) @ (igl.cotmatrix(V, F) @ V)
    assert np.abs(Hn - expected).max() <= 1e-10 * np.abs(expected).max()
    np.testing.assert_allclose(np.abs(H), np.linalg.norm(expected, axis=1), rtol=1e-9, atol=1e-12)
    normals = igl.per_vertex_normals(V, F, igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_ANGLE)
    assert np.all(np.sign(H[np.abs(H) > 1e-6]) ==
                  np.sign(np.einsum("ij,ij->i", expected, normals))[np.abs(H) > 1e-6])


def test_principal_curvatures_agree_with_libigl_in_the_large(shared_mesh):
    # Different estimators: ours fits the 2-ring, libigl fits quadrics over a radius of 5 mean
    # edge lengths, so on scanned meshes ours sees more detail (and noise): |H| comes out 1.2-1.7x
    # larger in the median. What must agree is the shape: the ranking of mean curvature
    # (Spearman 0.74-0.91 measured) and its sign wherever libigl's |H| is above its median
    # (97.5-99.3% measured).
    name, V, F = shared_mesh
    k1, k2, d1, d2 = geometry.principal_curvatures(V, F)
    _, _, igl_k1, igl_k2, _ = igl.principal_curvature(V, F)
    assert np.all(k1 >= k2)
    mean, igl_mean = 0.5 * (k1 + k2), 0.5 * (igl_k1 + igl_k2)
    assert scipy.stats.spearmanr(mean, igl_mean)[0] > 0.7, name
    strong = np.abs(igl_mean) > np.median(np.abs(igl_mean))
    assert np.mean(np.sign(mean[strong]) == np.sign(igl_mean[strong])) > 0.95, name


def test_uniform_laplacian_is_adjacency_minus_degree(shared_mesh):
    _, V, F = shared_mesh
    A = igl.adjacency_matrix(F).astype(float)
    expected = A - scipy.sparse.diags(np.asarray(A.sum(axis=1)).ravel())
    L = geometry.uniform_laplacian(F, len(V))
    assert abs(L - expected).max() == 0
    assert abs(geometry.uniform_laplacian(V, F) - L).max() == 0
    assert abs(geometry.uniform_laplacian(F) - L).max() == 0  # n = F.max() + 1 (all vertices used)
    U = geometry.uniform_laplacian(F, len(V), normalized=True)
    np.testing.assert_allclose(U.diagonal(), -1.0)
    np.testing.assert_allclose(U @ np.ones(len(V)), 0.0, atol=1e-12)


def test_mean_value_laplacian_matches_floater_weights_computed_in_numpy(shared_mesh):
    _, V, F = shared_mesh
    rows, cols, values = [], [], []
    for c in range(3):
        i, j, k = F[:, c], F[:, (c + 1) % 3], F[:, (c + 2) % 3]
        u, w = V[j] - V[i], V[k] - V[i]
        angle = np.arctan2(np.linalg.norm(np.cross(u, w), axis=1), np.einsum("ij,ij->i", u, w))
        half = np.tan(angle / 2)
        rows += [i, i]
        cols += [j, k]
        values += [half / np.linalg.norm(u, axis=1), half / np.linalg.norm(w, axis=1)]
    n = len(V)
    W = scipy.sparse.csc_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), (n, n))
    expected = W - scipy.sparse.diags(np.asarray(W.sum(axis=1)).ravel())
    L = geometry.mean_value_laplacian(V, F)
    assert relative_sparse_difference(L, expected) <= 1e-10
    off_diagonal = L - scipy.sparse.diags(L.diagonal())
    assert off_diagonal.min() >= 0
    assert relative_sparse_difference(L, L.T) > 1e-3  # not symmetric


# --- invariants and analytic truth ------------------------------------------------------------

@pytest.mark.parametrize("name", CLOSED_MESHES)
def test_gauss_bonnet_on_closed_meshes(data_dir, name):
    V, F = igl.read_triangle_mesh(str(data_dir / name))
    assert len(boundary_vertices(F)) == 0
    chi = euler_characteristic(V, F)
    assert geometry.gaussian_curvature(V, F).sum() == pytest.approx(2 * np.pi * chi, abs=1e-9)


def test_gauss_bonnet_with_boundary_needs_the_half_turn_rule(data_dir):
    V, F = igl.read_triangle_mesh(str(data_dir / "camelhead.off"))
    boundary = boundary_vertices(F)
    assert len(boundary) > 0
    chi = euler_characteristic(V, F)
    half = geometry.gaussian_curvature(V, F, boundary="half_turn")
    assert half.sum() == pytest.approx(2 * np.pi * chi, abs=1e-9)
    full = geometry.gaussian_curvature(V, F)
    np.testing.assert_allclose((full - half)[boundary], np.pi, atol=1e-12)
    interior = np.setdiff1d(np.arange(len(V)), boundary)
    np.testing.assert_array_equal(full[interior], half[interior])


@pytest.mark.parametrize("operator", ["cotan", "mean_value"])
def test_linear_precision_on_a_planar_mesh(operator):
    V, F = planar_mesh()
    L = {"cotan": geometry.cotan_laplacian, "mean_value": geometry.mean_value_laplacian}[operator](V, F)
    interior = np.setdiff1d(np.arange(len(V)), boundary_vertices(F))
    linear = 0.3 + 2.0 * V[:, 0] - 1.5 * V[:, 1]
    assert np.abs((L @ linear)[interior]).max() <= 1e-12 * np.abs(L).max()
    # the uniform Laplacian has no linear precision on an irregular mesh: the test can fail
    assert np.abs((geometry.uniform_laplacian(F, len(V)) @ linear)[interior]).max() > 1e-3


def test_sphere_curvature_converges_quadratically():
    # Observed on icospheres of radius 2 (subdivisions 2..5, edge length halving each time):
    # max |H - 1/r| and max |K - 1/r^2| (pointwise, mixed Voronoi areas) both shrink by 4.0x per
    # level, i.e. O(h^2) (errors 7.0e-5 -> 1.1e-6 for H, 5.1e-3 -> 8.9e-5 for K); the quadric-fit
    # principal curvatures converge as O(h^2) too (4.9e-2 -> 7.5e-4).
    r = 2.0
    errors = []
    for level in range(2, 6):
        V, F = icosphere(level, r)
        H, Hn = geometry.mean_curvature(V, F)
        K = geometry.gaussian_curvature(V, F, pointwise=True)
        k1, k2, _, _ = geometry.principal_curvatures(V, F)
        np.testing.assert_allclose(Hn / H[:, None], V / r, atol=0.02)  # outward unit normal
        errors.append([np.abs(H - 1 / r).max(), np.abs(K - 1 / r ** 2).max(),
                       max(np.abs(k1 - 1 / r).max(), np.abs(k2 - 1 / r).max())])
    errors = np.array(errors)
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all(orders > 1.8), orders
    assert np.all(H > 0)
    assert errors[-1, 0] < 2e-6 and errors[-1, 1] < 2e-4 and errors[-1, 2] < 2e-3


@pytest.mark.parametrize("method, tolerance", [("quadric_fit", 0.015), ("shape_operator", 0.004)])
def test_torus_principal_curvatures_and_directions(method, tolerance):
    V, F, phi, theta = torus(128, 64)
    k1, k2, d1, d2 = geometry.principal_curvatures(V, F, method=method)
    tube = 1.0                                   # 1/r, along the meridian circle
    axial = np.cos(theta) / (2.0 + np.cos(theta))  # around the axis
    assert np.abs(k1 - tube).max() < tolerance
    assert np.abs(k2 - axial).max() < tolerance
    around_axis = np.column_stack([-np.sin(phi), np.cos(phi), np.zeros_like(phi)])
    assert np.abs(np.einsum("ij,ij->i", d1, around_axis)).max() < 0.01
    assert np.abs(np.abs(np.einsum("ij,ij->i", d2, around_axis)) - 1).max() < 1e-4
    normals = geometry.vertex_normals(V, F)
    np.testing.assert_allclose(np.cross(normals, d1), d2, atol=1e-12)
    # libigl's estimator is much further off on this mesh (about 5%)
    _, _, igl_k1, _, _ = igl.principal_curvature(V, F)
    assert np.abs(igl_k1 - tube).max() > 3 * np.abs(k1 - tube).max()


def test_mean_gaussian_principal_curvatures_on_a_sphere():
    V, F = icosphere(4, 0.5)
    k1, k2, _, _ = geometry.principal_curvatures(V, F, method="mean_gaussian")
    H, _ = geometry.mean_curvature(V, F)
    np.testing.assert_allclose(k1, 2.0, rtol=1e-4)
    np.testing.assert_allclose(k2, 2.0, rtol=1e-4)
    assert np.all(k1 >= H) and np.all(k2 <= H)


def test_sphere_eigenvalues_are_l_times_l_plus_one():
    V, F = icosphere(3)
    values, vectors = geometry.laplacian_eigenpairs(V, F, 16)
    expected = np.concatenate([[l * (l + 1)] * (2 * l + 1) for l in range(4)])
    assert abs(values[0]) < 1e-8
    np.testing.assert_allclose(values[1:], expected[1:], rtol=0.03)
    M = geometry.mass_matrix(V, F)
    np.testing.assert_allclose(vectors.T @ M @ vectors, np.eye(16), atol=1e-9)
    # the first eigenvector is constant; each one solves -L u = lambda M u
    np.testing.assert_allclose(vectors[:, 0], vectors[0, 0], rtol=1e-8)
    L = geometry.cotan_laplacian(V, F)
    residual = -L @ vectors - (M @ vectors) * values
    assert np.abs(residual).max() < 1e-8


def test_eigenpairs_match_scipy_arpack(data_dir):
    V, F = igl.read_triangle_mesh(str(data_dir / "fertility.off"))
    values, vectors = geometry.laplacian_eigenpairs(V, F, 8, mass="barycentric")
    L = igl.cotmatrix(V, F)
    M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_BARYCENTRIC)
    expected = scipy.sparse.linalg.eigsh(-L, k=8, M=M, sigma=-1e-3, return_eigenvectors=False)
    np.testing.assert_allclose(values, np.sort(expected), rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(vectors.T @ M @ vectors, np.eye(8), atol=1e-9)


def test_progress_callback_can_cancel_eigenpairs():
    # progress reports are throttled to one per 50 ms, so the mesh must keep Lanczos busy longer
    V, F = icosphere(5)
    stages = []

    def stop(fraction, stage):
        stages.append(stage)
        return stage != "Lanczos iterations"

    with pytest.raises(meshsmith.Cancelled):
        geometry.laplacian_eigenpairs(V, F, 6, progress=stop)
    assert "Lanczos iterations" in stages


# --- degenerate and bad input -------------------------------------------------------------

def test_degenerate_faces_and_isolated_vertices_give_finite_results():
    V, F = icosphere(2)
    V = np.vstack([V, V[F[0, 0]] * 0.5 + V[F[0, 1]] * 0.5, [[5.0, 5.0, 5.0]]])
    collinear = len(V) - 2
    isolated = len(V) - 1
    F = np.vstack([F, [[F[0, 0], F[0, 1], collinear], [F[1, 0], F[1, 0], F[1, 1]]]])
    fn = geometry.face_normals(V, F)
    np.testing.assert_array_equal(fn[-2:], 0.0)
    for weighting in ("uniform", "area", "angle"):
        N = geometry.vertex_normals(V, F, weighting=weighting)
        assert np.isfinite(N).all()
        np.testing.assert_array_equal(N[isolated], 0.0)
    for matrix in (geometry.cotan_laplacian(V, F), geometry.mean_value_laplacian(V, F),
                   geometry.mass_matrix(V, F), geometry.mass_matrix(V, F, kind="barycentric")):
        assert np.isfinite(matrix.data).all()
        assert matrix[isolated, isolated] == 0
    H, Hn = geometry.mean_curvature(V, F)
    K = geometry.gaussian_curvature(V, F, pointwise=True)
    assert np.isfinite(H).all() and np.isfinite(Hn).all() and np.isfinite(K).all()
    assert H[isolated] == 0 and K[isolated] == 0
    assert geometry.gaussian_curvature(V, F)[isolated] == pytest.approx(2 * np.pi)
    for method in ("quadric_fit", "shape_operator", "mean_gaussian"):
        assert all(np.isfinite(a).all() for a in geometry.principal_curvatures(V, F, method=method))
    # the degenerate faces change nothing else: the cotangent Laplacian equals the clean one
    clean = geometry.cotan_laplacian(V, F[:-2])
    assert abs(geometry.cotan_laplacian(V, F) - clean).max() == 0


TETRA_V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
TETRA_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
ALL_MESH_FUNCTIONS = [
    geometry.face_normals, geometry.vertex_normals, geometry.cotan_laplacian,
    geometry.mean_value_laplacian, geometry.mass_matrix, geometry.vertex_areas,
    geometry.gaussian_curvature, geometry.mean_curvature, geometry.principal_curvatures,
    lambda V, F: geometry.laplacian_eigenpairs(V, F, 2),
    geometry.uniform_laplacian,
]


@pytest.mark.parametrize("function", ALL_MESH_FUNCTIONS)
@pytest.mark.parametrize("V, F, message", [
    (np.where(np.eye(4, 3) > 0, np.nan, TETRA_V), TETRA_F, "V[0, 0] is nan"),
    (TETRA_V, TETRA_F + 1, "indexes vertex 4"),
    (np.zeros((0, 3)), TETRA_F, "V is empty"),
    (TETRA_V, np.zeros((0, 3), int), "F is empty"),
    (TETRA_V[:, :2], TETRA_F, "V has shape (4, 2)"),
    (TETRA_V, TETRA_F.astype(float), "expected integer indices"),
])
def test_bad_input_raises_input_error(function, V, F, message):
    with pytest.raises(meshsmith.InputError, match=re.escape(message)):
        function(V, F)


@pytest.mark.parametrize("call, message", [
    (lambda: geometry.vertex_normals(TETRA_V, TETRA_F, weighting="length"), "weighting = 'length'"),
    (lambda: geometry.mass_matrix(TETRA_V, TETRA_F, kind="full"), "kind = 'full'"),
    (lambda: geometry.gaussian_curvature(TETRA_V, TETRA_F, boundary="none"), "boundary = 'none'"),
    (lambda: geometry.principal_curvatures(TETRA_V, TETRA_F, method="x"), "method = 'x'"),
    (lambda: geometry.laplacian_eigenpairs(TETRA_V, TETRA_F, 4), "expected 1 <= k < #V = 4"),
    (lambda: geometry.laplacian_eigenpairs(TETRA_V, TETRA_F, 0), "k = 0"),
    (lambda: geometry.laplacian_eigenpairs(np.vstack([TETRA_V, [[2.0, 2, 2]]]), TETRA_F, 2),
     "vertex 4 has zero area"),
    (lambda: geometry.uniform_laplacian(TETRA_F, 3), "outside [0, 3)"),
])
def test_bad_options_raise_input_error(call, message):
    with pytest.raises(meshsmith.InputError, match=re.escape(message)):
        call()


def test_inputs_are_not_modified():
    V, F = icosphere(1)
    V0, F0 = V.copy(), F.copy()
    for function in ALL_MESH_FUNCTIONS:
        function(V, F)
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(F, F0)
