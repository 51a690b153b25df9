"""Quad extraction from seamless parametrizations (§5.2.2 step 4) and quad-mesh quality.

The parametrizations are built here, independently of any field or MIQ solver: a flat square
(UV = scaled positions, aligned and jittered triangulations), a torus (UV from its angles, seams
with integer translations), a cube-like closed surface (each cube face on an integer square,
transitions by rotations: 8 valence-3 singularities), and a per-chart random rotation and integer
translation of each, which must not change the result.
"""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, topology
from meshsmith.quadrangulation import extract_quads, quad_quality


# --- synthetic seamless parametrizations -------------------------------------------------------

def square(k=5, n=7, jitter=0.0, seed=0):
    """The unit square as an n×n triangle grid (interior vertices jittered), UV = k·(x, y)."""
    V, F = datasets.grid(n, n)
    V = V.copy()
    if jitter:
        rng = np.random.default_rng(seed)
        inner = (V[:, :2] > 1e-9).all(1) & (V[:, :2] < 1 - 1e-9).all(1)
        V[inner, :2] += rng.uniform(-jitter, jitter, (inner.sum(), 2)) / n
    return V, F, k * V[F][:, :, :2]


def torus(nu=6, nv=3, n_major=20, n_minor=9):
    """datasets.torus with (u, v) = (nu·θ/2π, nv·φ/2π), unwrapped per face across the seams."""
    V, F = datasets.torus(1.0, 0.35, n_major, n_minor)
    i, j = np.divmod(np.arange(len(V)), n_minor)
    corners = []
    for values, period in ((i / n_major * nu, nu), (j / n_minor * nv, nv)):
        X = values[F]
        X = np.where(X.max(1, keepdims=True) - X > period / 2, X + period, X)
        corners.append(X)
    return V, F, np.stack(corners, -1)


def cube(n=3, t=4, bump=0.0):
    """The cube [-1, 1]^3, each face a t×t grid of squares split in two, each face's (u, v) on
    [0, n]^2 (its own frame, outward orientation); bump > 0 moves the points radially."""
    Vs, Fs, UVs, offset = [], [], [], 0
    s = np.linspace(-1.0, 1.0, t + 1)
    S, T = (a.ravel() for a in np.meshgrid(s, s, indexing="ij"))
    idx = np.arange((t + 1) ** 2).reshape(t + 1, t + 1)
    q = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], -1).reshape(-1, 4)
    tri = np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
    for axis in range(3):
        for direction in (1.0, -1.0):
            normal = np.zeros(3)
            normal[axis] = direction
            e1 = np.zeros(3)
            e1[(axis + 1) % 3] = 1.0
            e2 = np.cross(normal, e1)
            Vs.append(normal + S[:, None] * e1 + T[:, None] * e2)
            Fs.append(tri + offset)
            UVs.append(np.stack([(S + 1) / 2 * n, (T + 1) / 2 * n], -1)[tri])
            offset += len(S)
    V, F, UV = np.concatenate(Vs), np.concatenate(Fs), np.concatenate(UVs)
    _, first, inverse = np.unique(np.round(V * 1e6).astype(np.int64), axis=0, return_index=True,
                                  return_inverse=True)
    V, F = V[first], inverse.ravel()[F]
    if bump:
        V = V * (1 + bump * np.sin(3 * V[:, [1]]) * np.cos(2 * V[:, [2]]))
    return V, F, UV


def random_charts(UV, seed=1):
    """Each face's corners rotated by a random quarter turn and moved by a random integer vector."""
    rng = np.random.default_rng(seed)
    out = UV.copy()
    for f in range(len(UV)):
        X = out[f]
        for _ in range(rng.integers(4)):
            X = np.stack([-X[:, 1], X[:, 0]], -1)
        out[f] = X + rng.integers(-50, 50, 2)
    return out


# --- invariants -----------------------------------------------------------------------------------

def triangles(Q):
    return np.concatenate([Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]])


def assert_valid_quad_mesh(Vq, Q):
    assert Q.dtype == np.int64 and Q.shape[1] == 4 and Vq.shape == (Q.max() + 1, 3)
    assert (np.sort(Q, 1)[:, 1:] != np.sort(Q, 1)[:, :-1]).all(), "a quad repeats a corner"
    T = triangles(Q)
    assert topology.is_manifold(T) and topology.is_oriented(T)


def node_uv_is_exact(V, F, UV, result):
    """Every node's position is the surface point of its integer (u, v) in its face's chart."""
    uv = result.node_uv
    assert np.array_equal(uv, np.round(uv))
    f = result.node_face
    A, B, C = (UV[f, k] for k in range(3))
    M = np.stack([B - A, C - A], -1)
    b = np.linalg.solve(M, (uv - A)[..., None])[..., 0]
    weights = np.column_stack([1 - b.sum(1), b])
    assert (weights > -1e-9).all()
    expected = np.einsum("nk,nkd->nd", weights, V[F[f]])
    np.testing.assert_allclose(result.V, expected, atol=1e-12)


def assert_unit_squares_translations(result, periods=None):
    """With translation-only seams: each quad's corners, read in the (u, v) plane (modulo the
    periods), are the corners of a unit square, counter-clockwise."""
    uv = result.node_uv[result.Q]
    steps = np.roll(uv, -1, axis=1) - uv
    if periods is not None:
        steps = (steps + np.asarray(periods) / 2) % periods - np.asarray(periods) / 2
    assert np.allclose(np.abs(steps).sum(2), 1.0)
    turn = steps[:, :, 0] * np.roll(steps, -1, axis=1)[:, :, 1] - steps[:, :, 1] * np.roll(steps, -1, axis=1)[:, :, 0]
    assert np.allclose(turn, 1.0)


def sorted_rows(X):
    return X[np.lexsort(np.round(X, 9).T[::-1])]


# --- flat square --------------------------------------------------------------------------------

@pytest.mark.parametrize("n, jitter", [(5, 0.0), (7, 0.0), (9, 0.3), (30, 0.3)])
def test_flat_square_gives_exactly_the_k_by_k_grid(n, jitter):
    k = 5
    V, F, UV = square(k, n, jitter)
    result = extract_quads(V, F, UV)
    Vq, Q = result
    assert len(Q) == k * k and len(Vq) == (k + 1) ** 2
    assert_valid_quad_mesh(Vq, Q)
    grid = np.stack(np.meshgrid(np.arange(k + 1), np.arange(k + 1), indexing="ij"), -1).reshape(-1, 2) / k
    np.testing.assert_allclose(sorted_rows(Vq[:, :2]), sorted_rows(grid), atol=1e-12)
    # counter-clockwise seen from +z like the input, unit squares of side 1/k
    quality = quad_quality(Vq, Q)
    np.testing.assert_allclose(quality.angles, 90.0, atol=1e-9)
    np.testing.assert_allclose(quality.scaled_jacobian, 1.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(Vq[Q[:, 1]] - Vq[Q[:, 0]], axis=1), 1 / k, atol=1e-12)
    report = result.report
    assert report.complete and report.euler_input == report.euler_output == 1 and report.holes == 0
    assert report.flipped_triangles == 0 and len(report.singular_vertices) == 0
    node_uv_is_exact(V, F, UV, result)
    assert_unit_squares_translations(result)


def test_flat_square_invariant_under_random_chart_transforms():
    V, F, UV = square(6, 11, 0.3)
    a = extract_quads(V, F, UV)
    b = extract_quads(V, F, random_charts(UV))
    assert len(a.Q) == len(b.Q) == 36
    np.testing.assert_allclose(sorted_rows(a.V), sorted_rows(b.V), atol=1e-12)
    assert_valid_quad_mesh(b.V, b.Q)
    node_uv_is_exact(V, F, random_charts(UV), b)


def test_mirrored_map_is_read_mirrored_and_gives_outward_quads():
    V, F, UV = square(4, 6, 0.2)
    result = extract_quads(V, F, UV * [1, -1])
    assert result.report.mirrored and result.report.complete and len(result.Q) == 16
    # still counter-clockwise seen from +z (the input's orientation)
    assert (quad_quality(result.V, result.Q).scaled_jacobian > 0.99).all()
    P = result.V[result.Q]
    assert (np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])[:, 2] > 0).all()


# --- torus ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("nu, nv", [(6, 3), (10, 4)])
def test_torus_gives_a_regular_grid_with_euler_zero(nu, nv):
    V, F, UV = torus(nu, nv)
    result = extract_quads(V, F, UV)
    Vq, Q = result
    assert len(Q) == nu * nv and len(Vq) == nu * nv
    assert_valid_quad_mesh(Vq, Q)
    assert topology.euler_characteristic(triangles(Q)) == 0 == result.report.euler_output
    assert result.report.complete and len(result.report.singular_vertices) == 0
    assert (quad_quality(Vq, Q).valence == 4).all()
    node_uv_is_exact(V, F, UV, result)
    assert_unit_squares_translations(result, periods=(nu, nv))
    # invariance: the same nodes after random per-chart rotations and translations
    other = extract_quads(V, F, random_charts(UV, seed=3))
    assert len(other.Q) == nu * nv
    np.testing.assert_allclose(sorted_rows(other.V), sorted_rows(Vq), atol=1e-12)


# --- cube -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("n, t, bump", [(3, 4, 0.0), (5, 7, 0.0), (4, 9, 0.15)])
def test_cube_gives_6n2_quads_and_eight_valence_three_corners(n, t, bump):
    V, F, UV = cube(n, t, bump)
    result = extract_quads(V, F, UV)
    Vq, Q = result
    assert len(Q) == 6 * n * n and len(Vq) == 6 * n * n + 2
    assert_valid_quad_mesh(Vq, Q)
    report = result.report
    assert report.complete and report.euler_input == report.euler_output == 2
    corners = np.flatnonzero((np.abs(np.abs(V / np.abs(V).max(1, keepdims=True)) - 1) < 1e-9).all(1))
    assert sorted(report.singular_vertices.tolist()) == sorted(corners.tolist()) and len(corners) == 8
    assert (report.singular_indices == 1).all() and report.singular_indices.sum() == 4 * 2  # Poincaré–Hopf
    quality = quad_quality(Vq, Q)
    assert np.bincount(quality.valence).tolist()[3:5] == [8, 6 * n * n + 2 - 8]
    node_uv_is_exact(V, F, UV, result)
    if bump == 0.0:
        np.testing.assert_allclose(quality.angles, 90.0, atol=1e-9)
        np.testing.assert_allclose(np.linalg.norm(Vq[Q[:, 1]] - Vq[Q[:, 0]], axis=1), 2 / n, atol=1e-12)
        # outward: each quad's normal points away from the centre
        P = Vq[Q]
        assert (np.einsum("kd,kd->k", np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), P.mean(1)) > 0).all()
    other = extract_quads(V, F, random_charts(UV, seed=7))
    assert len(other.Q) == len(Q) and other.report.complete
    np.testing.assert_allclose(sorted_rows(other.V), sorted_rows(Vq), atol=1e-12)


# --- degenerate parametrizations: valid, reported ------------------------------------------------

def centre_edge(V, F):
    """(the vertex nearest the square's centre, a neighbour of it)."""
    w = int(np.argmin(np.linalg.norm(V[:, :2] - 0.5, axis=1)))
    face = F[np.flatnonzero((F == w).any(1))[0]]
    return w, int(face[(list(face).index(w) + 1) % 3])


def signed_areas(UV):
    d1, d2 = UV[:, 1] - UV[:, 0], UV[:, 2] - UV[:, 0]
    return d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]


@pytest.mark.parametrize("overshoot", [1.5, 3.0])
def test_a_fold_at_a_free_vertex_is_untangled(overshoot):
    V, F, UV = square(5, 9, 0.3)
    UV = UV.copy()
    w, target = centre_edge(V, F)                # an interior vertex, moved past its neighbour
    at_w, at_target = F == w, F == target
    UV[at_w] = UV[at_w][0] + overshoot * (UV[at_target][0] - UV[at_w][0])
    assert (signed_areas(UV) < 0).sum() >= 1
    result = extract_quads(V, F, UV)
    report = result.report
    assert report.untangled_vertices >= 1 and report.flipped_triangles == 0
    assert report.complete and len(result.Q) == 25
    assert_valid_quad_mesh(result.V, result.Q)


def test_a_fold_that_cannot_be_untangled_is_reported_and_the_rest_stays_valid():
    V, F, UV = square(5, 9, 0.3)
    UV = UV.copy()
    corner = int(np.argmin(V[:, 0] + V[:, 1]))   # the boundary corner (0, 0): not free to move
    UV[F == corner] = [1.7, 1.3]
    flipped = int((signed_areas(UV) < 0).sum())
    assert flipped >= 1
    result = extract_quads(V, F, UV)
    report = result.report
    assert report.flipped_triangles == flipped and report.untangled_vertices == 0 and not report.complete
    assert report.holes == 0  # the square's corner is cut off: the boundary loop changes, no hole opens
    assert report.squares_inconsistent + report.squares_cut_by_boundary >= 1 and 0 < len(result.Q) < 25
    assert_valid_quad_mesh(result.V, result.Q)


def test_zero_area_triangles_are_crossed():
    V, F, UV = square(5, 9, 0.3)
    UV = UV.copy()
    w, target = centre_edge(V, F)                # an interior vertex collapsed onto its neighbour
    UV[F == w] = UV[F == target][0]
    assert (signed_areas(UV) == 0).sum() == 2 and (signed_areas(UV) < 0).sum() == 0
    result = extract_quads(V, F, UV)
    assert result.report.degenerate_triangles == 2
    assert result.report.complete and len(result.Q) == 25
    assert_valid_quad_mesh(result.V, result.Q)


def test_non_integer_singularities_are_reported():
    V, F, UV = cube(3, 4)
    result = extract_quads(V, F, UV + 0.5)  # the seams still match; the corners are off the grid
    report = result.report
    assert report.non_integer_singularities == 8 and not report.complete
    if len(result.Q):
        assert_valid_quad_mesh(result.V, result.Q)


def test_boundary_off_the_grid_leaves_cut_squares_out():
    V, F, UV = square(4, 8, 0.2)
    result = extract_quads(V, F, UV + 0.3)
    report = result.report
    # of the 5×5 squares meeting [0.3, 4.3]^2, the 3×3 inside ones are complete
    assert report.squares_cut_by_boundary == 25 - 9 and len(result.Q) == 9
    assert not report.complete
    assert_valid_quad_mesh(result.V, result.Q)


def test_non_seamless_edges_are_counted_and_snapped():
    V, F, UV = torus(6, 3)
    clean = extract_quads(V, F, UV)
    UV = UV.copy()
    UV[0] += 0.25  # one face's corners moved by a non-integer translation
    result = extract_quads(V, F, UV)
    assert result.report.non_seamless_edges == 3  # its three edges
    # each vertex's corners are rebuilt from one of them through the rounded transitions
    assert len(result.Q) == len(clean.Q) and result.report.euler_output == 0
    assert_valid_quad_mesh(result.V, result.Q)


def test_progress_is_reported_and_can_cancel():
    V, F, UV = torus(6, 3)
    stages = []
    extract_quads(V, F, UV, progress=lambda fraction, stage: stages.append((fraction, stage)))
    assert stages[-1][0] == 1.0 and all(s.startswith("extract quads") for _, s in stages)
    with pytest.raises(meshsmith.Cancelled):
        extract_quads(V, F, UV, progress=lambda fraction, stage: False)


# --- bad input ------------------------------------------------------------------------------------

def test_bad_input_gets_input_errors():
    V, F, UV = square(3, 4)
    with pytest.raises(meshsmith.InputError, match=r"UV must have shape \(32, 3, 2\)"):
        extract_quads(V, F, UV[:, :, 0])
    bad = UV.copy()
    bad[3, 1, 0] = np.nan
    with pytest.raises(meshsmith.InputError, match="UV of face 3, corner 1"):
        extract_quads(V, F, bad)
    with pytest.raises(meshsmith.InputError, match="2\\^40"):
        extract_quads(V, F, UV * 1e13)
    with pytest.raises(meshsmith.InputError, match="more than 2\\^26"):
        extract_quads(V, F, UV * 1e5)
    # a fin: a third face on an edge
    V2 = np.vstack([V, [[0.1, 0.0, 1.0]]])
    f = len(F) // 2  # an interior face: its edges have two faces already
    F2 = np.vstack([F, [[F[f, 0], F[f, 1], len(V)]]])
    with pytest.raises(meshsmith.InputError, match="manifold"):
        extract_quads(V2, F2, np.concatenate([UV, UV[:1]]))
    F3 = F.copy()
    F3[2] = [F[2, 0], F[2, 0], F[2, 1]]
    with pytest.raises(meshsmith.InputError, match="face 2 repeats a vertex"):
        extract_quads(V, F3, UV)
    before = UV.copy()
    extract_quads(V, F, UV)
    assert np.array_equal(UV, before)


# --- quad quality, analytically -------------------------------------------------------------------

def test_quad_quality_of_known_quads():
    s3 = np.sqrt(3.0)
    V = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0],          # 2×1 rectangle
                  [0, 0, 0], [1, 0, 0], [1.5, s3 / 2, 0], [0.5, s3 / 2, 0],  # rhombus 60°/120°
                  [0, 0, 0], [2, 0, 0], [0.5, 0.5, 0], [0, 2, 0]], float)    # dart: reflex at corner 2
    Q = np.arange(12).reshape(3, 4)
    quality = quad_quality(V, Q)
    np.testing.assert_allclose(quality.angles[0], 90.0)
    np.testing.assert_allclose(quality.angles[1], [60, 120, 60, 120], atol=1e-12)
    assert quality.angle_deviation[0] == pytest.approx(0.0) and quality.angle_deviation[1] == pytest.approx(30.0)
    assert quality.scaled_jacobian[0] == pytest.approx(1.0)
    assert quality.scaled_jacobian[1] == pytest.approx(np.sin(np.radians(60)))
    assert quality.scaled_jacobian[2] < 0  # the reflex corner
    assert quality.aspect_ratio[0] == pytest.approx(2.0) and quality.aspect_ratio[1] == pytest.approx(1.0)
    assert quality.valence[:4].tolist() == [1, 1, 1, 1]
    # a regular grid: interior valence 4
    V, F, UV = square(4, 5)
    Vq, Q = extract_quads(V, F, UV)
    hist = quad_quality(Vq, Q).valence_histogram
    assert hist.tolist() == [0, 4, 12, 0, 9]


def test_quad_quality_rejects_bad_quads():
    V = np.eye(3)
    with pytest.raises(meshsmith.InputError, match="indexes outside V"):
        quad_quality(V, [[0, 1, 2, 5]])
    with pytest.raises(meshsmith.InputError, match="zero-length edge"):
        quad_quality(V, [[0, 1, 1, 2]])
    with pytest.raises(meshsmith.InputError):
        quad_quality(V, [[0, 1, 2]])


def test_a_fold_that_opens_a_hole_is_counted():
    V, F, UV = torus(6, 3)
    UV = UV.copy()
    w = 5 * 9 + 4                                # two neighbours pushed past each other
    face = F[np.flatnonzero((F == w).any(1))[0]]
    t = face[(list(face).index(w) + 1) % 3]
    a, b = UV[F == w][0].copy(), UV[F == t][0].copy()
    UV[F == w], UV[F == t] = a + 2 * (b - a), b + 2 * (a - b)
    result = extract_quads(V, F, UV)
    report = result.report
    assert report.flipped_triangles == 2 and not report.complete
    assert report.holes == 1 and report.euler_output == -1 and len(result.Q) == 17
    assert_valid_quad_mesh(result.V, result.Q)
