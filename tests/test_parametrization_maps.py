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


def _annulus(n_rings=8, n_segments=48):
    """A flat disk with its innermost rings removed: two boundary loops."""
    V, F = datasets.disk(n_rings=n_rings, n_segments=n_segments)
    keep = np.linalg.norm(V[F].mean(axis=1)[:, :2], axis=1) > 0.35
    F = F[keep]
    used = np.unique(F)
    remap = np.full(len(V), -1)
    remap[used] = np.arange(len(used))
    return V[used], remap[F]


def _sphere_cap(height):
    """The part of the unit icosphere with z < height (height > 0: more than a hemisphere)."""
    V, F = datasets.icosphere(4)
    F = F[(V[F][:, :, 2] < height).all(axis=1)]
    used = np.unique(F)
    remap = np.full(len(V), -1)
    remap[used] = np.arange(len(used))
    return V[used], remap[F]


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


@pytest.mark.parametrize("shape", ["torus", "sphere", "annulus", "disk"])
def test_cut_to_disk_procedural(shape):
    V, F = {"torus": lambda: datasets.torus(n_major=32, n_minor=16), "sphere": lambda: datasets.icosphere(3),
            "annulus": _annulus, "disk": datasets.disk}[shape]()
    cut = P.cut_to_disk(V, F)
    _check_cut(V, F, cut)
    if shape == "disk":
        assert len(cut.seam_edges) == 0 and len(cut.V) == len(V)
    else:
        assert len(cut.seam_edges) > 0
    V_cut, F_cut, seam = cut  # unpacks as documented
    assert V_cut is cut.V and seam is cut
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
    with pytest.raises(meshsmith.InputError, match="isolated vertex"):
        P.cut_to_disk(np.vstack([V, [[9.0, 9.0, 9.0]]]), F)
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
    with pytest.raises(meshsmith.InputError, match="1-D"):
        P.harmonic(V, F, boundary=[[1, 2, 3]])
    with pytest.raises(meshsmith.InputError, match="shape"):
        P.map_boundary(V, F, shape="triangle")
