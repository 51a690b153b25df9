"""The fill-reducing order of the parametrization solves (geometric nested dissection, used for
harmonic maps, stretch minimization and LSCM when the vertex positions are known): the solves it
orders must agree with independent solvers (libigl; scipy's SuperLU on the same system) to
round-off, including when the free vertices form several components or are a single vertex."""
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from meshsmith import datasets, geometry
from meshsmith import parametrization as P

igl = pytest.importorskip("igl")


def _bumpy_disk(n_rings, n_segments):
    V, F = datasets.disk(n_rings=n_rings, n_segments=n_segments)
    V = V.copy()
    V[:, 2] = 0.2 * np.sin(3 * V[:, 0]) * np.cos(2 * V[:, 1])
    return V, F


def _reference_harmonic(L, fixed, fixed_uv):
    """Solves L_FF X_F = -L_FB X_B with SuperLU (no ordering of ours involved)."""
    n = L.shape[0]
    free = np.setdiff1d(np.arange(n), fixed)
    L = sp.csc_matrix(L)
    X = np.zeros((n, 2))
    X[fixed] = fixed_uv
    X[free] = spla.spsolve(L[free][:, free].tocsc(), -(L[free][:, fixed] @ fixed_uv))
    return X


def test_harmonic_on_a_large_bumpy_disk_matches_libigl_and_superlu():
    # ~13k faces: the dissection recurses about ten levels deep.
    V, F = _bumpy_disk(60, 220)
    F64 = F.astype(np.int64)
    bnd = igl.boundary_loop(F64)
    bc = np.ascontiguousarray(igl.map_vertices_to_circle(np.asfortranarray(V), bnd.astype(np.int32)))
    UV = P.harmonic(V, F, weights="cotan")
    np.testing.assert_allclose(UV, igl.harmonic(V, F64, bnd, bc, 1), atol=1e-8)
    np.testing.assert_allclose(UV, _reference_harmonic(geometry.cotan_laplacian(V, F), bnd, bc), atol=1e-10)
    # the order is deterministic, so is the result, bit for bit
    assert np.array_equal(UV, P.harmonic(V, F, weights="cotan"))
    UV = P.harmonic(V, F, weights="uniform", shape="square")
    b, buv = P.map_boundary(V, F, shape="square")
    np.testing.assert_allclose(UV, _reference_harmonic(geometry.uniform_laplacian(F, len(V)), b, buv), atol=1e-10)


@pytest.mark.parametrize("weights", ["uniform", "cotan"])
def test_harmonic_with_free_vertices_in_two_components(weights):
    # Fixing the outer boundary and a middle ring splits the free vertices into an inner disk and
    # an annulus: the system is block diagonal and the order must handle a disconnected graph.
    V, F = _bumpy_disk(16, 64)
    radius = np.linalg.norm(V[:, :2], axis=1)
    outer, _ = P.map_boundary(V, F)
    ring = np.flatnonzero(np.isclose(radius, 0.5, atol=1e-9))
    assert len(ring) > 10
    fixed = np.concatenate([outer, ring])
    rng = np.random.default_rng(7)
    fixed_uv = rng.normal(size=(len(fixed), 2))
    UV = P.harmonic(V, F, boundary=fixed, boundary_uv=fixed_uv, weights=weights)
    L = geometry.cotan_laplacian(V, F) if weights == "cotan" else geometry.uniform_laplacian(F, len(V))
    np.testing.assert_allclose(UV, _reference_harmonic(L, fixed, fixed_uv), atol=1e-10)


def test_harmonic_with_a_single_free_vertex():
    # A fan around vertex 0: Tutte puts it at the average of its neighbours, and the cotan map
    # at their cotangent-weighted average.
    k = 7
    angles = np.sort(np.random.default_rng(3).uniform(0, 2 * np.pi, k))
    V = np.vstack([[0.1, -0.05, 0.2], np.column_stack([np.cos(angles), np.sin(angles), np.zeros(k)])])
    F = np.array([[0, 1 + i, 1 + (i + 1) % k] for i in range(k)])
    rim = np.arange(1, k + 1)
    rim_uv = np.column_stack([np.cos(angles), np.sin(angles)]) * 2.0 + [0.3, -0.1]
    UV = P.harmonic(V, F, boundary=rim, boundary_uv=rim_uv, weights="uniform")
    np.testing.assert_allclose(UV[0], rim_uv.mean(axis=0), atol=1e-14)
    UV = P.harmonic(V, F, boundary=rim, boundary_uv=rim_uv, weights="cotan")
    w = geometry.cotan_laplacian(V, F).toarray()[0, 1:]
    np.testing.assert_allclose(UV[0], w @ rim_uv / w.sum(), atol=1e-13)


def test_lscm_on_a_large_bumpy_disk_matches_libigl():
    # LSCM's Hermitian system is ordered the same way.
    V, F = _bumpy_disk(60, 220)
    pins, pins_uv = P.default_lscm_pins(V, F)
    expected, _ = igl.lscm(V, F.astype(np.int64), pins, np.ascontiguousarray(pins_uv))
    np.testing.assert_allclose(P.lscm(V, F, pins, pins_uv), expected, atol=1e-8)


def _grid(nx, ny):
    """A triangulated [0, nx-1] x [0, ny-1] grid in the plane z = 0, with a gentle bump."""
    x, y = np.meshgrid(np.arange(nx, dtype=float), np.arange(ny, dtype=float), indexing="ij")
    V = np.column_stack([x.ravel(), y.ravel(), 0.1 * np.sin(x.ravel()) * np.cos(y.ravel())])
    index = np.arange(nx * ny).reshape(nx, ny)
    a, b, c, d = index[:-1, :-1].ravel(), index[1:, :-1].ravel(), index[1:, 1:].ravel(), index[:-1, 1:].ravel()
    F = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return V, F


@pytest.mark.parametrize("weights", ["uniform", "cotan"])
def test_harmonic_with_free_parts_split_by_a_fixed_column(weights):
    # The fixed middle column leaves two free parts with no edge between them, side by side
    # along the longest axis: the first dissection split finds an empty separator.
    nx, ny = 61, 12
    V, F = _grid(nx, ny)
    index = np.arange(nx * ny).reshape(nx, ny)
    fixed = np.unique(np.concatenate([index[0], index[-1], index[:, 0], index[:, -1], index[nx // 2]]))
    fixed_uv = np.column_stack([np.cos(V[fixed, 0]), V[fixed, 1] + 0.5 * np.sin(V[fixed, 0])])
    UV = P.harmonic(V, F, boundary=fixed, boundary_uv=fixed_uv, weights=weights)
    L = geometry.cotan_laplacian(V, F) if weights == "cotan" else geometry.uniform_laplacian(F, len(V))
    np.testing.assert_allclose(UV, _reference_harmonic(L, fixed, fixed_uv), atol=1e-10)
