"""Parametrization maps (§5.1.1–2): boundary maps, harmonic/Tutte/mean-value maps, stretch
minimization, LSCM, cutting to a disk and the bijectivity check — against libigl, invariants and
bad input."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, geometry, io, topology
from meshsmith import parametrization as P

igl = pytest.importorskip("igl")


def _disk_topology(V, F):
    info = topology.info(V, F)
    return info.n_boundary_loops == 1 and info.euler_characteristic == 1


def _compact(V, F):
    """(V, F) without the vertices F does not use."""
    used = np.unique(F)
    remap = np.full(len(V), -1)
    remap[used] = np.arange(len(used))
    return V[used], remap[F]


def _annulus(n_rings=8, n_segments=48):
    """A flat disk with its innermost rings removed: two boundary loops."""
    V, F = datasets.disk(n_rings=n_rings, n_segments=n_segments)
    keep = np.linalg.norm(V[F].mean(axis=1)[:, :2], axis=1) > 0.35
    F = F[keep]
    return _compact(V, F)


def _sphere_cap(height):
    """The part of the unit icosphere with z < height (height > 0: more than a hemisphere)."""
    V, F = datasets.icosphere(4)
    F = F[(V[F][:, :, 2] < height).all(axis=1)]
    return _compact(V, F)


@pytest.fixture(scope="module")
def camelhead(data_dir):
    return io.read_mesh(data_dir / "camelhead.off")


@pytest.fixture(scope="module")
def hand(data_dir):
    return io.read_mesh(data_dir / "hand_lowres.obj")


# --- cut_to_disk ------------------------------------------------------------------------------

def _check_cut(V, F, cut):
    assert _disk_topology(cut.V, cut.F)
    n = len(V)
    np.testing.assert_array_equal(cut.vertex_origin[:n], np.arange(n))
    np.testing.assert_array_equal(cut.V, V[cut.vertex_origin])
    np.testing.assert_array_equal(cut.vertex_origin[cut.F], F)  # gluing the copies gives F back
    # every seam edge is an interior edge of the input, and is now boundary on both sides
    edges = {tuple(e) for e in topology.edges(F)}
    assert all(tuple(e) in edges for e in cut.seam_edges)
    info = topology.info(cut.V, cut.F)
    assert info.is_manifold and info.is_oriented
    assert info.n_boundary_edges == topology.info(V, F).n_boundary_edges + 2 * len(cut.seam_edges)


def _holed_torus():
    """A torus with two holes: genus 1 and two boundary loops."""
    V, F = datasets.torus(n_major=32, n_minor=16)
    F = F[~np.isin(F, [0, 200]).any(axis=1)]  # the fans of two vertices removed: two holes
    return _compact(V, F)


@pytest.mark.parametrize("shape", ["torus", "sphere", "annulus", "holed torus", "disk"])
def test_cut_to_disk_procedural(shape):
    V, F = {"torus": lambda: datasets.torus(n_major=32, n_minor=16), "sphere": lambda: datasets.icosphere(3),
            "annulus": _annulus, "holed torus": _holed_torus, "disk": datasets.disk}[shape]()
    cut = P.cut_to_disk(V, F)
    _check_cut(V, F, cut)
    if shape == "disk":
        assert len(cut.seam_edges) == 0 and len(cut.V) == len(V)
    else:
        assert len(cut.seam_edges) > 0
    V_cut, F_cut, origin, seam = cut  # unpacks as documented
    assert V_cut is cut.V and F_cut is cut.F and origin is cut.vertex_origin and seam is cut.seam_edges
    # the disk can be parametrized bijectively
    UV = P.harmonic(cut.V, cut.F, weights="mean_value")
    assert P.is_bijective(UV, cut.F)


@pytest.mark.parametrize("name", ["bunny.off", "spot.obj", "fertility.off", "torus.obj"])
def test_cut_to_disk_shared_meshes(data_dir, name):
    V, F = io.read_mesh(data_dir / name)
    genus = topology.info(V, F).genus
    cut = P.cut_to_disk(V, F)
    _check_cut(V, F, cut)
    # libigl's cut_to_disk needs the same number of independent cycles: 2g handle loops
    # (igl leaves a sphere uncut; we cut it along a path)
    assert genus == (0 if name in ("bunny.off", "spot.obj") else {"fertility.off": 4, "torus.obj": 1}[name])
    UV = P.harmonic(cut.V, cut.F, weights="uniform")
    assert P.is_bijective(UV, cut.F)


def test_cut_to_disk_bad_input():
    V, F = datasets.icosphere(2)
    two = np.vstack([V, V + 3.0]), np.vstack([F, F + len(V)])
    with pytest.raises(meshsmith.InputError, match="connected components"):
        P.cut_to_disk(*two)
    # an isolated vertex is no error: it stays in the cut mesh, used by no face
    cut = P.cut_to_disk(np.vstack([[[9.0, 9.0, 9.0]], V]), F + 1)
    reference = P.cut_to_disk(V, F)
    assert len(cut.V) == len(reference.V) + 1 and cut.vertex_origin[0] == 0 and 0 not in cut.F
    np.testing.assert_array_equal(cut.seam_edges, reference.seam_edges + 1)
    np.testing.assert_array_equal(cut.V[cut.F], reference.V[reference.F])
    with pytest.raises(meshsmith.InputError, match="non-manifold"):
        P.cut_to_disk(V, np.vstack([F, [[F[0, 0], F[0, 1], F[5, 2] if F[5, 2] not in F[0] else F[7, 2]]]]))
    flat = V.copy()
    flat[F[0]] = flat[F[0, 0]] + np.outer([0.0, 1.0, 2.0], [1.0, 0.0, 0.0])  # collinear corners
    with pytest.raises(meshsmith.InputError, match="zero area"):
        P.cut_to_disk(flat, F)


# --- is_bijective -----------------------------------------------------------------------------

def _strip(angle, nx=40, ny=4):
    """A grid strip bent into an annular sector of the given angle: the boundary of a sector
    beyond 2*pi runs over itself while every triangle stays counter-clockwise."""
    V, F = datasets.grid(nx, ny)
    theta = V[:, 0] / V[:, 0].max() * angle
    # a spiral rising by half the strip's width per turn: the second turn overlaps the first
    radius = 1.0 + 0.5 * V[:, 1] / V[:, 1].max() + 0.25 * theta / (2 * np.pi)
    UV = np.column_stack([radius * np.cos(theta), radius * np.sin(theta)])
    return UV, F


def test_is_bijective_concave_boundary():
    UV, F = _strip(1.5 * np.pi)  # a C shape: concave but simple boundary
    report = P.check_bijectivity(UV, F)
    assert report.orientation != 0 and len(report.flipped_faces) == 0
    assert report.bijective
    UV, F = _strip(2.6 * np.pi)  # the spiral overlaps its own start: locally fine, globally not
    report = P.check_bijectivity(UV, F)
    assert len(report.flipped_faces) == 0 and len(report.degenerate_faces) == 0
    assert not report.bijective and len(report.crossing_boundary_sides) > 0
    assert not P.is_bijective(UV, F)


def test_is_bijective_high_curvature_cap():
    # Projecting a spherical cap onto the xy-plane is one-to-one below the equator and folds over
    # once the cap goes past it.
    V, F = _sphere_cap(-0.3)
    assert P.is_bijective(V[:, :2], F)
    V, F = _sphere_cap(0.5)
    report = P.check_bijectivity(V[:, :2], F)
    assert not report.bijective and len(report.flipped_faces) > 0


def test_is_bijective_catches_a_double_cover():
    # z -> z^2 wraps the disk twice around its centre: every triangle stays counter-clockwise
    # (locally injective away from the centre), only the boundary, running round twice, tells.
    V, F = datasets.disk(n_rings=6, n_segments=37)
    z = (V[:, 0] + 1j * V[:, 1]) ** 2
    report = P.check_bijectivity(np.column_stack([z.real, z.imag]), F)
    assert report.orientation == 1 and len(report.flipped_faces) == 0
    assert not report.bijective and len(report.crossing_boundary_sides) > 0


def test_is_bijective_flip_touch_and_exactness():
    V, F = datasets.disk(n_rings=6, n_segments=24)
    UV = V[:, :2].copy()
    assert P.is_bijective(UV, F) and P.is_bijective(UV[:, ::-1], F)  # all clockwise is one-to-one too
    folded = UV.copy()
    folded[0] = [0.9, 0.0]  # the centre dragged across its ring
    report = P.check_bijectivity(folded, F)
    assert not report.bijective and len(report.flipped_faces) > 0
    # two boundary vertices moved onto one point: the boundary touches itself
    loop = topology.boundary_loops(F)[0]
    touching = UV.copy()
    touching[loop[0]] = touching[loop[len(loop) // 2]] * 0.999999
    assert not P.is_bijective(touching, F)
    # a triangle flattened to exactly collinear corners is degenerate, one off by 1 ulp is not
    tri = np.array([[0.0, 0.0], [1.0, 1.0], [3.0, 3.0]])
    assert P.check_bijectivity(tri, [[0, 1, 2]]).degenerate_faces.tolist() == [0]
    tri[2, 1] = np.nextafter(3.0, 4.0)
    assert P.is_bijective(tri, [[0, 1, 2]])


def test_is_bijective_bad_input():
    with pytest.raises(meshsmith.InputError, match="UV"):
        P.is_bijective(np.array([[0.0, 0.0], [1.0, np.nan], [0.0, 1.0]]), [[0, 1, 2]])
    with pytest.raises(meshsmith.InputError, match="outside"):
        P.is_bijective(np.zeros((3, 2)), [[0, 1, 3]])
    with pytest.raises(meshsmith.InputError):
        P.is_bijective(np.zeros((3, 3)), [[0, 1, 2]])


# --- boundary maps and harmonic maps ----------------------------------------------------------

def test_map_boundary_matches_libigl(camelhead):
    V, F = camelhead
    bnd = igl.boundary_loop(F.astype(np.int64))
    indices, uv = P.map_boundary(V, F)
    np.testing.assert_array_equal(indices, bnd)
    expected = igl.map_vertices_to_circle(np.asfortranarray(V), bnd.astype(np.int32))
    np.testing.assert_allclose(uv, expected, atol=1e-12)
    # square: corners of the unit square, every vertex on the perimeter, arc length monotone
    indices, uv = P.map_boundary(V, F, shape="square")
    on_side = np.isclose(uv, 0.0) | np.isclose(uv, 1.0)
    assert on_side.any(axis=1).all()
    assert sum(any(np.allclose(p, c) for p in uv) for c in ([0, 0], [1, 0], [1, 1], [0, 1])) == 4
    perimeter_position = np.where(np.isclose(uv[:, 1], 0) & (uv[:, 0] < 1), uv[:, 0],
                         np.where(np.isclose(uv[:, 0], 1) & (uv[:, 1] < 1), 1 + uv[:, 1],
                         np.where(np.isclose(uv[:, 1], 1) & (uv[:, 0] > 0), 3 - uv[:, 0], 4 - uv[:, 1])))
    assert (np.diff(perimeter_position) > 0).all()


def test_harmonic_cotan_matches_libigl(camelhead):
    V, F = camelhead
    bnd = igl.boundary_loop(F.astype(np.int64))
    bc = igl.map_vertices_to_circle(np.asfortranarray(V), bnd.astype(np.int32))
    expected = igl.harmonic(V, F.astype(np.int64), bnd.astype(np.int64), np.ascontiguousarray(bc), 1)
    np.testing.assert_allclose(P.harmonic(V, F, weights="cotan"), expected, atol=1e-8)
    np.testing.assert_allclose(P.harmonic(V, F, boundary=bnd, boundary_uv=bc, weights="cotan"), expected, atol=1e-8)


@pytest.mark.parametrize("weights", ["uniform", "mean_value"])
@pytest.mark.parametrize("shape", ["circle", "square"])
def test_tutte_and_mean_value_are_bijective(camelhead, hand, weights, shape):
    meshes = [camelhead, hand, datasets.disk(n_rings=12, n_segments=40), datasets.noisy(*datasets.disk(), sigma=0.02)]
    for V, F in meshes:
        UV = P.harmonic(V, F, weights=weights, shape=shape)
        d = geometry.triangle_distortion(V, F, UV)
        assert len(d.flipped_faces) == 0 and len(d.degenerate_parameter_faces) == 0
        assert P.is_bijective(UV, F)


def test_harmonic_linear_precision_and_equilibrium():
    # A flat disk whose boundary is mapped by an affine map: cotan and mean-value weights have
    # linear precision, so the interior follows the same affine map exactly.
    V, F = datasets.noisy(*datasets.disk(n_rings=10, n_segments=36), sigma=0.0)
    A = np.array([[2.0, 0.5], [-0.3, 1.5]])
    bnd, _ = P.map_boundary(V, F)
    for weights in ("cotan", "mean_value"):
        UV = P.harmonic(V, F, boundary=bnd, boundary_uv=V[bnd, :2] @ A.T, weights=weights)
        np.testing.assert_allclose(UV, V[:, :2] @ A.T, atol=1e-10)
    # Tutte: every interior vertex is the average of its neighbours
    UV = P.harmonic(V, F)
    L = geometry.uniform_laplacian(F, len(V))
    interior = np.setdiff1d(np.arange(len(V)), bnd)
    np.testing.assert_allclose((L @ UV)[interior], 0.0, atol=1e-10)


def test_harmonic_bad_input():
    V, F = datasets.disk(n_rings=4, n_segments=16)
    with pytest.raises(meshsmith.InputError, match="closed"):
        P.harmonic(*datasets.icosphere(2))
    with pytest.raises(meshsmith.InputError, match="not a topological disk"):
        P.harmonic(*_annulus())
    with pytest.raises(meshsmith.InputError, match="weights"):
        P.harmonic(V, F, weights="cot")
    with pytest.raises(meshsmith.InputError, match="twice"):
        P.harmonic(V, F, boundary=[1, 2, 1], boundary_uv=np.zeros((3, 2)))
    with pytest.raises(meshsmith.InputError, match="positions"):
        P.harmonic(V, F, boundary=[1, 2, 3], boundary_uv=np.zeros((2, 2)))
    with pytest.raises(meshsmith.InputError, match="boundary_uv"):
        P.harmonic(V, F, boundary_uv=np.zeros((2, 2)))
    with pytest.raises(meshsmith.InputError, match=r"boundary has shape \(1, 3\): expected \(n,\)"):
        P.harmonic(V, F, boundary=[[1, 2, 3]])
    with pytest.raises(meshsmith.InputError, match="shape"):
        P.map_boundary(V, F, shape="triangle")


# --- stretch minimization ---------------------------------------------------------------------

@pytest.mark.parametrize("weights", ["mean_value", "uniform"])
def test_stretch_minimizing_lowers_stretch(camelhead, hand, weights):
    for V, F in (camelhead, hand):
        start = P.harmonic(V, F, weights=weights)
        result = P.stretch_minimizing(V, F, iterations=6, weights=weights)
        start_stretch = geometry.triangle_distortion(V, F, start).normalized_global_stretch_l2
        final = geometry.triangle_distortion(V, F, result.uv)
        assert result.stretch[0] == pytest.approx(start_stretch, rel=1e-10)
        assert final.normalized_global_stretch_l2 == pytest.approx(result.stretch[result.best_iteration], rel=1e-10)
        assert final.normalized_global_stretch_l2 < 0.8 * start_stretch
        assert result.best_iteration >= 1 and len(result.stretch) <= 7
        assert P.is_bijective(result.uv, F)  # positive weights on a convex boundary stay bijective
        # the boundary stays where the harmonic map put it
        bnd, bnd_uv = P.map_boundary(V, F)
        np.testing.assert_allclose(result.uv[bnd], bnd_uv, atol=1e-12)


def test_stretch_minimizing_zero_iterations_and_bad_input():
    V, F = datasets.disk(n_rings=6, n_segments=24)
    result = P.stretch_minimizing(V, F, iterations=0)
    np.testing.assert_allclose(result.uv, P.harmonic(V, F, weights="mean_value"), atol=1e-12)
    assert len(result.stretch) == 1
    with pytest.raises(meshsmith.InputError, match="iterations"):
        P.stretch_minimizing(V, F, iterations=-1)
    with pytest.raises(meshsmith.InputError, match="closed"):
        P.stretch_minimizing(*datasets.icosphere(2))
    calls = []
    with pytest.raises(meshsmith.Cancelled):
        P.stretch_minimizing(V, F, progress=lambda fraction, stage: calls.append(fraction) or False)
    assert calls


# --- LSCM -------------------------------------------------------------------------------------

def test_lscm_matches_libigl(camelhead, hand):
    for V, F in (camelhead, hand, datasets.noisy(*datasets.disk(), sigma=0.02)):
        b, bc = P.default_lscm_pins(V, F)
        expected, _ = igl.lscm(V, F.astype(np.int64), b, np.ascontiguousarray(bc))
        np.testing.assert_allclose(P.lscm(V, F), expected, atol=1e-8)
        bnd = igl.boundary_loop(F.astype(np.int64))
        pins = np.array([bnd[0], bnd[len(bnd) // 2]])
        pins_uv = np.array([[0.0, 0.0], [1.0, 0.0]])
        expected, _ = igl.lscm(V, F.astype(np.int64), pins, pins_uv)
        UV = P.lscm(V, F, pins, pins_uv)
        np.testing.assert_allclose(UV, expected, atol=1e-8)
        assert P.is_bijective(UV, F)
    # default pins: boundary vertices far apart, at (0, 0) and (distance, 0)
    V, F = camelhead
    b, bc = P.default_lscm_pins(V, F)
    bnd = igl.boundary_loop(F.astype(np.int64))
    assert set(b) <= set(bnd)
    assert bc[1, 0] == pytest.approx(np.linalg.norm(V[b[0]] - V[b[1]]))
    diameter = max(np.linalg.norm(V[bnd] - V[v], axis=1).max() for v in bnd)
    assert bc[1, 0] > 0.9 * diameter


def test_lscm_reproduces_a_flat_conformal_map():
    # A flat disk has a zero-energy map: itself. With two pins on it, LSCM returns it exactly.
    V, F = datasets.noisy(*datasets.disk(n_rings=8, n_segments=30), sigma=0.0)
    pins = np.array([1, 5])
    UV = P.lscm(V, F, pins, V[pins, :2])
    np.testing.assert_allclose(UV, V[:, :2], atol=1e-10)


def _similarity_residual(A, B):
    """Relative residual of the best complex-linear fit B ~ a A + b (a similarity, no reflection)."""
    za, zb = A[:, 0] + 1j * A[:, 1], B[:, 0] + 1j * B[:, 1]
    M = np.column_stack([za, np.ones_like(za)])
    coef, *_ = np.linalg.lstsq(M, zb, rcond=None)
    return np.linalg.norm(M @ coef - zb) / np.linalg.norm(zb - zb.mean())


def test_lscm_spectral_matches_scipy_eigsh(camelhead, hand):
    scipy_linalg = pytest.importorskip("scipy.sparse.linalg")
    import scipy.sparse as sparse
    for V, F in (camelhead, hand):
        n = len(V)
        # the same problem built from libigl's LSCM energy and boundary, solved by ARPACK
        bnd = igl.boundary_loop(F.astype(np.int64))
        _, Q = igl.lscm(V, F.astype(np.int64), bnd[:2], np.array([[0.0, 0.0], [1.0, 0.0]]))
        mass = np.zeros(n)
        lengths = np.linalg.norm(V[bnd] - V[np.roll(bnd, -1)], axis=1)
        np.add.at(mass, bnd, 0.5 * lengths)
        np.add.at(mass, np.roll(bnd, -1), 0.5 * lengths)
        B = sparse.diags(np.concatenate([mass, mass])).tocsc()
        values, vectors = scipy_linalg.eigsh(Q.tocsc(), k=4, M=B, sigma=-1e-6)
        fiedler = vectors[:, np.argsort(values)[2]]
        expected = np.column_stack([fiedler[:n], fiedler[n:]])
        UV = P.lscm_spectral(V, F)
        assert _similarity_residual(UV, expected) < 1e-6
        assert P.is_bijective(UV, F)
        d = geometry.triangle_distortion(V, F, UV)
        assert d.parameter_areas.sum() == pytest.approx(d.surface_areas.sum(), rel=1e-9)


def test_angle_distortion_lscm_below_tutte(camelhead, hand):
    for V, F in (camelhead, hand):
        conformal = {name: np.average(geometry.triangle_distortion(V, F, UV).conformal,
                                      weights=geometry.face_areas(V, F))
                     for name, UV in (("tutte", P.harmonic(V, F)), ("lscm", P.lscm(V, F)),
                                      ("spectral", P.lscm_spectral(V, F)))}
        assert conformal["lscm"] < conformal["tutte"] and conformal["spectral"] < conformal["tutte"]


def test_lscm_bad_input():
    V, F = datasets.disk(n_rings=4, n_segments=16)
    bad_inputs = {
        "closed": datasets.icosphere(2),
        "connected components": (np.vstack([V, V + 3.0]), np.vstack([F, F + len(V)])),
        "zero area": (V, np.vstack([F, [[0, 1, 1]]])),
        "non-manifold": (np.vstack([V, [[0.0, 0.0, 1.0]]]),
                         np.vstack([F, [[F[0, 0], F[0, 1], len(V)]]])),
        "not a topological disk": _annulus(),
    }
    for message, (Vb, Fb) in bad_inputs.items():
        for function in (P.lscm, P.harmonic, P.stretch_minimizing):
            with pytest.raises(meshsmith.InputError, match=message if message != "zero area" else "repeats|zero area"):
                function(Vb, Fb)
    with pytest.raises(meshsmith.InputError, match="closed"):
        P.lscm_spectral(*datasets.icosphere(2))
    with pytest.raises(meshsmith.InputError, match="at least two"):
        P.lscm(V, F, [3], [[0.0, 0.0]])
    with pytest.raises(meshsmith.InputError, match="same position"):
        P.lscm(V, F, [3, 4], np.zeros((2, 2)))
    with pytest.raises(meshsmith.InputError, match="both"):
        P.lscm(V, F, [3, 4])
    with pytest.raises(meshsmith.InputError, match="outside"):
        P.lscm(V, F, [3, 4000], np.eye(2))
    # an isolated vertex is no error: its row is NaN, the others are the map without it
    isolated = np.vstack([V, [[5.0, 5.0, 5.0]]])
    for function in (P.lscm, P.harmonic, P.lscm_spectral, lambda V, F: P.stretch_minimizing(V, F).uv):
        UV = function(isolated, F)
        assert np.isnan(UV[-1]).all()
        np.testing.assert_array_equal(UV[:-1], function(V, F))
    with pytest.raises(meshsmith.InputError, match=f"pinned: vertex {len(V)} is used by no face"):
        P.lscm(isolated, F, [3, len(V)], np.eye(2))
    # an annulus is fine for LSCM with explicit pins (any surface with a boundary)
    Va, Fa = _annulus()
    bnd = topology.boundary_loops(Fa)[0]
    UV = P.lscm(Va, Fa, [bnd[0], bnd[len(bnd) // 2]], np.eye(2))
    assert P.is_bijective(UV, Fa)


@pytest.mark.parametrize("method", ["lscm", "harmonic", "tutte"])
def test_parametrize_reports_progress_for_the_maps_and_honours_cancel(method):
    """The maps solve one factorization each and report nothing themselves: parametrize reports
    its stages (chart by chart, then distortion), increasing to 1; False cancels, garbage is named."""
    V, F = datasets.icosphere(2)
    calls = []
    P.parametrize(V, F, method=method, progress=lambda f, s: calls.append((f, s)))
    fractions = [f for f, _ in calls]
    assert fractions == sorted(fractions) and fractions[0] == 0.0 and fractions[-1] == 1.0 and len(calls) >= 3
    assert calls[0][1] == f"{method}: chart 1 of 1"
    with pytest.raises(meshsmith.Cancelled, match="cancelled by the progress callback"):
        P.parametrize(V, F, method=method, progress=lambda f, s: False)
    with pytest.raises(meshsmith.InputError, match="progress callback returned 'x'"):
        P.parametrize(V, F, method=method, progress=lambda f, s: "x")
